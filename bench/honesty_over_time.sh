#!/usr/bin/env bash
# Where in a run the heading sigma is too narrow or too wide: the sweep's worlds scored per quarter
# of the run, at 2 k sigma for k from 0.5 to 1.5 (issue 12, must-show 4; see honesty_over_time.cpp).
# Usage: bench/honesty_over_time.sh [SEEDS] [HOURS] [FIRST_SEED]  (about a minute for 200 seeds of 2 h)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/honesty_over_time" "${1:-200}" "${2:-2}" "${3:-1}"
