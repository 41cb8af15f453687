#!/usr/bin/env bash
# Method auto against the paper's C on every simulator scenario, seeds 1 2 3 (about 3 min):
# heading error, stillness classification on slow rotation, honesty of sigma, 4 h hold.
# Arguments pass through to the program, e.g. --seeds 1,2 --scenarios creep,still
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/auto_report" "$@"
