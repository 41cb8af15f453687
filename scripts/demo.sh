#!/usr/bin/env bash
# The README's first command: builds headingd and runs its main job on the bundled
# recording (a simulated warehouse AGV), then compares the methods on an hour of the same work.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet

headingd="$HEADINGD_ROOT/build/default/daemon/headingd"
recording="$HEADINGD_ROOT/data/agv-demo"
out="$HEADINGD_ROOT/build/demo"
mkdir -p "$out"

"$headingd" replay --no-dds "$recording/imu.csv" --output "$out/estimates.csv"
echo
echo "Estimates: $out/estimates.csv (first rows below)"
head -n 4 "$out/estimates.csv"

# Two minutes hold too few stops to compare methods; an hour of the same kind of AGV work does.
echo
echo "Heading error on a simulated hour of AGV work (headingd simulate --scenario agv --seed 1):"
"$headingd" simulate --scenario agv --seed 1 --output-dir "$out/agv-1h" 2>/dev/null
first=1
for method in auto a b c; do
  "$headingd" replay --no-dds "$out/agv-1h/imu.csv" --method "$method" --output "$out/agv-1h/estimates-$method.csv" --quiet
  header=()
  [ "$first" -eq 1 ] && header=(--header) && first=0
  "$headingd" score "$out/agv-1h/estimates-$method.csv" "$out/agv-1h/truth.csv" --label "$method" "${header[@]}"
done
