#!/usr/bin/env bash
# Runs a talker on a random DDS domain and the independent ROS 2 peer (peer.js) against it.
#
#   run_interop.sh [--expect-fail] <talker command...>
#
# The talker is started as `<talker command> --domain <id> --out <json>` and must write the exact
# messages it publishes to <json>, then publish until killed. Exit status: the peer's (0 = every
# topic, field and the ROS 2 node matched); 77 (ctest SKIP) when Node.js or the npm packages are
# missing. --expect-fail inverts the peer's verdict (to show the peer catches a wrong message).
set -u

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
expect_fail=0
if [[ "${1:-}" == "--expect-fail" ]]; then
  expect_fail=1
  shift
fi
if [[ $# -lt 1 ]]; then
  echo "usage: run_interop.sh [--expect-fail] <talker command...>" >&2
  exit 2
fi

if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node (Node.js >= 18) is not installed; the interop peer needs it." >&2
  exit 77
fi
if [[ ! -d "$here/node_modules/@foxglove/rtps" || ! -d "$here/node_modules/@foxglove/rosmsg2-serialization" ]]; then
  echo "SKIP: npm packages of the interop peer are missing; run: (cd $here && npm ci)" >&2
  exit 77
fi

# A domain per run keeps parallel tests and other DDS users off our topics. Fast DDS accepts
# domains up to 232 with its default port mapping.
domain=$(( 150 + (RANDOM + $$) % 80 ))
workdir="$(mktemp -d "${TMPDIR:-/tmp}/mcvio_interop.XXXXXX")"
expected="$workdir/expected.json"
talker_pid=""

cleanup() {
  if [[ -n "$talker_pid" ]] && kill -0 "$talker_pid" 2>/dev/null; then
    kill "$talker_pid" 2>/dev/null
    wait "$talker_pid" 2>/dev/null
  fi
  rm -rf "$workdir"
}
trap cleanup EXIT

echo "interop: domain $domain, talker: $*"
"$@" --domain "$domain" --out "$expected" >"$workdir/talker.log" 2>&1 &
talker_pid=$!

# The talker writes its JSON before it starts publishing.
for _ in $(seq 1 200); do
  [[ -s "$expected" ]] && break
  if ! kill -0 "$talker_pid" 2>/dev/null; then
    echo "interop: talker exited before writing $expected:" >&2
    cat "$workdir/talker.log" >&2
    exit 1
  fi
  sleep 0.1
done
if [[ ! -s "$expected" ]]; then
  echo "interop: talker wrote no $expected within 20 s" >&2
  cat "$workdir/talker.log" >&2
  exit 1
fi

timeout -k 5 90 node "$here/peer.js" --domain "$domain" --expected "$expected" --timeout 60
status=$?

if ! kill -0 "$talker_pid" 2>/dev/null; then
  echo "interop: talker died during the test:" >&2
  cat "$workdir/talker.log" >&2
  status=1
elif [[ $status -ne 0 && -s "$workdir/talker.log" ]]; then
  echo "interop: talker log:" >&2
  tail -n 50 "$workdir/talker.log" >&2
fi

if [[ $expect_fail -eq 1 ]]; then
  if [[ $status -eq 1 ]]; then
    echo "interop: the peer rejected the altered message, as it should"
    exit 0
  fi
  echo "interop: expected the peer to fail (status 1), got $status" >&2
  exit 1
fi
exit $status
