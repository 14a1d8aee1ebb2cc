#!/usr/bin/env bash
# Each bad input must end with a non-zero exit and a message naming what was wrong, never a crash.
set -u
mcvio=$1
domain=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
. "$(dirname "$0")/expect.sh"
printf '<dds><profiles><participant profile_name="x"><rtps>' > "$tmp/broken.xml"
expect 2 "$tmp/broken.xml" -- "$mcvio" --domain "$domain" --dds-profiles "$tmp/broken.xml" topics --wait 0.1
expect 2 "does not exist" -- "$mcvio" --domain "$domain" --dds-profiles "$tmp/missing.xml" topics --wait 0.1
expect 2 "invalid topic name '/bad topic'" -- "$mcvio" --domain "$domain" echo "/bad topic"
expect 2 "invalid topic name '/a//b'" -- "$mcvio" --domain "$domain" echo "/a//b"
expect 2 "domain id 233 is out of range" -- "$mcvio" --domain 233 topics
expect 2 "domain id -1 is out of range" -- "$mcvio" --domain -1 nodes
expect 2 "unknown type 'foo_msgs/msg/Bar'" -- "$mcvio" --domain "$domain" echo /imu0 --type foo_msgs/msg/Bar
expect 1 "no publisher of /nothing_here" -- "$mcvio" --domain "$domain" echo /nothing_here --timeout 1
expect 2 "unknown command 'no_such_command' (commands: topics" -- "$mcvio" no_such_command
expect 2 "unknown command 'no_such_command'" -- "$mcvio" --domain "$domain" no_such_command
expect 106 "A subcommand is required" -- "$mcvio" --domain "$domain"
expect 105 "--log-level: loud not in {trace,debug,info,warn,error,off}" -- "$mcvio" --log-level loud topics --wait 0.1
# Global options may follow the command too.
expect 105 "--log-level: loud not in {trace,debug,info,warn,error,off}" -- "$mcvio" topics --wait 0.1 --log-level loud
expect 2 "domain id 300 is out of range" -- "$mcvio" topics --wait 0.1 --domain 300
expect 2 "MCVIO_LOG_LEVEL: unknown level 'loud'" -- env MCVIO_LOG_LEVEL=loud "$mcvio" --domain "$domain" topics --wait 0.1
touch "$tmp/a_file"
expect 2 "output folder '$tmp/a_file/out': cannot create it" -- "$mcvio" run --dataset "$tmp/missing" --out "$tmp/a_file/out"
# Found by a bad-input audit (2026-11-29): each was accepted, hung or said something unrelated.
expect 2 "ROS_DOMAIN_ID='abc' is not a domain id" -- env ROS_DOMAIN_ID=abc "$mcvio" topics --wait 0.1
expect 0 "" -- env ROS_DOMAIN_ID=abc "$mcvio" --domain "$domain" topics --wait 0.1
# A one-second clean sequence (its conflict defaults, 20 s in, used to be checked against its length).
expect 0 "21 stereo frames (0 in conflict)" -- "$mcvio" sim --duration 1 --out "$tmp/tiny"
# Every frame is accounted for: 19 frames are too few to initialise, so no pose, and that is a
# failure (exit 1) rather than an empty trajectory; frames past the IMU's end are rejected, not "0 skipped".
cp -r "$tmp/tiny" "$tmp/tiny19"
for c in cam0 cam1; do head -n -2 "$tmp/tiny/mav0/$c/data.csv" > "$tmp/tiny19/mav0/$c/data.csv"; done
expect 1 "run: no pose was estimated (19 frames waited to initialise" -- "$mcvio" run --dataset "$tmp/tiny19" --out "$tmp/o19" -q
"$mcvio" sim --duration 4 --out "$tmp/four" > /dev/null 2>&1
head -n 602 "$tmp/four/mav0/imu0/data.csv" > "$tmp/imu_3s.csv" && mv "$tmp/imu_3s.csv" "$tmp/four/mav0/imu0/data.csv"
expect 0 "20 rejected by the estimator, 0 skipped by the frontend" -- "$mcvio" run --dataset "$tmp/four" --out "$tmp/o4" -q
expect 2 "$tmp: is a folder; the pipeline config file must be a YAML file" -- "$mcvio" run --dataset "$tmp/tiny" --out "$tmp/o" --config "$tmp"
printf 'estimator:\n  keyframe_window_size: 100000000\n' > "$tmp/window.yaml"
expect 2 "keyframe_window_size' must be in [1, 1000]" -- "$mcvio" run --dataset "$tmp/tiny" --out "$tmp/o" --config "$tmp/window.yaml"
printf 'frontend:\n  ransac_iterations: 2000000000\n' > "$tmp/ransac.yaml"
expect 2 "ransac_iterations' must be in [1, 100000]" -- "$mcvio" run --dataset "$tmp/tiny" --out "$tmp/o" --config "$tmp/ransac.yaml"
: > "$tmp/empty.yaml"
expect 2 "$tmp/empty.yaml: the pipeline config file is empty" -- "$mcvio" run --dataset "$tmp/tiny" --out "$tmp/o" --config "$tmp/empty.yaml"
expect 2 "$tmp/empty.yaml: is a file, not a EuRoC folder" -- "$mcvio" run --dataset "$tmp/empty.yaml" --out "$tmp/o"
cp -r "$tmp/tiny" "$tmp/calx" && echo "gyroscope_noise_densty: 1.0e-4" >> "$tmp/calx/mav0/imu0/sensor.yaml"
expect 0 "sensor.yaml:20: key 'gyroscope_noise_densty' is not one mcvio reads from an IMU's" -- "$mcvio" calib "$tmp/calx"
expect 2 "scenario.onset_s' must not be negative" -- "$mcvio" sim --scenario elevator --onset -5 --out "$tmp/sim"
expect 2 "scenario.coverage' must be in (0, 1]" -- "$mcvio" sim --scenario self_occlusion --coverage nan --out "$tmp/sim"
expect 2 "--texture-filter: unknown texture filter 'bicubic' (isotropic, anisotropic)" -- "$mcvio" sim --texture-filter bicubic --out "$tmp/sim"
expect 0 "21 stereo frames (0 in conflict)" -- "$mcvio" sim --duration 1 --texture-filter anisotropic --out "$tmp/tiny_aniso"
expect 2 "depth_m' must be in [0.1, 100]" -- "$mcvio" inject --depth -1 "$tmp/missing" "$tmp/injected"
# A config without center_m keeps its default (it used to be required); an onset after the input's end is refused.
printf 'depth_m: 2.0\nonset_s: 50\n' > "$tmp/inject.yaml"
expect 2 "option 'onset_s' (50.000000 s) is after the end of $tmp/tiny" -- "$mcvio" inject --config "$tmp/inject.yaml" "$tmp/tiny" "$tmp/injected"
expect 105 "--duration: 'nan' must be a finite number >= 0" -- "$mcvio" record -o "$tmp/bag" --duration nan
expect 2 "invalid topic name 'bad topic'" -- "$mcvio" --domain "$domain" record -o "$tmp/bag" "bad topic"
expect 2 "-o/--output is empty" -- "$mcvio" --domain "$domain" record -o "" /imu0
expect 2 "$tmp/no_bag: no such bag directory or file" -- "$mcvio" bag info "$tmp/no_bag"
expect 105 "--wait: Value 1e300 not in range" -- "$mcvio" --domain "$domain" nodes --wait 1e300
expect 105 "--timeout: 'nan' must be a finite number > 0" -- "$mcvio" --domain "$domain" echo /imu0 --timeout nan
# The offline commands end on the first SIGTERM; only the bus commands turn it into a clean stop.
"$mcvio" sim --duration 60 --out "$tmp/sig" > "$tmp/sig.txt" 2>&1 &
pid=$!
sleep 2
kill -TERM $pid
for _ in $(seq 1 50); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
if kill -0 $pid 2>/dev/null; then
  echo "FAIL: mcvio sim still runs 5 s after SIGTERM"
  kill -KILL $pid
  failed=1
