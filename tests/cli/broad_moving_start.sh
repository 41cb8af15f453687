#!/usr/bin/env bash
# The five real BROAD trials cut to begin 3 s after their first movement (the dataset's mask),
# so that the start-up falls inside a hand-moved rotation, tapping or vibration: heading RMSE
# during movement of `auto` against the raw gyro with no bias removal (what knowing nothing at
# start gives), each no worse than today's ratio (bench/broad_moving_start.sh prints the
# figures; before the moving start-up was detected, auto gave 54-124 deg on every cut).
# Usage: broad_moving_start.sh HEADINGD BROAD_HEADING_ERROR DATA_ROOT
set -uo pipefail
source "$(dirname "$0")/broad_common.sh"
# trial:largest auto/raw ratio accepted (today: 1.002, 0.20, 0.69, 3.78, 1.07; broad-24's is the
# start-up segment's 3 s, held still as every start-up is until its blocks are judged); and at least
# 95 % of each cut's moving samples within auto's own 2 sigma (today 100.0 % on each)
for limit in broad-01:1.05 broad-05:0.25 broad-08:0.75 broad-24:3.9 broad-26:1.1; do
  trial="${limit%%:*}"
  first=$(awk -F, 'NR > 1 && $6 == 1 { print $1; exit }' "$data/$trial/truth.csv")
  [ -n "$first" ] || fail "$trial: no movement in its truth"
  cut=$(awk -v a="$first" 'BEGIN { printf "%.3f", a + 3 }')
  awk -F, -v c="$cut" 'NR == 1 || $1 / 1e9 >= c' "$data/$trial/imu.csv" >"$dir/imu.csv"
  awk -F, -v c="$cut" 'NR == 1 || $1 >= c' "$data/$trial/truth.csv" >"$dir/truth.csv"
  check_ratio "$trial from $cut s" "$dir/imu.csv" "$dir/truth.csv" "no bias removal" "${limit#*:}" 95
done
echo "ok: five BROAD trials started while moving"
