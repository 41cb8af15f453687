#!/usr/bin/env bash
# The five real BROAD trials (../shared/data): heading RMSE during movement of `auto` against the
# gyro-only reference with the first rest's bias, each no worse than today's ratio (a guard, with
# today's figures in bench/broad.sh's output and the README; issue 12 asks for <= 1.0 on each).
# Usage: broad_trials.sh HEADINGD BROAD_HEADING_ERROR DATA_ROOT
set -uo pipefail
source "$(dirname "$0")/broad_common.sh"
# trial:largest auto/reference ratio accepted (today: 1.006, 1.44, 1.001, 0.95, 0.98). And on
# each, at least 95 % of the moving samples within auto's own 2 sigma (today 99.6, 99.9, 99.9,
# 98.2, 98.9 %; 29.5 % on broad-01 and 74.6 % on broad-26 while only z's scale error counted).
for limit in broad-01:1.02 broad-05:1.50 broad-08:1.02 broad-24:1.00 broad-26:1.00; do
  trial="${limit%%:*}"
  check_ratio "$trial" "$data/$trial/imu.csv" "$data/$trial/truth.csv" "bias of first rest by hand" "${limit#*:}" 95
done
echo "ok: five BROAD trials"
