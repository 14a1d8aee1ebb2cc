#!/usr/bin/env bash
# `mcvio launch` as a user runs it: the shipped config/pipeline.yaml lists its arguments, runs a
# lossless player -> frontend -> backend -> recorder launch to the end (every frame handled, the
# poses in the bag), in one process and with --processes (one per component: the same bag
# contents; a killed backend respawned), stops cleanly on Ctrl-C with the bag closed, and bad
# launch input is named. Remapped onto a camera driver's topic names the same launch gives the
# same poses, and `mcvio run --remap` on its bag gives those of the EuRoC folder (and so do
# Kalibr files whose rostopic names the driver's topics).
set -u
mcvio=$1
file="$(cd "$(dirname "$0")/../.." && pwd)/config/pipeline.yaml"
domain=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
. "$(dirname "$0")/expect.sh"
expect 0 "data:=(required)" -- "$mcvio" launch "$file" --show-args
expect 2 "give the required argument(s) data:=VALUE" -- "$mcvio" --domain "$domain" launch "$file"
expect 2 "launch argument 'data=/x' is not NAME:=VALUE" -- "$mcvio" --domain "$domain" launch "$file" data=/x
expect 2 "no argument 'dta' is declared (declared: data, mode" -- "$mcvio" --domain "$domain" launch "$file" data:=/x dta:=1
expect 2 "argument 'mode' is given twice" -- "$mcvio" --domain "$domain" launch "$file" data:=/x mode:=imu mode:=auto
expect 2 "component 'backend': 'mode': unknown mode 'fast'" -- "$mcvio" --domain "$domain" launch "$file" data:=/x mode:=fast
expect 2 "components[3].if is 'maybe'; it must be true or false" -- "$mcvio" --domain "$domain" launch "$file" data:=/x play:=maybe
expect 2 "$tmp: is a folder; the launch file must be a YAML file" -- "$mcvio" --domain "$domain" launch "$tmp"
expect 2 "$tmp/missing.yaml" -- "$mcvio" --domain "$domain" launch "$tmp/missing.yaml"
printf 'components:\n  - component: player\n    input: x\n    rat: 2\n' > "$tmp/typo.yaml"
expect 2 "$tmp/typo.yaml:2: component 'player': unknown launch key 'components[0].rat'" -- "$mcvio" --domain "$domain" launch "$tmp/typo.yaml"
expect 2 "/nonexistent: calibration folder or file does not exist" -- "$mcvio" --domain "$domain" launch "$file" data:=/nonexistent

"$mcvio" sim --duration 3 --out "$tmp/seq" > /dev/null 2>&1
expect_timeout=120 expect 0 "frontend 'frontend': 61 stereo pairs, 61 feature frames published, 0 skipped, 0 dropped" -- \
  "$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" lossless:=true record:=true bag:="$tmp/bag" -q
poses=$("$mcvio" bag info "$tmp/bag" | grep -F 'Topic: /mcvio/odometry |' | sed -nE 's/.*Count: ([0-9]+).*/\1/p')
if [ "${poses:-0}" -gt 0 ]; then echo "ok: the bag holds $poses poses"; else echo "FAIL: no /mcvio/odometry in the launch's bag"; failed=1; fi
expect 2 "$tmp/bag: exists and is not an empty directory" -- "$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" record:=true bag:="$tmp/bag"

# The same pipeline on a driver's topic names (remap: in the launch file, both forms), a typo
# warned about; the bag holds the driver's names, and `mcvio run --remap` on it gives the poses
# of `mcvio run` on the EuRoC folder.
cat > "$tmp/remap.yaml" <<'YAML'
arguments:
  data: {description: "EuRoC folder"}
  bag: {description: "bag to record"}
