#!/usr/bin/env bash
# The five real BROAD trials (../shared/data) with holes: 0.5 s of samples removed every 20 s from
# 10 s on (lost FIFOs, a chip set up again). `auto` bridges each gap at the rate on either side;
# against the gyro-only reference with the first rest's bias integrated over the same holes (each
# one's time at the sample after it, as any integrator that does not know about gaps does), its
# heading RMSE while moving is no worse than today's ratio, and at least 95 % of the moving samples
# lie within its own 2 sigma (before gaps were bridged: 85, 100, 100, 82 and 19 %). The replay
# summary counts the gaps. Figures: bench/broad_gaps.sh and the README.
# Usage: broad_gaps.sh HEADINGD BROAD_HEADING_ERROR DATA_ROOT
set -uo pipefail
source "$(dirname "$0")/broad_common.sh"
# trial:largest ratio accepted (today 0.71, 0.55, 0.67, 0.76, 0.15)
for limit in broad-01:0.75 broad-05:0.60 broad-08:0.70 broad-24:0.80 broad-26:0.20; do
  trial="${limit%%:*}"
  holed="$dir/$trial-holed.csv"
  awk -F, 'NR == 1 || /^#/ { print; next } { t = $1 / 1e9 - 10; if (t >= 0 && t - 20 * int(t / 20) < 0.5) next; print }' \
    "$data/$trial/imu.csv" >"$holed"
  expected=$(awk -F, 'NR > 1 && !/^#/ { t = $1 / 1e9 } END { n = 0; for (s = 10; s + 0.5 < t; s += 20) n++; print n }' \
    "$data/$trial/imu.csv")
  summary=$("$headingd" replay --no-dds "$holed" -o "$dir/summary-est.csv" 2>&1) || fail "$trial: replay failed: $summary"
  gaps=$(sed -n 's/^  gaps *\([0-9]*\) in the samples.*/\1/p' <<<"$summary")
  [ "$gaps" = "$expected" ] || fail "$trial: the summary counts '${gaps}' gaps, not $expected: $summary"
  echo "$trial: $gaps gaps bridged"
  check_ratio "$trial" "$holed" "$data/$trial/truth.csv" "bias of first rest by hand" "${limit#*:}" 95
done
echo "ok: five BROAD trials with holes"
