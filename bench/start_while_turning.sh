#!/usr/bin/env bash
# A start-up while the platform turns, without saved state: the simulated AGV hour (seed 1) cut
# so the recording begins 40 s in, on the way into a 90 deg turn. Prints the heading error
# without and with the recovery of `auto` (recover_after_s), and the final sigma. (Since the
# start-up's blocks are judged, this start-up is seen to move and both rows are the same: no
# restart is needed.)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/../scripts/lib.sh"
build_preset default quiet
headingd="$HEADINGD_ROOT/build/default/app/headingd"
out="$HEADINGD_ROOT/build/bench/start-while-turning"
mkdir -p "$out"
"$headingd" simulate --scenario agv --seed 1 --output-dir "$out/full" 2>/dev/null
cut_at() {  # keeps comment lines and the header, then rows from t >= 40 s
  awk -F, '/^#/ || /^time_s/ { print; next } $1 >= 40.0' "$1"
}
cut_at "$out/full/imu.csv" >"$out/imu.csv"
# The truth, shifted so that it starts at heading 0 like the estimate.
cut_at "$out/full/truth.csv" | awk -F, -v OFS=, '/^#/ || /^time_s/ { print; next } !h0_set { h0 = $2; h0_set = 1 } { $2 = $2 - h0; print }' >"$out/truth.csv"
for after in 0 90; do
  printf '[estimator.auto]\nrecover_after_s = %s\n' "$after" >"$out/cfg-$after.toml"
  "$headingd" replay "$out/imu.csv" --no-dds -c "$out/cfg-$after.toml" -o "$out/est-$after.csv" -q
  sigma=$(tail -n 1 "$out/est-$after.csv" | cut -d, -f10)
  label="recover_after_s=$after"
  [ "$after" = 0 ] && label="no recovery"
  header=()
  [ "$after" = 0 ] && header=(--header)
  "$headingd" score "$out/est-$after.csv" "$out/truth.csv" --label "$label" "${header[@]}"
  echo "  final heading sigma: $sigma deg"
done
