#!/usr/bin/env bash
# How much of the randomized sweep is where the 3 s segment grid happens to fall: the same worlds
# (bench/sweep.sh), the estimators started 0, 1, 2, ... samples into each. Prints each run's
# summary figures, the seeds whose `auto` max changes by more than 1.5x between runs (decisions on
# a knife edge), how many seeds count as a loss to C in some runs and not in others, the seeds a
# loss to C and those where the temperature model costs more than 0.05 deg in every run, and how many
# seeds each estimator is worse than itself by more than 0.05 deg: the noise under any
# comparison of two sweeps.
# Usage: bench/sweep_phase.sh [PHASES (4)] [SEEDS (200)] [HOURS (2)] [FIRST_SEED (1)]  (PHASES x ~100 s)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
phases="${1:-4}"
[[ "$phases" =~ ^[1-9][0-9]*$ ]] || {
  echo "sweep_phase: PHASES must be a positive whole number, not '$phases'" >&2
  exit 64
}
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
runs=()
for ((k = 0; k < phases; ++k)); do
  "$HEADINGD_ROOT/build/default/bench/sweep" "${2:-200}" "${3:-2}" "${4:-1}" "$k" >"$dir/$k.txt"
  runs+=("$dir/$k.txt")
done

echo "per run (estimators started SKIP samples into each world):"
printf '%5s %9s %9s %7s %13s %7s\n' skip median p90 losses "model worse" honest
for ((k = 0; k < phases; ++k)); do
  awk -v k="$k" '
    /^auto / && !m { median = $2; p90 = $3; m = 1 }
    /^auto worse than C/ { losses = $6 }
    /^temperature model on vs off/ { for (i = 1; i <= NF; ++i) if ($i == "on" && $(i + 1) ~ /^[0-9]+$/) worse = $(i + 1) }
    /^sigma honesty/ { honest = $3 }
    END { printf "%5d %9s %9s %7s %13s %7s\n", k, median, p90, losses, worse, honest }' "$dir/$k.txt"
done

# Per seed: auto's max, auto-notemp's and C's in every run. Then each estimator against itself
# started 0 samples in: how many seeds a start one or more samples later makes "worse by more
# than 0.05 deg", the margin issue 12 sets between the temperature model on and off; a comparison
# of two sweeps counts that many seeds worse from the phase alone.
awk -F'|' '
  FNR == 1 { ++run }
  NF == 4 { split($1, a, " "); if (a[1] !~ /^[0-9]+$/) next
    split($2, b, " "); split($3, c, " "); s = a[1]
    auto[s, run] = b[1]; notemp[s, run] = c[1]; cmax[s, run] = c[2]; seeds[s] = 1 }
  END {
    edge = ""; flips = ""; n_edge = 0; n_flips = 0; always_lost = ""; n_always_lost = 0; always_worse = ""; n_always_worse = 0
    for (s in seeds) {
      lo = 1e300; hi = 0; lost = 0; worse = 0
      for (r = 1; r <= run; ++r) {
        v = auto[s, r] + 0; if (v < lo) lo = v; if (v > hi) hi = v
        lost += (auto[s, r] + 0 > cmax[s, r] + 0)
        worse += (auto[s, r] + 0 > notemp[s, r] + 0.05)
      }
      if (hi > 1.5 * (lo > 0.5 ? lo : 0.5)) { edge = edge sprintf(" %s (%.1f-%.1f)", s, lo, hi); ++n_edge }
      if (lost > 0 && lost < run) { flips = flips " " s; ++n_flips }
      if (lost == run) { always_lost = always_lost " " s; ++n_always_lost }
      if (worse == run) { always_worse = always_worse " " s; ++n_always_worse }
    }
    printf "\nseeds whose auto max changes by more than 1.5x between runs: %d%s\n", n_edge, n_edge ? ":" edge : ""
    printf "seeds a loss to C in some runs and not in others: %d%s\n", n_flips, n_flips ? ":" flips : ""
    printf "seeds a loss to C in every run: %d%s\n", n_always_lost, n_always_lost ? ":" always_lost : ""
    printf "seeds where the model on is worse than off by more than 0.05 deg in every run: %d%s\n", n_always_worse,
           n_always_worse ? ":" always_worse : ""
    print "\nseeds worse by more than 0.05 deg than the same estimator started 0 samples in:"
    for (r = 2; r <= run; ++r) {
      w = 0; n = 0
      for (s in seeds) { w += (auto[s, r] > auto[s, 1] + 0.05); n += (notemp[s, r] > notemp[s, 1] + 0.05) }
      printf "  skip %d: auto %d, auto-notemp %d\n", r - 1, w, n
    }
  }' "${runs[@]}"
