#!/bin/sh
# Builds the libFuzzer targets (mcvio_bag: MCAP reader, sqlite3 reader, metadata.yaml parser;
# mcvio_rosmsg: the CDR decoder) with clang (ASan + UBSan) and runs each for a bounded
# time on a seed corpus of valid bags written by mcvio_bag itself.
#   test/fuzz/run_fuzz.sh [SECONDS_PER_TARGET=60] [WORK_DIR=/tmp/mcvio_fuzz]
# Needs clang-14 and libclang-rt-14-dev (Debian), and mcvio_cmake + mcvio_core installed by
# colcon (INSTALL_BASE, default <repo>/install). Exits non-zero when a target finds a crash;
# the reproducer is left in WORK_DIR/<target>/artifacts.
set -eu
seconds=${1:-60}
work=${2:-/tmp/mcvio_fuzz}
repo=$(cd "$(dirname "$0")/../.." && pwd)
install=${INSTALL_BASE:-$repo/install}
cxx=${CXX_FUZZ:-clang++-14}
command -v "$cxx" >/dev/null || { echo "$cxx not found (apt-get install clang-14 libclang-rt-14-dev)"; exit 2; }
mkdir -p "$work"
cmake -S "$repo/src/mcvio_bag" -B "$work/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$cxx" -DMCVIO_BAG_FUZZ=ON -DMCVIO_BUILD_TESTS=OFF \
  -DMCVIO_BUILD_BENCHMARKS=OFF \
  -DCMAKE_PREFIX_PATH="$install/mcvio_cmake;$install/mcvio_core;$install" >"$work/cmake.log"
cmake --build "$work/build" -j2 >"$work/build.log"
mkdir -p "$work/fuzz_mcap_reader/corpus" "$work/fuzz_sqlite_reader/corpus" "$work/fuzz_bag_metadata/corpus"
"$work/build/make_fuzz_seeds" "$work/fuzz_mcap_reader/corpus" "$work/fuzz_sqlite_reader/corpus" \
  "$work/fuzz_bag_metadata/corpus"
status=0
for target in fuzz_mcap_reader fuzz_sqlite_reader fuzz_bag_metadata; do
  dir="$work/$target"
  mkdir -p "$dir/artifacts"
  echo "== $target for ${seconds}s"
  if ! "$work/build/$target" "$dir/corpus" -max_total_time="$seconds" -max_len=65536 \
      -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$dir/artifacts/" -print_final_stats=1 \
      >"$dir/log.txt" 2>&1; then
    echo "$target FAILED: see $dir/log.txt and $dir/artifacts/"
    status=1
  fi
  grep -E "stat::number_of_executed_units|cov:" "$dir/log.txt" | tail -2
done

# The dynamic CDR decoder (mcvio_rosmsg), from an empty corpus: libFuzzer finds the structure.
cmake -S "$repo/src/mcvio_rosmsg" -B "$work/build_rosmsg" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$cxx" -DMCVIO_ROSMSG_FUZZ=ON -DMCVIO_BUILD_TESTS=OFF \
  -DCMAKE_PREFIX_PATH="$install/mcvio_cmake;$install/mcvio_core;$install" >"$work/cmake_rosmsg.log"
cmake --build "$work/build_rosmsg" -j2 >"$work/build_rosmsg.log"
dir="$work/fuzz_cdr_decoder"
mkdir -p "$dir/corpus" "$dir/artifacts"
echo "== fuzz_cdr_decoder for ${seconds}s"
if ! "$work/build_rosmsg/fuzz_cdr_decoder" "$dir/corpus" -max_total_time="$seconds" -max_len=65536 \
    -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$dir/artifacts/" -print_final_stats=1 \
    >"$dir/log.txt" 2>&1; then
  echo "fuzz_cdr_decoder FAILED: see $dir/log.txt and $dir/artifacts/"
  status=1
fi
grep -E "stat::number_of_executed_units|cov:" "$dir/log.txt" | tail -2
exit $status
