#!/usr/bin/env bash
# The randomized sweep of issue 12: `auto`, `auto` without its temperature model, the paper's C and
# a Fusion-style tracker on 200 random worlds (2 h each), scored as excess error over the floor.
# Usage: bench/sweep.sh [--chip-temperature] [SEEDS] [HOURS] [FIRST_SEED] [SKIP_SAMPLES] [RECOVER_AFTER_S]
# (about 90 s for 200 seeds of 2 h on 2 cores; FIRST_SEED 201 gives the seeds held out from the
# choices made on 1-200; SKIP_SAMPLES: bench/sweep_phase.sh; RECOVER_AFTER_S: bench/sweep_wait.sh;
# --chip-temperature: the estimators read the temperature as the L3GD20H reports it, whole
# degrees refreshed at 1 Hz, where the random worlds otherwise hand them the exact one)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
chip=()
if [ "${1:-}" = --chip-temperature ]; then
  chip=(--chip-temperature)
  shift
fi
"$HEADINGD_ROOT/build/default/bench/sweep" "${chip[@]}" "${1:-200}" "${2:-2}" "${3:-1}" "${4:-0}" ${5:+"$5"}
