#!/usr/bin/env bash
# A Cyclone DDS subscriber (idlc-generated types) reads headingd's Orientation and the ROS 2
# Imu topic published by Fast DDS, over UDP on 127.0.0.1.
set -uo pipefail
headingd="$1"
subscriber="$2"
root="$3"
dir="$(mktemp -d)"
trap 'kill $replay 2>/dev/null; rm -rf "$dir"' EXIT
printf '[dds]\ndomain_id = 44\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$root" >"$dir/cfg.toml"
export CYCLONEDDS_URI="file://$root/tests/interop/cyclone.xml"
"$headingd" replay "$root/tests/data/agv-1min/imu.csv" --speed 4 --wait-subscribers 20 -c "$dir/cfg.toml" -o /dev/null -q &
replay=$!
"$subscriber" 44 headingd/orientation rt/imu/data 50 30 >"$dir/sub.out" 2>&1
rc=$?
cat "$dir/sub.out"
[ "$rc" -eq 0 ] || { echo "FAIL: the Cyclone subscriber did not get 50 of each"; exit 1; }
grep -q "frame_id 'imu_link'" "$dir/sub.out" && grep -q "linear_acceleration_covariance\[0\] -1" "$dir/sub.out" ||
  { echo "FAIL: Imu fields"; exit 1; }
echo "ok: Cyclone DDS read headingd's Orientation and the ROS 2 Imu topic"

# A reader that requests a deadline (100 ms) matches only a writer offering one as short: none by
# default (no timer restart per message), 3 periods (60 ms) with orientation_deadline_periods = 3.
deadline_run() {
  printf '[dds]\ndomain_id = 44\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n%s\n' "$root" "$1" >"$dir/cfg.toml"
  "$headingd" replay "$root/tests/data/agv-1min/imu.csv" --speed 4 --wait-subscribers "$2" -c "$dir/cfg.toml" \
    -o /dev/null -q &
  replay=$!
  "$subscriber" 44 headingd/orientation rt/imu/data 50 "$2" 100 >"$dir/sub.out" 2>&1
  rc=$?
  kill $replay 2>/dev/null
  wait $replay 2>/dev/null
  cat "$dir/sub.out"
}
deadline_run "orientation_deadline_periods = 3" 30
[ "$rc" -eq 0 ] || { echo "FAIL: a reader requesting a 100 ms deadline got too little with 3 periods offered"; exit 1; }
deadline_run "" 6
grep -q "^cyclone: 0 Orientation" "$dir/sub.out" ||
  { echo "FAIL: a reader requesting a deadline matched a writer that offers none"; exit 1; }
echo "ok: a deadline-requesting Cyclone reader is served when orientation_deadline_periods offers one, and only then"
