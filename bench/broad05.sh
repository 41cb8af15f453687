#!/usr/bin/env bash
# Real data: heading RMSE during movement on ../shared/data/broad-05 (the BROAD benchmark's
# trial 05), as its README defines it, for method auto and the paper's C, beside the
# dataset's own references (no bias removal; bias from the first rest by hand).
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
data="${1:-$HEADINGD_ROOT/../shared/data/broad-05}"
out="$HEADINGD_ROOT/build/bench/$(basename "$data")"
mkdir -p "$out"
args=()
for method in auto c; do
  "$bin/app/headingd" replay --no-dds "$data/imu.csv" --method "$method" --output-rate 0 --output "$out/est-$method.csv" --quiet
  args+=("$method=$out/est-$method.csv")
done
"$bin/bench/broad_heading_error" "$data/truth.csv" "$data/imu.csv" "${args[@]}"
