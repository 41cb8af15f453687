#!/usr/bin/env bash
# What per-run sigma honesty any estimator can reach: worlds drawn from the angle/bias filter's own
# model, where its sigma is right by construction (issue 12, must-show 4; see honesty_limit.cpp).
# Usage: bench/honesty_limit.sh [RUNS] [HOURS] [FIRST_SEED]  (well under a minute for 200 runs)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/honesty_limit" "${1:-200}" "${2:-2}" "${3:-1}"
