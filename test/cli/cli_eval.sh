#!/usr/bin/env bash
# `mcvio eval` end to end on a small synthetic sequence: reports and figures are written, the
# baseline comparison is printed, and bad input exits 2 naming the file.
set -u
mcvio=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
. "$(dirname "$0")/expect.sh"
fail() { echo "FAIL: $*"; failed=1; }

# (%.0f for nanosecond stamps: mawk's %d is 32-bit.)
# Ground truth: 10 s at 200 Hz on a 2 m circle with a slow height wave, body turning with the path.
mkdir -p "$tmp/seq/mav0/state_groundtruth_estimate0" "$tmp/ref" "$tmp/mc"
awk 'BEGIN {
  print "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,b_w_x,b_w_y,b_w_z,b_a_x,b_a_y,b_a_z";
  for (i = 0; i <= 2000; i++) { t = i / 200.0; a = 0.25 * t;
    printf "%.0f,%.9f,%.9f,%.9f,%.9f,0,0,%.9f,0,0,0,0,0,0,0,0,0\n", 1000000000 + i * 5000000,
      2 * cos(0.5 * t), 2 * sin(0.5 * t), 1 + 0.2 * sin(t), cos(a), sin(a) } }' \
  > "$tmp/seq/mav0/state_groundtruth_estimate0/data.csv"
# Labels at 20 Hz, conflict from 4 s to 6 s; runs at 20 Hz, off in height during the conflict.
awk 'BEGIN { print "#timestamp [ns],in_conflict,motion,covered_fraction";
  for (i = 0; i <= 200; i++) { c = (i >= 80 && i < 120); printf "%.0f,%d,%s,%s\n", 1000000000 + i * 50000000, c, c ? "elevator" : "none", c ? "0.8" : "0" } }' \
  > "$tmp/seq/mav0/conflict_labels.csv"
run() {  # run DIR HEIGHT_ERROR
  awk -v dz="$2" 'BEGIN { print "# t x y z qx qy qz qw";
    for (i = 0; i <= 200; i++) { t = i / 20.0; a = 0.25 * t; e = (i >= 80 && i < 120) ? dz : 0;
      printf "%d.%09d %.9f %.9f %.9f 0 0 %.9f %.9f\n", 1 + int(t), (i % 20) * 50000000,
        2 * cos(0.5 * t), 2 * sin(0.5 * t), 1 + 0.2 * sin(t) + e, sin(a), cos(a) } }' > "$1/trajectory.tum"
}
run "$tmp/ref" 0.2
run "$tmp/mc" 0.05
awk 'BEGIN { print "timestamp_ns,state,propagated_chi2,propagated_threshold,landmarks_tested,landmarks_inconsistent,inconsistent_fraction,coherence,interval_start_ns,resolution_mode";
  for (i = 0; i <= 200; i++) { c = (i >= 82 && i < 120);
    printf "%.0f,%s,%.1f,12.59,60,%d,%.3f,0.9,0,imu\n", 1000000000 + i * 50000000, c ? "conflict" : "none",
      c ? 20 + i % 7 : 2 + i % 9, c ? 30 : 3, c ? 0.5 : 0.05 } }' > "$tmp/mc/conflict.csv"

out=$("$mcvio" eval --gt "$tmp/seq" --est reference="$tmp/ref" --est mcvio="$tmp/mc" --out "$tmp/report" 2>"$tmp/err")
rc=$?
[ "$rc" -eq 0 ] || { fail "eval exited $rc"; cat "$tmp/err"; }
grep -qF "| Metric | reference | mcvio | mcvio reduction vs reference |" <<<"$out" || fail "no comparison table in: $out"
grep -qF "| ATE SE(3) RMSE in conflict [m] |" <<<"$out" || fail "no conflict ATE row"
grep -qE "^\| Detection TPR \(per frame\) \| n/a \| 0\.950 \|" <<<"$out" || fail "TPR of 38/40 frames missing: $(grep TPR <<<"$out")"
# Labelled 4.00-5.95 s, detected from frame 82 (0.10 s late) to the label's last frame.
grep -qF "| mcvio | 4.00 - 5.95 | 38/40 | 0.10 | 0.00 |" <<<"$out" || fail "interval timing missing: $(grep -A4 'per labelled interval' <<<"$out")"
for f in eval.json eval.md trajectory_top.png trajectory_side.png error_over_time.png roc.png ground_truth.tum mcvio_aligned_se3.tum; do
  [ -s "$tmp/report/$f" ] || fail "missing or empty $f"
done
# A quarter of the height error: 75% less ATE after position+yaw alignment (the x-y are exact, so
# the yaw is too and the error scales; the SE(3) rotation would bend with the height error).
reduction=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["relative_reduction_percent"]["mcvio"]["ate_posyaw_rmse_m"])' "$tmp/report/eval.json")
python3 -c 'import sys; sys.exit(0 if abs(float(sys.argv[1]) - 75.0) < 1e-6 else 1)' "$reduction" \
  || fail "ATE reduction in eval.json is '$reduction', want 75%"
[ "$failed" -eq 0 ] && echo "ok: report with comparison, detection and figures"

printf '1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n' > "$tmp/bad.tum"
expect 2 "$tmp/bad.tum:2: TUM pose has 7 fields" -- "$mcvio" eval --gt "$tmp/seq" --est "$tmp/bad.tum" --out "$tmp/r2"
expect 2 "$tmp/none: no such file" -- "$mcvio" eval --gt "$tmp/none" --est "$tmp/ref" --out "$tmp/r2"
expect 2 "no trajectory.tum" -- "$mcvio" eval --gt "$tmp/seq" --est "$tmp/seq" --out "$tmp/r2"
printf 'timestamp_ns,state\n1000000000,maybe\n' > "$tmp/ref/conflict.csv"
expect 2 "$tmp/ref/conflict.csv:2: column 'state'" -- "$mcvio" eval --gt "$tmp/seq" --est "$tmp/ref" --out "$tmp/r2"
rm "$tmp/ref/conflict.csv"
expect 2 "baseline 'okvis'" -- "$mcvio" eval --gt "$tmp/seq" --est "$tmp/ref" --baseline okvis --out "$tmp/r2"
exit $failed
