#!/usr/bin/env bash
# CPU time per wake-up and per sample of the L3GD20H driver (against the simulated chip), the IIO
# source (against a fake IIO tree fed through a FIFO), and the estimator at 400 Hz, as fast as
# they go and at the chip's real pace (3 minutes). Prints the figures the README quotes.
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/driver_bench"
