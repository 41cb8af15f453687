#!/usr/bin/env bash
# A state file whose zero-rate level is not the sensor's any more (a power cycle's turn-on shift, a
# chip replaced): a simulated AGV quarter-hour (stops of 8-46 s, none as long as recover_after_s)
# whose z rates are shifted by awk, replayed through `headingd run --recording --state` with the
# state file an unshifted run left (its heading taken out, so only the bias differs), beside the same
# run without state. Maximum and RMS heading error against the shifted truth (`headingd score`).
# Usage: bench/moved_level.sh [HEADINGD]  (default: this checkout's build)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
headingd="${1:-$HEADINGD_ROOT/build/default/app/headingd}"
out="$HEADINGD_ROOT/build/bench/moved-level"
mkdir -p "$out"
printf '[state]\nrestore_heading = false\n' >"$out/no-heading.toml"
"$headingd" simulate --scenario agv --seed 3 --hours 0.25 --output-dir "$out/saved" >/dev/null
"$headingd" simulate --scenario agv --seed 4 --hours 0.25 --output-dir "$out/agv" >/dev/null
rm -f "$out/saved.state"
"$headingd" run --recording "$out/saved/imu.csv" --speed max --no-dds --state "$out/saved.state" -o /dev/null 2>/dev/null
printf '%9s | %12s %12s | %12s %12s   (heading error, deg)\n' "shift dps" "none max" "none RMS" "state max" "state RMS"
for shift in -1.0 -0.05 0 0.02 0.1 0.5 2.0; do
  awk -F, -v o="$shift" 'BEGIN { OFS = "," } /^#/ || /^time/ { print; next } { $4 += o; print }' \
    "$out/agv/imu.csv" >"$out/imu.csv"
  awk -F, -v o="$shift" 'BEGIN { OFS = "," } /^#/ || /^time/ { print; next } { $3 += o; print }' \
    "$out/agv/truth.csv" >"$out/truth.csv"
  "$headingd" run --recording "$out/imu.csv" --speed max --no-dds -o "$out/none.csv" 2>/dev/null
  cp "$out/saved.state" "$out/copy.state"
  "$headingd" run --config "$out/no-heading.toml" --recording "$out/imu.csv" --speed max --no-dds \
    --state "$out/copy.state" -o "$out/state.csv" 2>/dev/null
  none=$("$headingd" score "$out/none.csv" "$out/truth.csv" --label none | awk '$1 == "none" && NF == 6 { print $2, $4 }')
  with=$("$headingd" score "$out/state.csv" "$out/truth.csv" --label state | awk '$1 == "state" && NF == 6 { print $2, $4 }')
  read -r none_max none_rms <<<"$none"
  read -r state_max state_rms <<<"$with"
  printf '%9s | %12s %12s | %12s %12s\n' "$shift" "$none_max" "$none_rms" "$state_max" "$state_rms"
done
# And a state file another rate left: the unshifted run averaged over 16 samples (25 Hz), so its
# sigma_still is about a third of the 400 Hz sensor's; the level the same.
awk -F, 'BEGIN { OFS = "," } /^#/ || /^time/ { print; next }
  { n++; if (n % 16 == 1) t = $1; for (i = 2; i <= NF; i++) s[i] += $i
    if (n % 16 == 0) { line = t; for (i = 2; i <= 4; i++) { line = line "," s[i] / 16 }; print line "," $5
      for (i = 2; i <= NF; i++) s[i] = 0 } }' "$out/saved/imu.csv" >"$out/slow.csv"
rm -f "$out/slow.state"
"$headingd" run --recording "$out/slow.csv" --speed max --no-dds --state "$out/slow.state" -o /dev/null 2>/dev/null
"$headingd" run --config "$out/no-heading.toml" --recording "$out/agv/imu.csv" --speed max --no-dds \
  --state "$out/slow.state" -o "$out/slow-state.csv" 2>"$out/summary.txt"
still=$(sed -n 's/.*segments up to [0-9.]* s: \([0-9]*\) accepted as still.*/\1/p' "$out/summary.txt")
slow=$("$headingd" score "$out/slow-state.csv" "$out/agv/truth.csv" --label s | awk '$1 == "s" && NF == 6 { print $2, $4 }')
echo "state saved at 25 Hz, run at 400 Hz: $still segments accepted as still; heading error max and RMS $slow deg"
