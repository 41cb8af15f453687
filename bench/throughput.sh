#!/usr/bin/env bash
# Replay throughput on the 12-hour 400 Hz paper12h file (about 17 million samples), and the
# core alone. Prints the figures the README quotes.
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default"
data="$HEADINGD_ROOT/build/bench/paper12h-s1"
[ -f "$data/imu.csv" ] || "$bin/app/headingd" simulate --scenario paper12h --seed 1 --output-dir "$data"
echo "file: $(grep -vc '^#' "$data/imu.csv") lines, $(du -h "$data/imu.csv" | cut -f1)"
"$bin/bench/replay_throughput" "$data/imu.csv"
