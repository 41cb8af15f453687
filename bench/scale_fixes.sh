#!/usr/bin/env bash
# Heading fixes in the random worlds of issue 12: the z scale error `auto` learns from them
# against each world's own, and the heading error just before a fix with and without learning.
# Usage: bench/scale_fixes.sh [SEEDS] [HOURS] [FIX_EVERY_S] [FIRST_SEED]  (about 3 minutes for 200 seeds on
# 2 cores; FIRST_SEED 201 gives the held-out seeds)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/scale_fixes" "${1:-200}" "${2:-2}" "${3:-600}" "${4:-1}"
