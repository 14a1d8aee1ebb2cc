#!/bin/sh
# ctest driver: run_bag_check.sh GENERATOR OUT_DIR [NODE]
# Exits 77 (ctest skip) when node or the npm packages are missing (run `npm ci` here first).
set -e
here=$(cd "$(dirname "$0")" && pwd)
node=${3:-node}
if ! command -v "$node" >/dev/null 2>&1; then echo "node not found: skipping"; exit 77; fi
if [ ! -d "$here/node_modules/@mcap/core" ]; then
  echo "$here/node_modules missing (run: cd $here && npm ci): skipping"; exit 77
fi
"$1" "$2"
cd "$here"
exec "$node" check_mcap.js "$2"
