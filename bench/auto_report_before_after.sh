#!/usr/bin/env bash
# Issue 12's must-show 6 as a measurement: every `bench/auto_report.sh` run (scenario x seed) replayed
# by `auto` as built here and as built at a baseline revision (default 38df02f, the last commit
# before issue 12's changes), each from its recording started 0, 1, ... PHASES-1 samples late: where
# the 3 s segment grid falls is chance, so one figure's change means something only beyond the
# spread those starts give. Prints, per run, the range over the starts of the max, final and RMS
# heading error (deg) before and after, and per figure whether after is worse or better than before
# on every start ("worse"/"better"), or the two ranges overlap ("same").
# Usage: bench/auto_report_before_after.sh [PHASES (4)] [BASELINE_REV (38df02f)]
#        [SCENARIOS (paper12h,creep,thermal,still,agv)] [SEEDS (1,2,3)]
# About 15 min for the defaults, plus one build of the baseline's daemon (kept in build/baseline-REV).
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet

phases="${1:-4}"
rev="${2:-38df02f}"
scenarios="${3:-paper12h,creep,thermal,still,agv}"
seeds="${4:-1,2,3}"
usage() {
  echo "auto_report_before_after: $1" >&2
  echo "usage: bench/auto_report_before_after.sh [PHASES] [BASELINE_REV] [SCENARIOS a,b] [SEEDS 1,2]" >&2
  exit 64
}
[[ "$phases" =~ ^[1-9][0-9]*$ ]] || usage "PHASES must be a positive whole number, not '$phases'"
[[ "$scenarios" =~ ^[a-z0-9-]+(,[a-z0-9-]+)*$ ]] || usage "SCENARIOS must be names separated by commas"
[[ "$seeds" =~ ^[0-9]+(,[0-9]+)*$ ]] || usage "SEEDS must be numbers separated by commas"
[[ "$rev" =~ ^[0-9A-Za-z_][0-9A-Za-z._/-]*$ ]] || usage "BASELINE_REV must be a commit or tag name, not '$rev'"
sha="$(git -C "$HEADINGD_ROOT" rev-parse --verify --quiet "$rev^{commit}")" ||
  usage "no commit '$rev' in this clone"

before="$(baseline_daemon "$sha")"
after="$HEADINGD_ROOT/build/default/app/headingd"

work="$(mktemp -d)"
writer=""  # the background job feeding a replay through a FIFO: not left blocked if the replay fails
trap '[ -z "$writer" ] || kill "$writer" 2>/dev/null; rm -rf "$work"' EXIT
results="$work/results.txt"
: >"$results"
IFS=, read -r -a scenario_list <<<"$scenarios"
IFS=, read -r -a seed_list <<<"$seeds"
for scenario in "${scenario_list[@]}"; do
  for seed in "${seed_list[@]}"; do
    run="$work/run"
    rm -rf "$run"
    mkdir -p "$run"
    if ! "$after" simulate --scenario "$scenario" --seed "$seed" --output-dir "$run" >/dev/null 2>"$run/simulate.log"; then
      cat "$run/simulate.log" >&2
      exit 1
    fi
    for ((k = 0; k < phases; ++k)); do
      for version in before after; do
        binary="$before"
        [ "$version" = after ] && binary="$after"
        # The recording less its first k samples, streamed through a pipe (paper12h is over 1 GB).
        mkfifo "$run/late.csv"
        awk -v k="$k" '/^#/ || /^time_s/ { print; next } { if (n++ >= k) print }' "$run/imu.csv" >"$run/late.csv" &
        writer=$!
        "$binary" replay --quiet --no-dds "$run/late.csv" -o "$run/estimates.csv"
        wait "$writer"
        writer=""
        rm -f "$run/late.csv"
        # score prints: label max final RMS drift hours
        "$after" score --label x "$run/estimates.csv" "$run/truth.csv" | awk -v s="$scenario" -v d="$seed" \
          -v v="$version" -v k="$k" '$1 == "x" { print s, d, v, k, $2, $3, $4 }' >>"$results"
      done
    done
    rm -rf "$run"
  done
done

echo "auto at ${sha:0:12} (before) and at $(git -C "$HEADINGD_ROOT" rev-parse --short=12 HEAD) (after), recordings started 0-$((phases - 1)) samples late"
echo "heading error, deg: the lowest-highest over the starts"
awk '
  function lo_hi(key) { return sprintf("%5.2f-%-5.2f", lo[key], hi[key]) }
  function verdict(b, a) { return lo[a] > hi[b] + 1e-9 ? "worse" : (hi[a] < lo[b] - 1e-9 ? "better" : "same") }
  {
    run = $1 " " $2
    if (!(run in seen)) { seen[run] = 1; order[++runs] = run }
    for (m = 1; m <= 3; ++m) {
      key = run SUBSEP $3 SUBSEP m
      value = $(4 + m)
      if (!(key in lo) || value < lo[key]) lo[key] = value
      if (!(key in hi) || value > hi[key]) hi[key] = value
    }
  }
  END {
    printf "%-9s %4s | %-11s %-11s %-11s | %-11s %-11s %-11s | %s\n", "scenario", "seed", "before max", "final", "RMS",
           "after max", "final", "RMS", "after vs before (max final RMS)"
    for (i = 1; i <= runs; ++i) {
      split(order[i], p, " ")
      line = sprintf("%-9s %4s |", p[1], p[2])
      for (m = 1; m <= 3; ++m) line = line " " lo_hi(order[i] SUBSEP "before" SUBSEP m)
      line = line " |"
      for (m = 1; m <= 3; ++m) line = line " " lo_hi(order[i] SUBSEP "after" SUBSEP m)
      line = line " |"
      for (m = 1; m <= 3; ++m) {
        v = verdict(order[i] SUBSEP "before" SUBSEP m, order[i] SUBSEP "after" SUBSEP m)
        line = line " " v
        count[v]++
      }
      print line
    }
    printf "figures worse on every start: %d, better on every start: %d, ranges overlapping: %d (of %d)\n",
           count["worse"], count["better"], count["same"], 3 * runs
  }' "$results"
