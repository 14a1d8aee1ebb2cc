#!/usr/bin/env bash
# `mcvio demo` as a new user runs it, shortened to one 12 s sequence: it renders, runs the DDS
# components with a recorder, runs the reference offline, evaluates, prints the table and leaves
# the report, plots, bag and trajectories; a rerun with --keep reuses the rendering; bad options
# and a domain where the demo's topics are already published are refused with a message naming
# them. About a minute here.
set -u
mcvio=$1
export ROS_DOMAIN_ID=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
check() {  # name, command...
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; failed=1; fi
}
out="$tmp/demo"

"$mcvio" demo --only elevator --duration 12 --keep --out "$out" > "$tmp/run1.txt" 2>&1
rc=$?
cat "$tmp/run1.txt"
check "demo exits 0" test "$rc" -eq 0
check "prints the table row" grep -qE '^\| elevator \| [0-9]+ \| [0-9.]+ \| [0-9.]+ \|' "$tmp/run1.txt"
check "prints when MC-VIO detected the conflict" grep -qE '^\| elevator( \| [^|]+){10} \| [0-9]+\.[0-9]{2} \|$' "$tmp/run1.txt"
check "prints the report path" grep -qF "$out/elevator/report/eval.md" "$tmp/run1.txt"
check "prints the ride and the cabin's own motion" grep -qE "^  the cabin's own motion \(secondary frame, secondary.tum\) [0-9]+\.[0-9]{2} m \([0-9]+\.[0-9] % off\)" "$tmp/run1.txt"
for f in report/eval.json report/eval.md report/trajectory_top.png report/error_over_time.png report/roc.png report/evidence_over_time.png report/ride_heights.png \
         bag/metadata.yaml mcvio/trajectory.tum mcvio/secondary.tum mcvio/conflict.csv reference/trajectory.tum reference/conflict.csv; do
  check "wrote $f" test -s "$out/elevator/$f"
done
check "conflict.csv has the columns of mcvio run" \
  test "$(head -1 "$out/elevator/mcvio/conflict.csv")" = "$(head -1 "$out/elevator/reference/conflict.csv")"
poses=$(grep -vc '^#' "$out/elevator/mcvio/trajectory.tum")
rows=$(($(wc -l < "$out/elevator/mcvio/conflict.csv") - 1))
check "one conflict row per DDS pose ($rows, $poses)" test "$rows" -eq "$poses" -a "$poses" -gt 100
check "the bag holds every pose" bash -c "'$mcvio' bag info '$out/elevator/bag' | grep -qE 'Topic: /mcvio/odometry \\| .*\\| Count: $poses( |\$)'"

# The bag holds what the DDS backend got (/mcvio/features, /imu0): `mcvio run` on it runs the
# estimator alone and must give exactly what the backend published, and in reference mode what
# the demo's offline reference run gave from the images.
same() {  # two TUM/CSV files with the same data lines (comments aside)
  test -s "$1" -a -s "$2" && diff <(grep -v '^#' "$1") <(grep -v '^#' "$2") > /dev/null
}
"$mcvio" run --dataset "$out/elevator/bag" --calib "$out/elevator/data" --out "$tmp/replay" --mode auto -q > "$tmp/replay.txt" 2>&1
check "mcvio run on the demo's bag of features exits 0" test $? -eq 0
for f in trajectory.tum trajectory_online.tum secondary.tum conflict.csv; do
  check "the replay's $f is the DDS backend's" same "$tmp/replay/$f" "$out/elevator/mcvio/$f"
done
check "stats.json says it ran on recorded features" grep -qF '"input": "recorded features (estimator only)"' "$tmp/replay/stats.json"
"$mcvio" run --dataset "$out/elevator/bag" --calib "$out/elevator/data" --out "$tmp/replay_ref" --mode reference -q > /dev/null 2>&1
check "the reference replay is the demo's reference run" same "$tmp/replay_ref/trajectory.tum" "$out/elevator/reference/trajectory.tum"

"$mcvio" demo --only elevator --duration 12 --keep --out "$out" > "$tmp/run2.txt" 2>&1
rc=$?
check "second run exits 0" test "$rc" -eq 0
check "second run reuses the rendering" grep -qF "reusing the rendering" "$tmp/run2.txt"

"$mcvio" demo --mode reference --out "$tmp/bad" > "$tmp/bad1.txt" 2>&1
check "--mode reference is refused" test $? -ne 0
check "the refusal names --mode" grep -qF -- "--mode" "$tmp/bad1.txt"
"$mcvio" demo --quick --duration 20 --out "$tmp/bad" > "$tmp/bad2.txt" 2>&1
check "--quick with --duration is refused (exit 2)" test $? -eq 2
"$mcvio" demo --duration 5 --out "$tmp/bad" > "$tmp/bad3.txt" 2>&1
check "--duration 5 is refused" test $? -ne 0
check "the refusal names --duration" grep -qF -- "--duration" "$tmp/bad3.txt"

# Another publisher of the demo's topics on the domain: refused, not mixed in.
"$mcvio" bus-demo --duration 30 > "$tmp/busdemo.txt" 2>&1 &
bus=$!
for _ in $(seq 1 10); do timeout -s KILL 30 "$mcvio" topics --wait 1 2>/dev/null | grep -qF "/imu0" && break; done
"$mcvio" demo --only elevator --duration 12 --out "$tmp/mixed" > "$tmp/mixed.txt" 2>&1
check "a busy domain is refused" test $? -ne 0
check "the refusal names the topic and --domain" grep -qE "already has a publisher of /.*--domain" "$tmp/mixed.txt"
kill -TERM $bus 2>/dev/null
wait $bus
check "the bus demo still runs as bus-demo" grep -qF "Delivered" "$tmp/busdemo.txt"
exit $failed
