#!/usr/bin/env bash
# The README's first command: builds headingd and runs its main job on the bundled
# recording (a simulated warehouse AGV), then compares the methods on an hour of the same work.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet

headingd="$HEADINGD_ROOT/build/default/app/headingd"
recording="$HEADINGD_ROOT/data/agv-demo"
out="$HEADINGD_ROOT/build/demo"
mkdir -p "$out"

# The daemon's pipeline: replay publishes over DDS (loopback only) as the live daemon would,
# and `headingd echo` shows what a navigation stack subscribing to it receives.
cat >"$out/dds.toml" <<TOML
[dds]
profiles_xml = "$HEADINGD_ROOT/config/fastdds-loopback.xml"
TOML
"$headingd" echo orientation bias status -c "$out/dds.toml" --timeout 30 >"$out/echo.txt" 2>&1 &
echo_pid=$!
"$headingd" replay "$recording/imu.csv" --speed 10 --wait-subscribers 10 -c "$out/dds.toml" --output "$out/estimates.csv"
kill -INT "$echo_pid" 2>/dev/null || true
wait "$echo_pid" 2>/dev/null || true
echo
echo "What a DDS subscriber received ($(grep -c '^orientation' "$out/echo.txt") Orientation messages at 50 Hz; a few lines):"
grep -m 2 '^orientation' "$out/echo.txt" || true
grep -m 1 '^bias' "$out/echo.txt" || true
grep '^status' "$out/echo.txt" | tail -n 1 || true
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
