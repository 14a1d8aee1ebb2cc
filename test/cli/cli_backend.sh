#!/usr/bin/env bash
# `mcvio backend` as a user runs it. Bad options end with a clear message and a non-zero exit.
# Then a lossless pipeline over the real excerpt in separate processes (backend, frontend,
# recorder, player): the backend uses every feature frame, and the recorded /mcvio/odometry holds
# every pose the backend reports. Skips that part (77) without ../shared.
set -u
mcvio=$1
export ROS_DOMAIN_ID=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done; rm -rf "$tmp"' EXIT
failed=0
expect_timeout=30
. "$(dirname "$0")/expect.sh"
expect 106 "--calib is required" -- "$mcvio" backend
expect 2 "/nonexistent: calibration folder or file does not exist" -- "$mcvio" backend --calib /nonexistent
expect 105 "bogus not in {reference,imu,selective,auto}" -- "$mcvio" backend --calib /nonexistent --mode bogus
expect 105 "--path-max: '-3' must be a finite number >= 0" -- "$mcvio" backend --calib /nonexistent --path-max -3
for o in --calib --config --mode --lossless --world-frame --body-frame --secondary-frame --landmarks-every --path-max --max-imu-wait; do
  expect 0 "  $o" -- "$mcvio" backend --help  # its line in the option table
done

data=${MCVIO_SHARED_DIR:-}/data/euroc_V1_01_excerpt
if [ ! -d "$data/mav0" ]; then
  echo "SKIP: $data not found"
  [ $failed -eq 0 ] && exit 77 || exit 1
fi
printf 'estimator:\n  max_iterations: -1\n' > "$tmp/bad.yaml"
expect 2 "max_iterations" -- "$mcvio" backend --calib "$data" --config "$tmp/bad.yaml"

"$mcvio" backend --calib "$data" --lossless > "$tmp/backend.txt" 2>&1 &
backend=$!; pids+=($backend)
"$mcvio" frontend --calib "$data" --lossless > "$tmp/frontend.txt" 2>&1 &
frontend=$!; pids+=($frontend)
"$mcvio" record -o "$tmp/bag" /mcvio/odometry /cam0/image_raw /cam1/image_raw /cam0/camera_info /cam1/camera_info /imu0 /ground_truth/odometry > "$tmp/record.txt" 2>&1 &
rec=$!; pids+=($rec)
timeout -s KILL 300 "$mcvio" play "$data" --lossless --duration 5 -q --wait-for-readers 30 > "$tmp/play.txt" 2>&1 || { echo "FAIL: play"; tail -n 5 "$tmp/play.txt"; exit 1; }
# The frontend finishes its queue when stopped; reliable delivery then needs a moment.
sleep 5
kill -INT $frontend; wait $frontend
sleep 3
kill -INT $backend; wait $backend
sleep 2
kill -INT $rec; wait $rec
tail -n 1 "$tmp/frontend.txt"
tail -n 1 "$tmp/backend.txt"
pairs=$(sed -nE 's/.*: ([0-9]+) stereo frames,.*/\1/p' "$tmp/play.txt")
frames=$(sed -nE 's/^mcvio backend: ([0-9]+) feature frames \(0 rejected, 0 dropped.*/\1/p' "$tmp/backend.txt")
poses=$(sed -nE 's/^mcvio backend: .*, ([0-9]+) poses,.*/\1/p' "$tmp/backend.txt")
[ -n "$frames" ] && [ "$frames" = "$pairs" ] && echo "ok: backend used $frames feature frames of $pairs pairs" ||
  { echo "FAIL: backend feature frames '$frames', played $pairs pairs"; failed=1; }
[ -n "$poses" ] && [ "$poses" -gt 0 ] && echo "ok: $poses poses" || { echo "FAIL: no poses"; failed=1; }
"$mcvio" bag info "$tmp/bag" > "$tmp/info.txt" 2>&1 || { echo "FAIL: bag info"; cat "$tmp/info.txt"; failed=1; }
recorded=$(sed -nE 's#.*Topic: /mcvio/odometry \|.*Count: ([0-9]+).*#\1#p' "$tmp/info.txt")
[ "$recorded" = "$poses" ] && echo "ok: /mcvio/odometry recorded $recorded" ||
  { echo "FAIL: /mcvio/odometry recorded '$recorded', backend published $poses"; failed=1; }

# --log-level debug: `mcvio run` logs one line per tracked estimator frame, with its solve and
# biases; at the default level none.
"$mcvio" --log-level debug run --dataset "$data" --out "$tmp/run" -q > /dev/null 2> "$tmp/run_debug.txt" ||
  { echo "FAIL: mcvio --log-level debug run"; tail -n 5 "$tmp/run_debug.txt"; failed=1; }
lines=$(grep -cE '^.*\[mcvio_estimator\] frame [0-9]+ t=[0-9]+: .* iterations, ba \(' "$tmp/run_debug.txt")
tracked=$(grep -vc '^#' "$tmp/run/trajectory.tum")
# Every pose but the first (the initialisation's) comes with its line.
[ "${tracked:-0}" -gt 1 ] && [ "$lines" -ge "$((tracked - 1))" ] && echo "ok: $lines debug lines for $tracked poses" ||
  { echo "FAIL: $lines debug lines for $tracked poses:"; tail -n 3 "$tmp/run_debug.txt"; failed=1; }
"$mcvio" run --dataset "$data" --out "$tmp/run_info" -q > /dev/null 2> "$tmp/run_info.txt"
grep -qF "iterations, ba (" "$tmp/run_info.txt" && { echo "FAIL: debug lines at the default level"; failed=1; }
exit $failed