components:
  - component: recorder
    output: $(arg bag)
    regex: "^/(driver/.*|odom)$"
  - component: frontend
    calibration: $(arg data)
    lossless: true
    remap:
      - /cam0/image_raw:=/driver/left/image_raw
      - {from: /cam1/image_raw, to: /driver/right/image_raw}
      - /imu0:=/driver/imu
  - component: backend
    calibration: $(arg data)
    lossless: true
    remap: [/imu0:=/driver/imu, /mcvio/odometry:=/odom, /mcvio/odometri:=/x]
  - component: player
    input: $(arg data)
    lossless: true
    remap: [/cam0/image_raw:=/driver/left/image_raw, /cam1/image_raw:=/driver/right/image_raw, /imu0:=/driver/imu,
            /cam0/camera_info:=/driver/left/camera_info, /cam1/camera_info:=/driver/right/camera_info]
YAML
expect_timeout=120 expect 0 "component 'backend': remap /mcvio/odometri:=/x matches none of its topics" -- \
  "$mcvio" --domain "$domain" launch "$tmp/remap.yaml" data:="$tmp/seq" bag:="$tmp/rbag" -q
remapped_poses=$("$mcvio" bag info "$tmp/rbag" | grep -F 'Topic: /odom |' | sed -nE 's/.*Count: ([0-9]+).*/\1/p')
if [ "${remapped_poses:-0}" -gt 0 ] && [ "$remapped_poses" = "$poses" ] && "$mcvio" bag info "$tmp/rbag" | grep -qF 'Topic: /driver/imu |' &&
   ! "$mcvio" bag info "$tmp/rbag" | grep -qF 'Topic: /imu0 |'; then
  echo "ok: the remapped launch published $remapped_poses poses on /odom and the driver's topics"
else
  echo "FAIL: the remapped launch's bag:"; "$mcvio" bag info "$tmp/rbag" | grep -F Topic; failed=1
fi
expect 0 "remap /nope:=/x: $tmp/rbag has no topic /nope" -- \
  "$mcvio" --domain "$domain" play "$tmp/rbag" --remap /driver/imu:=/imu0 --remap /nope:=/x --wait-for-readers 0 -q --rate 50
expect 0 "poses" -- "$mcvio" run --dataset "$tmp/seq" --out "$tmp/run_euroc" -q
driver_remap=(--remap /cam0/image_raw:=/driver/left/image_raw --remap /cam1/image_raw:=/driver/right/image_raw --remap /imu0:=/driver/imu)
# same_trajectory A B WHAT: runs A and B wrote the same trajectory.tum, byte for byte.
same_trajectory() {
  if [ -s "$1/trajectory.tum" ] && cmp -s "$1/trajectory.tum" "$2/trajectory.tum"; then echo "ok: $3"; else echo "FAIL: not so: $3"; failed=1; fi
}
expect 0 "poses" -- "$mcvio" run --dataset "$tmp/rbag" --calib "$tmp/seq" --out "$tmp/run_rbag" -q "${driver_remap[@]}"
same_trajectory "$tmp/run_euroc" "$tmp/run_rbag" "mcvio run --remap on the driver-named bag gives the EuRoC folder's trajectory"
# The sequence's calibration as Kalibr writes it (camchain-imucam + imu.yaml, no time shift):
# `mcvio run --calib` on those gives the EuRoC run's poses.
python3 - "$tmp/seq/mav0" "$tmp/kalibr" <<'PY'
import os, re, sys
mav0, out = sys.argv[1], sys.argv[2]
os.makedirs(out)
def keys(path):
    text = open(path).read()
    grab = lambda k: re.search(r'^' + k + r':\s*(.*?)\s*(#.*)?$', text, re.M).group(1)
    data = [float(v) for v in re.search(r'data:\s*\[([^\]]*)\]', text).group(1).replace('\n', ' ').split(',')]
    return grab, [data[0:4], data[4:8], data[8:12], data[12:16]]
