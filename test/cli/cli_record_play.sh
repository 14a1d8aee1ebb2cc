#!/usr/bin/env bash
# Record while `mcvio play --lossless` plays the real EuRoC excerpt: every topic's count in the bag
# equals what the player published, and `bag info --verify` finds a byte flipped in it. Then a
# recorder killed with -9 leaves a bag that `mcvio bag reindex` makes readable again. Skips (77)
# without ../shared.
set -u
mcvio=$1
data=${MCVIO_SHARED_DIR:-}/data/euroc_V1_01_excerpt
[ -d "$data/mav0" ] || { echo "SKIP: $data not found"; exit 77; }
export ROS_DOMAIN_ID=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
trap 'pkill -KILL -f "mcvio record -o $tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
failed=0

"$mcvio" record -o "$tmp/bag" --all > "$tmp/record.txt" 2>&1 &
rec=$!
timeout -s KILL 300 "$mcvio" play "$data" --lossless --duration 20 -q --wait-for-readers 30 > "$tmp/play.txt" 2>&1 || { echo "FAIL: play"; cat "$tmp/play.txt"; exit 1; }
kill -INT $rec; wait $rec
cat "$tmp/play.txt" | tail -n 1
frames=$(sed -nE 's/.*: ([0-9]+) stereo frames, ([0-9]+) IMU samples, ([0-9]+) ground-truth.*/\1/p' "$tmp/play.txt")
imu=$(sed -nE 's/.*: ([0-9]+) stereo frames, ([0-9]+) IMU samples, ([0-9]+) ground-truth.*/\2/p' "$tmp/play.txt")
gt=$(sed -nE 's/.*: ([0-9]+) stereo frames, ([0-9]+) IMU samples, ([0-9]+) ground-truth.*/\3/p' "$tmp/play.txt")
"$mcvio" bag info "$tmp/bag" > "$tmp/info.txt" 2>&1 || { echo "FAIL: bag info"; cat "$tmp/info.txt"; failed=1; }
count() { sed -nE "s#.*Topic: $1 \\|.*Count: ([0-9]+).*#\\1#p" "$tmp/info.txt"; }
for t in /cam0/image_raw /cam1/image_raw /cam0/camera_info /cam1/camera_info; do
  [ "$(count $t)" = "$frames" ] && echo "ok: $t $frames" || { echo "FAIL: $t has $(count $t), played $frames"; failed=1; }
done
[ "$(count /imu0)" = "$imu" ] && echo "ok: /imu0 $imu" || { echo "FAIL: /imu0 has $(count /imu0), played $imu"; failed=1; }
[ "$(count /ground_truth/odometry)" = "$gt" ] && echo "ok: ground truth $gt" || { echo "FAIL: gt $(count /ground_truth/odometry) vs $gt"; failed=1; }

# bag info --verify reads every message: 0 unreadable here; one flipped byte in the middle of the
# file (inside a chunk, behind an intact summary) is reported with exit status 1.
"$mcvio" bag info --verify "$tmp/bag" > "$tmp/verify.txt" 2>&1 && grep -qE '^Verified: +[0-9]+ messages read intact, 0 unreadable$' "$tmp/verify.txt" &&
  echo "ok: $(grep '^Verified:' "$tmp/verify.txt")" || { echo "FAIL: bag info --verify"; cat "$tmp/verify.txt"; failed=1; }
file=$(ls "$tmp"/bag/*.mcap | head -n 1)
at=$(( $(stat -c %s "$file") / 2 ))
byte=$(od -An -tu1 -j "$at" -N1 "$file" | tr -d ' ')
printf "\\$(printf %o $(( byte ^ 0x5A )))" | dd of="$file" bs=1 seek="$at" conv=notrunc status=none
if "$mcvio" bag info --verify "$tmp/bag" > "$tmp/verify2.txt" 2>&1; then
  echo "FAIL: bag info --verify passed a damaged chunk"; cat "$tmp/verify2.txt"; failed=1
elif grep -q "messages unreadable; the first: .*byte offset" "$tmp/verify2.txt"; then
  echo "ok: $(grep '^Verified:' "$tmp/verify2.txt")"
else
  echo "FAIL: bag info --verify did not name the damaged chunk"; cat "$tmp/verify2.txt"; failed=1
fi
# `mcvio run` on the damaged bag stops at the damaged chunk, naming it and what repairs it.
"$mcvio" run --dataset "$tmp/bag" --calib "$data" --out "$tmp/run_damaged" -q > "$tmp/run_damaged.txt" 2>&1
rc=$?
if [ $rc -eq 2 ] && grep -q "$file: .*byte offset .*; \`mcvio bag reindex $tmp/bag\` rewrites the file" "$tmp/run_damaged.txt"; then
  echo "ok: mcvio run on the damaged bag names the chunk and \`mcvio bag reindex\`"
else
  echo "FAIL: mcvio run on the damaged bag (exit $rc)"; cat "$tmp/run_damaged.txt"; failed=1
fi

# kill -9 mid-recording, then reindex.
"$mcvio" record -o "$tmp/killed" --all > "$tmp/record2.txt" 2>&1 &
rec=$!
timeout -s KILL 300 "$mcvio" play "$data" --lossless --duration 20 -q --wait-for-readers 30 > "$tmp/play2.txt" 2>&1
kill -KILL $rec; wait $rec 2>/dev/null
if "$mcvio" bag info "$tmp/killed" > /dev/null 2>&1; then
  echo "note: bag info read the killed bag's metadata as written so far"
fi
"$mcvio" bag reindex "$tmp/killed" > "$tmp/reindex.txt" 2>&1 || { echo "FAIL: reindex"; cat "$tmp/reindex.txt"; failed=1; }
recovered=$(sed -nE 's/^Messages: +([0-9]+).*/\1/p' "$tmp/reindex.txt")
if [ -n "$recovered" ] && [ "$recovered" -gt 0 ]; then
  echo "ok: reindex recovered $recovered messages after kill -9"
else
  echo "FAIL: nothing recovered"; cat "$tmp/reindex.txt"; failed=1
fi
exit $failed
