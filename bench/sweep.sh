#!/usr/bin/env bash
# The randomized sweep of issue 12: `auto`, `auto` without its temperature model, the paper's C and
# a Fusion-style tracker on 200 random worlds (2 h each), scored as excess error over the floor.
# Usage: bench/sweep.sh [SEEDS] [HOURS] [FIRST_SEED] [SKIP_SAMPLES] [RECOVER_AFTER_S]  (about 90 s for
# 200 seeds of 2 h on 2 cores; FIRST_SEED 201 gives the seeds held out from the choices made on
# 1-200; SKIP_SAMPLES: bench/sweep_phase.sh; RECOVER_AFTER_S: bench/sweep_wait.sh)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/sweep" "${1:-200}" "${2:-2}" "${3:-1}" "${4:-0}" ${5:+"$5"}
