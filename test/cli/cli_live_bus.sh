#!/usr/bin/env bash
# `mcvio bus-demo` publishes; topics, echo and nodes in other processes must see it as ROS 2 tools would.
set -u
mcvio=$1
export ROS_DOMAIN_ID=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
"$mcvio" bus-demo --duration 20 > "$tmp/demo.txt" 2>&1 &
demo=$!
trap 'kill -TERM $demo 2>/dev/null; wait $demo 2>/dev/null; rm -rf "$tmp"' EXIT
failed=0
# The demo needs a moment to start under load: poll `mcvio topics` until its topics show up.
for attempt in 1 2 3 4 5 6 7 8 9 10; do
  timeout -s KILL 30 "$mcvio" topics --wait 1 > "$tmp/topics.txt" 2>&1
  grep -qF "/cam0/camera_info" "$tmp/topics.txt" && break
done
check() {  # check NAME PATTERN FILE
  if grep -qF -- "$2" "$3"; then echo "ok: $1"; else echo "FAIL: $1: no '$2' in:"; sed 's/^/    /' "$3" | head -n 20; failed=1; fi
}
check "topics lists the image with its ROS 2 type" "/cam0/image_raw [sensor_msgs/msg/Image]" "$tmp/topics.txt"
check "topics lists the IMU" "/imu0 [sensor_msgs/msg/Imu]" "$tmp/topics.txt"
check "topics lists calibration" "/cam0/camera_info [sensor_msgs/msg/CameraInfo]" "$tmp/topics.txt"
timeout -s KILL 30 "$mcvio" echo /imu0 --count 2 --timeout 10 > "$tmp/echo.txt" 2>&1
check "echo decodes the IMU frame id" "frame_id: 'imu0'" "$tmp/echo.txt"
check "echo decodes gravity" "z: 9.81" "$tmp/echo.txt"
[ "$(grep -c '^---$' "$tmp/echo.txt")" -eq 2 ] && echo "ok: echo --count 2 printed 2 messages" || { echo "FAIL: echo count"; failed=1; }
timeout -s KILL 30 "$mcvio" echo /cam0/camera_info --count 1 --timeout 10 > "$tmp/info.txt" 2>&1
check "echo gets transient-local calibration as a late joiner" "distortion_model: 'plumb_bob'" "$tmp/info.txt"
for attempt in 1 2 3 4 5; do  # discovery of a new participant can take a moment under load
  timeout -s KILL 30 "$mcvio" nodes --wait 2 > "$tmp/nodes.txt" 2>&1
  grep -qF "/mcvio/demo_device" "$tmp/nodes.txt" && break
done
check "nodes shows the demo's node" "/mcvio/demo_device" "$tmp/nodes.txt"
exit $failed
