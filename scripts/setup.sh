#!/usr/bin/env bash
# mcvio set-up on Debian 12: installs what is missing (Debian and npm packages only), then builds
# the colcon workspace in Release. Idempotent: a second run installs nothing and rebuilds only
# what changed.
#   scripts/setup.sh            install + build
#   scripts/setup.sh --no-build install only
set -euo pipefail
cd "$(dirname "$0")/.."

DEBIAN_PACKAGES=(
  g++ make cmake git python3 pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libeigen3-dev libceres-dev libopencv-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libssl-dev
  libzstd-dev liblz4-dev libsqlite3-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  colcon python3-colcon-cmake python3-colcon-metadata python3-colcon-recursive-crawl
  python3-colcon-package-selection python3-colcon-parallel-executor python3-colcon-output
  python3-colcon-bash python3-colcon-defaults python3-colcon-package-information
  python3-colcon-library-path python3-colcon-test-result
  nodejs npm
)

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for p in "${DEBIAN_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js from another source (e.g. NodeSource) already brings npm; do not fight it.
if command -v node >/dev/null && command -v npm >/dev/null; then
  filtered=()
  for p in "${missing[@]}"; do [ "$p" = nodejs ] || [ "$p" = npm ] || filtered+=("$p"); done
  missing=("${filtered[@]+"${filtered[@]}"}")
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  as_root apt-get update -qq
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# npm packages of the tests' independent peers (versions pinned by package-lock.json).
for dir in test/interop test/bag_check; do
  [ -f "$dir/package-lock.json" ] || continue
  if [ ! -d "$dir/node_modules" ] || [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; then
    echo "setup: npm ci in $dir"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
  fi
done

[ "${1:-}" = "--no-build" ] && exit 0

# Build every package; Release and per-package CMake arguments come from colcon.meta.
jobs=$(nproc)
MAKEFLAGS="-j${jobs}" colcon build --metas colcon.meta --parallel-workers "${jobs}" \
  --event-handlers console_cohesion- console_stderr+ summary+
