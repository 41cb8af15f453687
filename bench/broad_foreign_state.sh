#!/usr/bin/env bash
# Real data, a state file from another power-up: each BROAD trial in ../shared/data replayed
# through `headingd run --recording --state` with the state file another trial left (its bias,
# noise and temperature; not its heading: `[state] restore_heading = false`), as a daemon restarted
# after a power cycle or with another sensor finds it. The trials were recorded at separate
# power-ups of the same IMU type, and their zero-rate levels differ by up to 0.73 dps on z: the
# turn-on shift the state's widening (restart_bias_sigma_dps, 0.02 dps) does not cover. Heading
# RMSE during movement (bench/broad_heading_error, the dataset's definition) with no state and
# with the other trial's, and the share of moving samples within auto's own 2 sigma. Then each
# trial with the state its own recording left when averaged over 4 and 8 samples (the level the
# same, the per-sample noise a half and a third: a state saved at another rate or bandwidth).
# Usage: bench/broad_foreign_state.sh [HEADINGD]  (default: this checkout's build)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
headingd="${1:-$bin/app/headingd}"
data="$HEADINGD_ROOT/../shared/data"
out="$HEADINGD_ROOT/build/bench/broad-foreign-state"
mkdir -p "$out"
printf '[state]\nrestore_heading = false\n' >"$out/no-heading.toml"
trials=(broad-01 broad-05 broad-08 broad-24 broad-26)
bias_z() { sed -n 's/^bias_dps=[^ ]* [^ ]* \([^ ]*\)$/\1/p' "$1"; }
for trial in "${trials[@]}"; do
  rm -f "$out/$trial.state"
  "$headingd" run --recording "$data/$trial/imu.csv" --speed max --no-dds --state "$out/$trial.state" \
    --output-rate 0 -o "$out/$trial-none.csv" 2>/dev/null
done
printf '%-10s %-10s %8s | %9s %9s   (heading RMSE while moving, deg) | %s\n' trial "state of" "dz dps" "no state" \
  "its state" "moving within 2 sigma"
for trial in "${trials[@]}"; do
  own=$(bias_z "$out/$trial.state")
  for from in "${trials[@]}"; do
    [ "$from" = "$trial" ] && continue
    cp "$out/$from.state" "$out/copy.state"
    "$headingd" run --config "$out/no-heading.toml" --recording "$data/$trial/imu.csv" --speed max --no-dds \
      --state "$out/copy.state" --output-rate 0 -o "$out/$trial-from-$from.csv" 2>/dev/null
    "$bin/bench/broad_heading_error" "$data/$trial/truth.csv" "$data/$trial/imu.csv" "none=$out/$trial-none.csv" \
      "foreign=$out/$trial-from-$from.csv" >"$out/score.txt"
    awk -v trial="$trial" -v from="$from" -v dz="$(awk -v a="$(bias_z "$out/$from.state")" -v b="$own" \
      'BEGIN { printf "%+.3f", a - b }')" '
      /headingd none/ { none = $3 }
      /headingd foreign/ { foreign = $3; within = $9 }
      END { printf "%-10s %-10s %8s | %9s %9s | %s %%\n", trial, from, dz, none, foreign, within }' "$out/score.txt"
  done
done
printf '\n%-10s %-16s | %9s %9s   (heading RMSE while moving, deg) | %s | %s\n' trial "state saved at" \
  "no state" "its state" "moving within 2 sigma" "segments accepted as still"
for trial in "${trials[@]}"; do
  for k in 4 8; do
    awk -F, -v k="$k" 'BEGIN { OFS = "," } NR == 1 { print; next }
      { n++; if (n % k == 1) t = $1; for (i = 2; i <= NF; i++) s[i] += $i
        if (n % k == 0) { line = t; for (i = 2; i <= NF; i++) { line = line "," s[i] / k; s[i] = 0 }; print line } }' \
      "$data/$trial/imu.csv" >"$out/slow.csv"
    rm -f "$out/slow.state"
    "$headingd" run --recording "$out/slow.csv" --speed max --no-dds --state "$out/slow.state" -o /dev/null 2>/dev/null
    "$headingd" run --config "$out/no-heading.toml" --recording "$data/$trial/imu.csv" --speed max --no-dds \
      --state "$out/slow.state" --output-rate 0 -o "$out/$trial-slow-$k.csv" 2>"$out/summary.txt"
    still=$(sed -n 's/.*segments up to [0-9.]* s: \([0-9]*\) accepted as still.*/\1/p' "$out/summary.txt")
    "$bin/bench/broad_heading_error" "$data/$trial/truth.csv" "$data/$trial/imu.csv" "none=$out/$trial-none.csv" \
      "slow=$out/$trial-slow-$k.csv" >"$out/score.txt"
    awk -v trial="$trial" -v at="1/$k of the rate" -v still="$still" '
      /headingd none/ { none = $3 }
      /headingd slow/ { slow = $3; within = $9 }
      END { printf "%-10s %-16s | %9s %9s | %s %% | %s\n", trial, at, none, slow, within, still }' "$out/score.txt"
  done
done
