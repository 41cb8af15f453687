#!/usr/bin/env bash
# Real data with holes: each BROAD trial in ../shared/data with its samples removed for GAP s
# every 20 s from 10 s on (a lost FIFO, a chip set up again after bus errors, a recording's hole),
# at five placements (the first hole 10, 14, 18, 22 or 26 s in). Heading RMSE while moving
# (bench/broad_heading_error, the dataset's definition) for auto, median and range over the
# placements, beside the trial without holes, and the share of moving samples within auto's 2
# sigma (median, lowest). With BASELINE_REV, the same for auto as built at that revision (built
# once in build/baseline-REV, as bench/auto_report_before_after.sh does).
# Usage: bench/broad_gaps.sh [BASELINE_REV|-] [GAP_S...]   (default: - 0.1 0.5 2)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
data="$HEADINGD_ROOT/../shared/data"
out="$HEADINGD_ROOT/build/bench/broad-gaps"
mkdir -p "$out"
gap_bench_args broad_gaps "0.1 0.5 2" "$@"

# RMSE and the share within 2 sigma of one estimate file ("rmse share").
score() {
  "$bin/bench/broad_heading_error" "$1" "$2" "auto=$3" |
    awk '/headingd auto/ { share = $9; print $3, share }'
}
# Median, lowest and highest of the numbers on standard input ("median low high").
spread() {
  sort -g | awk '{ v[NR] = $1 } END { m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2;
    printf "%.2f %.2f %.2f", m, v[1], v[NR] }'
}

printf '%-9s %6s | %8s |' trial "gap s" "no holes"
for b in "${binaries[@]}"; do printf ' %-6s RMSE median (range)   2 sigma median (lowest) |' "${b%%=*}"; done
printf '\n'
for trial in broad-01 broad-05 broad-08 broad-24 broad-26; do
  "$bin/app/headingd" replay --no-dds "$data/$trial/imu.csv" --output-rate 0 --output "$out/$trial-whole.csv" --quiet
  whole=$(score "$data/$trial/truth.csv" "$data/$trial/imu.csv" "$out/$trial-whole.csv" | cut -d' ' -f1)
  for g in "${gaps[@]}"; do
    printf '%-9s %6s | %8s |' "$trial" "$g" "$whole"
    for b in "${binaries[@]}"; do
      name="${b%%=*}" daemon="${b#*=}"
      : >"$out/scores"
      for first in 10 14 18 22 26; do
        holed="$out/$trial-$g-$first.csv"
        awk -F, -v g="$g" -v f="$first" 'NR == 1 || /^#/ { print; next }
          { t = $1 / 1e9 - f; if (t >= 0 && t - 20 * int(t / 20) < g) next; print }' \
          "$data/$trial/imu.csv" >"$holed"
        "$daemon" replay --no-dds "$holed" --output-rate 0 --output "$out/est-$name.csv" --quiet 2>/dev/null
        score "$data/$trial/truth.csv" "$data/$trial/imu.csv" "$out/est-$name.csv" >>"$out/scores"
      done
      rmse=$(cut -d' ' -f1 "$out/scores" | spread)
      share=$(cut -d' ' -f2 "$out/scores" | spread)
      read -r rm rl rh <<<"$rmse"
      read -r sm sl _ <<<"$share"
      printf ' %-6s %7s (%s-%s)   %5s %% (%s %%) |' "$name" "$rm" "$rl" "$rh" "$sm" "$sl"
    done
    printf '\n'
  done
done