chain = ''
for cam in ('cam0', 'cam1'):
    grab, T = keys(f'{mav0}/{cam}/sensor.yaml')
    R = [row[:3] for row in T[:3]]; t = [row[3] for row in T[:3]]
    Rt = [[R[c][r] for c in range(3)] for r in range(3)]
    ti = [-sum(Rt[r][c] * t[c] for c in range(3)) for r in range(3)]
    rows = [Rt[r] + [ti[r]] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
    model = {'radial-tangential': 'radtan'}.get(grab('distortion_model'), grab('distortion_model'))
    chain += (f'{cam}:\n  camera_model: pinhole\n  intrinsics: {grab("intrinsics")}\n  distortion_model: {model}\n'
              f'  distortion_coeffs: {grab("distortion_coefficients")}\n  resolution: {grab("resolution")}\n'
              f'  rostopic: /{cam}/image_raw\n  timeshift_cam_imu: 0.0\n  T_cam_imu:\n' +
              ''.join('  - [' + ', '.join(repr(v) for v in row) + ']\n' for row in rows))
open(f'{out}/camchain-imucam-seq.yaml', 'w').write(chain)
grab, _ = keys(f'{mav0}/imu0/sensor.yaml')
open(f'{out}/imu.yaml', 'w').write(''.join(f'{k}: {grab(k)}\n' for k in (
    'accelerometer_noise_density', 'accelerometer_random_walk', 'gyroscope_noise_density', 'gyroscope_random_walk')) +
    f'update_rate: {grab("rate_hz")}\nrostopic: /imu0\n')
PY
expect 0 "poses" -- "$mcvio" run --dataset "$tmp/seq" --calib "$tmp/kalibr" --out "$tmp/run_kalibr" -q
if [ -s "$tmp/run_kalibr/trajectory.tum" ] && [ "$(wc -l < "$tmp/run_kalibr/trajectory.tum")" = "$(wc -l < "$tmp/run_euroc/trajectory.tum")" ] &&
   paste -d' ' "$tmp/run_euroc/trajectory.tum" "$tmp/run_kalibr/trajectory.tum" | awk '
     /^#/ { next } { if ($1 != $9) bad = 1; for (k = 2; k <= 4; ++k) { d = $k - $(k + 8); if (d > 1e-6 || d < -1e-6) bad = 1 } }
     END { exit bad }'; then
  echo "ok: mcvio run --calib with Kalibr's files gives the EuRoC calibration's poses (within 1 um)"
else
  echo "FAIL: mcvio run --calib KALIBR differs from the EuRoC run"; failed=1
fi
expect 2 "neither a EuRoC folder" -- "$mcvio" run --dataset "$tmp/seq" --calib "$tmp" --out "$tmp/run_nocalib" -q
baseline=$("$mcvio" calib "$tmp/seq" | grep '^stereo:')
expect 0 "$baseline" -- "$mcvio" calib "$tmp/kalibr"
expect 0 "wrote $tmp/kalibr_euroc/mav0/{cam0,cam1,imu0}/sensor.yaml" -- "$mcvio" calib "$tmp/kalibr" --to-euroc "$tmp/kalibr_euroc"
expect 0 "$baseline" -- "$mcvio" calib "$tmp/kalibr_euroc"
expect 2 "$tmp/kalibr_euroc/mav0: already exists" -- "$mcvio" calib "$tmp/kalibr" --to-euroc "$tmp/kalibr_euroc"
# Kalibr's rostopic naming the driver's topics: `mcvio run` on the driver-named bag takes them as
# the --remap rules given by hand do (OpenVINS reads its topics from there too).
expect 0 "wrote $tmp/kalibr_driver/camchain-imucam.yaml and imu.yaml" -- "$mcvio" calib "$tmp/seq" --to-kalibr "$tmp/kalibr_driver"
expect 0 "$baseline" -- "$mcvio" calib "$tmp/kalibr_driver"
expect 2 "$tmp/kalibr_driver/camchain-imucam.yaml: already exists; --to-kalibr does not overwrite" -- \
  "$mcvio" calib "$tmp/seq" --to-kalibr "$tmp/kalibr_driver"
sed -i 's|^  rostopic: /cam0/image_raw$|  rostopic: /driver/left/image_raw|; s|^  rostopic: /cam1/image_raw$|  rostopic: /driver/right/image_raw|' \
  "$tmp/kalibr_driver/camchain-imucam.yaml"
sed -i 's|^rostopic: /imu0$|rostopic: /driver/imu|' "$tmp/kalibr_driver/imu.yaml"
expect 0 "topics (rostopic): cam0 /driver/left/image_raw, cam1 /driver/right/image_raw, imu0 /driver/imu" -- \
  "$mcvio" calib "$tmp/kalibr_driver"
expect 0 "reading /imu0 from /driver/imu, its rostopic in the calibration" -- \
  "$mcvio" run --dataset "$tmp/rbag" --calib "$tmp/kalibr_driver" --out "$tmp/run_rostopic" -q
expect 0 "poses" -- "$mcvio" run --dataset "$tmp/rbag" --calib "$tmp/kalibr_driver" --out "$tmp/run_rostopic_by_hand" -q "${driver_remap[@]}"
same_trajectory "$tmp/run_rostopic" "$tmp/run_rostopic_by_hand" \
  "mcvio run with Kalibr's rostopic on the driver-named bag gives the trajectory of the --remap rules"
expect 2 "the bag has no /imu0" -- "$mcvio" run --dataset "$tmp/rbag" --calib "$tmp/kalibr_driver" --out "$tmp/run_rostopic2" -q --remap /imu0:=/imu0

expect 2 "the bag has no /cam0/image_raw (it holds " -- "$mcvio" run --dataset "$tmp/rbag" --calib "$tmp/seq" --out "$tmp/run_rbag2" -q
expect 2 "--remap names a bag's topics; $tmp/seq is a EuRoC folder" -- \
  "$mcvio" run --dataset "$tmp/seq" --out "$tmp/run_r3" -q --remap /imu0:=/driver/imu
expect 2 "remap rule '/imu0': expected FROM:=TO" -- "$mcvio" --domain "$domain" backend --calib "$tmp/seq" --remap /imu0
printf 'components:\n  - component: recorder\n    output: %s\n    all: true\n    remap: [/a:=/b]\n' "$tmp/nobag" > "$tmp/rrec.yaml"
expect 2 "'remap' is for players, frontends and backends" -- "$mcvio" --domain "$domain" launch "$tmp/rrec.yaml"
printf 'components:\n  - component: frontend\n    calibration: %s\n    image_transport: h264\n' "$tmp/seq" > "$tmp/tbad.yaml"
expect 2 "'image_transport' is 'h264'; it must be raw or compressed" -- "$mcvio" --domain "$domain" launch "$tmp/tbad.yaml"
expect 105 "--image-transport: h264 not in {raw,compressed}" -- "$mcvio" --domain "$domain" frontend --calib "$tmp/seq" --image-transport h264
printf 'components:\n  - component: backend\n    calibration: %s\n    remap: [{from: /imu0}]\n' "$tmp/seq" > "$tmp/rbad.yaml"
expect 2 "remap[0] must be FROM:=TO or a map with exactly 'from' and 'to'" -- "$mcvio" --domain "$domain" launch "$tmp/rbad.yaml"

# One process per component: every process ends cleanly and the bag holds what the in-process
# launch recorded, topic by topic.
expect_timeout=120 expect 0 "recorder 'recorder': process" -- \
  "$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" lossless:=true record:=true bag:="$tmp/pbag" -q --processes
counts() { "$mcvio" bag info "$1" | grep -F 'Count:' | sed -E 's/.*Topic: ([^ ]+) .*Count: ([0-9]+).*/\1 \2/' | sort; }
if [ -n "$(counts "$tmp/bag")" ] && [ "$(counts "$tmp/bag")" = "$(counts "$tmp/pbag")" ]; then
  echo "ok: --processes recorded what the in-process launch did ($(counts "$tmp/pbag" | tr '\n' ' '))"
else
  echo "FAIL: --processes recorded other counts:"; diff <(counts "$tmp/bag") <(counts "$tmp/pbag"); failed=1
fi
expect 1 "launch: frontend 'frontend' exited with 2 before it started" -- \
  "$mcvio" --domain "$domain" launch "$file" data:=/nonexistent --processes
expect 2 "starts no component 'nope'" -- "$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" --node nope

# respawn:=true with --processes: a backend killed while the player plays is started again, and
# the launch ends cleanly once the player is done.
"$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" respawn:=true --processes -q > "$tmp/respawn.txt" 2>&1 &
pid=$!
for _ in $(seq 1 200); do grep -q "started player 'player'" "$tmp/respawn.txt" && break; sleep 0.1; done
backend=$(sed -nE "s/.*started backend 'backend' \(pid ([0-9]+)\).*/\1/p" "$tmp/respawn.txt" | head -n 1)
sleep 0.5
[ -n "$backend" ] && kill -KILL "$backend"
wait $pid
rc=$?
if [ $rc -eq 0 ] && [ -n "$backend" ] &&
   grep -qF "backend 'backend' was ended by signal 9 (Killed) while the launch ran; respawning it (respawn 1)" "$tmp/respawn.txt" &&
   grep -qE "backend 'backend': process [0-9]+, exited cleanly \(respawned 1 time\)" "$tmp/respawn.txt"; then
  echo "ok: mcvio launch --processes respawned the killed backend (pid $backend) and ended cleanly"
else
  echo "FAIL: mcvio launch --processes respawn:=true exited $rc after killing the backend (pid ${backend:-none}):"
  tail -n 12 "$tmp/respawn.txt"; failed=1
fi

# Without a player it runs until Ctrl-C, then closes the bag: exit 130. In one process 'respawn'
# is named as ignored.
"$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" play:=false record:=true bag:="$tmp/live" respawn:=true \
  > "$tmp/live.txt" 2>&1 &
pid=$!
for _ in $(seq 1 100); do grep -q "running; Ctrl-C to stop" "$tmp/live.txt" && break; sleep 0.1; done
kill -INT $pid
wait $pid
rc=$?
if [ $rc -eq 130 ] && grep -q "interrupted" "$tmp/live.txt" && [ -f "$tmp/live/metadata.yaml" ] &&
   grep -qF "backend 'backend' has 'respawn', which takes --processes (in one process a crash ends the launch); ignored" "$tmp/live.txt"; then
  echo "ok: mcvio launch stopped on SIGINT (130), bag closed; respawn named as ignored in one process"
else
  echo "FAIL: mcvio launch after SIGINT exited $rc:"; tail -n 5 "$tmp/live.txt"; failed=1
fi

# --processes without a player: Ctrl-C reaches the supervisor, which stops every process; 130,
# bag closed.
"$mcvio" --domain "$domain" launch "$file" data:="$tmp/seq" play:=false record:=true bag:="$tmp/plive" --processes \
  > "$tmp/plive.txt" 2>&1 &
pid=$!
for _ in $(seq 1 200); do grep -q "started backend 'backend'" "$tmp/plive.txt" && break; sleep 0.1; done
sleep 1
kill -INT $pid
wait $pid
rc=$?
if [ $rc -eq 130 ] && grep -q "recorder 'recorder': process [0-9]*, exited with 130 (interrupted)" "$tmp/plive.txt" &&
   [ -f "$tmp/plive/metadata.yaml" ]; then
  echo "ok: mcvio launch --processes stopped every process on SIGINT (130), bag closed"
else
  echo "FAIL: mcvio launch --processes after SIGINT exited $rc:"; tail -n 8 "$tmp/plive.txt"; failed=1
fi
exit $failed
