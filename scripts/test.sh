#!/usr/bin/env bash
# Set up (install what is missing, build) and run every test of every package.
# The last line is the summary: "N passed, N failed, N skipped".
set -uo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh || { echo "0 passed, 1 failed (set-up or build failed)"; exit 1; }

# The DDS-free libraries (src/) run as many tests at a time as there are cores: each test is a
# process of its own with its own temporary files, and most of the suite's time is their
# CPU-bound offline runs (the feature-level ones single-threaded). The DDS packages run one test
# at a time, package after package: discovery and the components' queues would otherwise compete
# for 2 cores.
# colcon test exits non-zero only when a package's test step itself broke (its tests then have
# no results and would be missing from the counts below, not failed): that fails the run.
jobs=$(nproc)
libraries=$(colcon list --names-only --base-paths src | tr '\n' ' ')
# shellcheck disable=SC2086  # one package name per word
colcon test --metas colcon.meta --executor sequential --packages-select $libraries \
  --ctest-args --output-on-failure -j"${jobs}" --event-handlers console_cohesion+ summary+
libraries_status=$?
# shellcheck disable=SC2086
colcon test --metas colcon.meta --executor sequential --packages-skip $libraries \
  --ctest-args --output-on-failure --event-handlers console_cohesion+ summary+
test_status=$?
[ "$libraries_status" -ne 0 ] && test_status=$libraries_status
result=$(colcon test-result --test-result-base build --all 2>&1)
status=$?
echo "$result" | grep -vE '^build/.*: [0-9]+ tests, 0 errors, 0 failures' | tail -n 40
summary=$(echo "$result" | grep -E '^Summary:' | tail -n 1)
# "Summary: 233 tests, 0 errors, 1 failure, 0 skipped" (singular forms too)
field() { sed -nE "s/.* ([0-9]+) $1.*/\\1/p" <<<"$summary"; }
total=$(field 'tests?')
errors=$(field 'errors?')
failures=$(field 'failures?')
skipped=$(field 'skipped')
if [ -z "$summary" ] || [ -z "$total" ] || [ -z "$errors" ] || [ -z "$failures" ] || [ -z "$skipped" ]; then
  echo "0 passed, 1 failed (no test results found)"
  exit 1
fi
failed=$((errors + failures))
passed=$((total - failed - skipped))
if [ "$test_status" -ne 0 ]; then
  echo "colcon test failed (exit $test_status): a package's tests did not run, see 'Failed <<<' above"
  failed=$((failed + 1))
fi
echo "${passed} passed, ${failed} failed, ${skipped} skipped"
[ "$failed" -eq 0 ] && [ "$status" -eq 0 ]
