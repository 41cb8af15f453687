#!/usr/bin/env bash
# The README's first command: builds headingd and runs its main job on the bundled
# recording (a simulated warehouse AGV with its true heading), then scores the result.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet

headingd="$HEADINGD_ROOT/build/default/daemon/headingd"
recording="$HEADINGD_ROOT/data/agv-demo"
out="$HEADINGD_ROOT/build/demo"
mkdir -p "$out"

"$headingd" replay "$recording/imu.csv" --output "$out/estimates.csv"
echo
echo "Heading error against the recording's truth (paper's metrics):"
first=1
for method in a b c; do
  "$headingd" replay "$recording/imu.csv" --method "$method" --output "$out/estimates-$method.csv" --quiet
  header=()
  [ "$first" -eq 1 ] && header=(--header) && first=0
  "$headingd" score "$out/estimates-$method.csv" "$recording/truth.csv" --label "$method" "${header[@]}"
done
echo
echo "Estimates: $out/estimates.csv (first rows below)"
head -n 4 "$out/estimates.csv"
