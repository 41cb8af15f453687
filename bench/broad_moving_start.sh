#!/usr/bin/env bash
# Real data started while moving: each BROAD trial in ../shared/data cut to begin a few seconds
# after its first movement (the dataset's own mask), so that the start-up segment falls inside a
# hand-moved rotation. Heading RMSE during movement (bench/broad_heading_error, the dataset's
# definition) for auto and the paper's C beside the raw gyro with no bias removal, which is what
# an estimator that knows nothing at start would give. The last column: the share of the first
# start-up segment's 3 s (its output held at 0 deg until judged) that auto's sigma covers, |E| <= 2
# sigma, over those seconds' moving samples (the sigma of the turn the held segment could hide).
# Usage: bench/broad_moving_start.sh [SECONDS_AFTER_FIRST_MOVEMENT...]  (default: 3 10)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
data="$HEADINGD_ROOT/../shared/data"
out="$HEADINGD_ROOT/build/bench/broad-moving-start"
mkdir -p "$out"
offsets=("$@")
[ ${#offsets[@]} -eq 0 ] && offsets=(3 10)
printf '%-10s %8s | %9s %9s %9s   (heading RMSE while moving, deg) | %s\n' trial "start s" "raw gyro" auto C \
  "held 3 s within 2 sigma"
for trial in broad-01 broad-05 broad-08 broad-24 broad-26; do
  # The first row the dataset marks as moving.
  first=$(awk -F, 'NR > 1 && $6 == 1 { print $1; exit }' "$data/$trial/truth.csv")
  for offset in "${offsets[@]}"; do
    cut=$(awk -v a="$first" -v b="$offset" 'BEGIN { printf "%.3f", a + b }')
    dir="$out/$trial-$offset"
    mkdir -p "$dir"
    awk -F, -v c="$cut" 'NR == 1 || $1 / 1e9 >= c' "$data/$trial/imu.csv" >"$dir/imu.csv"
    awk -F, -v c="$cut" 'NR == 1 || $1 >= c' "$data/$trial/truth.csv" >"$dir/truth.csv"
    for method in auto c; do
      "$bin/app/headingd" replay --no-dds "$dir/imu.csv" --method "$method" --output-rate 0 \
        --output "$dir/est-$method.csv" --quiet
    done
    "$bin/bench/broad_heading_error" "$dir/truth.csv" "$dir/imu.csv" "auto=$dir/est-auto.csv" \
      "c=$dir/est-c.csv" >"$dir/score.txt"
    # The held start-up segment alone: each file cut to its first 3 s, scored the same way.
    awk -F, -v c="$cut" 'NR == 1 || $1 / 1e9 < c + 3.0' "$dir/imu.csv" >"$dir/held-imu.csv"
    awk -F, -v c="$cut" 'NR == 1 || $1 < c + 3.0' "$dir/truth.csv" >"$dir/held-truth.csv"
    awk -F, -v c="$cut" 'NR == 1 || $1 < c + 3.0' "$dir/est-auto.csv" >"$dir/held-est-auto.csv"
    held=$("$bin/bench/broad_heading_error" "$dir/held-truth.csv" "$dir/held-imu.csv" "auto=$dir/held-est-auto.csv" |
      awk '/headingd auto/ { print $9 " %" }')
    awk -v trial="$trial" -v cut="$cut" -v held="$held" '
      /no bias removal/ { raw = $NF }
      /headingd auto/ { auto = $3 }  # the figure, before the share within 2 sigma
      /headingd c/ { c = $3 }
      END { printf "%-10s %8s | %9s %9s %9s | %s\n", trial, cut, raw, auto, c, held }' "$dir/score.txt"
  done
done
