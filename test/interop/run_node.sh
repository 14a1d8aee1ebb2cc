#!/usr/bin/env bash
# Runs a Node.js script of the interop peer; exits 77 (ctest SKIP) when Node.js or the peer's
# npm packages are missing, so a machine without them skips instead of failing.
#   run_node.sh <script.js> [args...]
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node (Node.js >= 18) is not installed; the interop peer needs it." >&2
  exit 77
fi
if [[ ! -d "$here/node_modules/@foxglove/rtps" || ! -d "$here/node_modules/@foxglove/rosmsg2-serialization" ]]; then
  echo "SKIP: npm packages of the interop peer are missing; run: (cd $here && npm ci)" >&2
  exit 77
fi
exec node "$@"