else
  wait $pid
  rc=$?
  if [ $rc -eq 143 ]; then echo "ok: mcvio sim ended on SIGTERM (143)"; else echo "FAIL: mcvio sim exited $rc after SIGTERM (want 143)"; failed=1; fi
fi
# `mcvio run` turns the first Ctrl-C into a clean stop: exit 130, the frames done kept and marked.
"$mcvio" sim --duration 20 --out "$tmp/twenty" > /dev/null 2>&1
"$mcvio" run --dataset "$tmp/twenty" --out "$tmp/twenty_run" -q > "$tmp/run_int.txt" 2>&1 &
pid=$!
sleep 1
kill -INT $pid
wait $pid
rc=$?
if [ $rc -eq 130 ] && grep -q "interrupted before frame" "$tmp/run_int.txt" &&
   grep -q '"completed": false' "$tmp/twenty_run/stats.json"; then
  echo "ok: mcvio run stopped on SIGINT: $(grep -o 'interrupted before frame [0-9]* of [0-9]*' "$tmp/run_int.txt")"
else
  echo "FAIL: mcvio run after SIGINT exited $rc:"; tail -n 3 "$tmp/run_int.txt"; failed=1
fi
# `mcvio play` with nobody listening waits for readers; Ctrl-C must end that wait too (it once
# waited out --wait-for-readers topic after topic, deaf to the signal).
"$mcvio" --domain "$domain" play "$tmp/tiny" --wait-for-readers 60 > "$tmp/play_wait.txt" 2>&1 &
pid=$!
for _ in $(seq 1 100); do grep -q "waiting up to 60 s for readers of" "$tmp/play_wait.txt" && break; sleep 0.1; done
kill -INT $pid
for _ in $(seq 1 50); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
if kill -0 $pid 2>/dev/null; then
  echo "FAIL: mcvio play still waits for readers 5 s after SIGINT"; kill -KILL $pid; failed=1
else
  wait $pid
  rc=$?
  if [ $rc -eq 130 ] && grep -q "waiting up to 60 s for readers of /cam0/image_raw" "$tmp/play_wait.txt" &&
     grep -q "interrupted" "$tmp/play_wait.txt"; then
    echo "ok: mcvio play stopped waiting for readers on SIGINT (130)"
  else
    echo "FAIL: mcvio play after SIGINT while waiting exited $rc:"; cat "$tmp/play_wait.txt"; failed=1
  fi
fi
exit $failed
