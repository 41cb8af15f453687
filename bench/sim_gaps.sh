#!/usr/bin/env bash
# Simulated recordings with holes: `headingd simulate` (scenarios still, paper12h and agv, seed 1,
# 2 h each) with GAP s of samples removed every 180 s from 17 s on. For each hole, the heading's
# change across it (the sample after it against the one before) less the truth's: RMS, mean and
# largest over the holes; beside them `headingd score`'s max, final and RMS heading error of the
# whole run. With BASELINE_REV, the same for auto as built at that revision (bench/broad_gaps.sh
# says how; the real-data side of the same question).
# Usage: bench/sim_gaps.sh [BASELINE_REV|-] [GAP_S...]   (default: - 0.15 0.5 2)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
out="$HEADINGD_ROOT/build/bench/sim-gaps"
mkdir -p "$out"
gap_bench_args sim_gaps "0.15 0.5 2" "$@"

# Per hole: the estimate's heading change across it less the truth's, from the last 0.1 s instant
# before it to the first after it (the truth's grid). "holes RMS mean largest".
across_holes() {
  awk -F, 'FNR == 1 { file++ } /^#/ || /^time/ { next }
    file == 1 { truth[sprintf("%.1f", $1)] = $2; next }
    { on_grid = ($1 * 10 - int($1 * 10 + 0.5)) ^ 2 < 1e-8
      if (seen && $1 - t > 0.05) pending = 1
      if (on_grid) {
        k = sprintf("%.1f", $1)
        if (pending && (k in truth) && (g in truth)) {
          d = ($2 - gh) - (truth[k] - truth[g]); n++; s += d; ss += d * d; if (d * d > m * m) m = d < 0 ? -d : d
        }
        pending = 0; g = k; gh = $2
      }
      seen = 1; t = $1 }
    END { if (n == 0) { print "0 - - -"; exit } printf "%d %.3f %+.4f %.3f", n, sqrt(ss / n), s / n, m }' "$1" "$2"
}

printf '%-9s %5s |' scenario "gap s"
for b in "${binaries[@]}"; do printf ' %-6s holes  RMS    mean     largest | max   final  RMS (deg) |' "${b%%=*}"; done
printf '\n'
for scenario in still paper12h agv; do
  world="$out/$scenario"
  [ -s "$world/imu.csv" ] || "$bin/app/headingd" simulate --scenario "$scenario" --seed 1 --hours 2 --output-dir "$world" >/dev/null
  for g in "${gaps[@]}"; do
    awk -F, -v g="$g" '/^#/ || /^time/ { print; next } { t = $1 - 17; if (t >= 0 && t - 180 * int(t / 180) < g) next; print }' \
      "$world/imu.csv" >"$out/holed.csv"
    printf '%-9s %5s |' "$scenario" "$g"
    for b in "${binaries[@]}"; do
      name="${b%%=*}" daemon="${b#*=}"
      "$daemon" replay --no-dds "$out/holed.csv" --output-rate 0 --output "$out/est.csv" --quiet 2>/dev/null
      read -r n rms mean largest <<<"$(across_holes "$world/truth.csv" "$out/est.csv")"
      read -r _ max final whole _ <<<"$("$bin/app/headingd" score "$out/est.csv" "$world/truth.csv" --label "$name" | tail -n 1)"
      printf ' %-6s %5s %6s %8s %7s | %5s %5s %5s       |' "$name" "$n" "$rms" "$mean" "$largest" "$max" "$final" "$whole"
    done
    printf '\n'
  done
done
