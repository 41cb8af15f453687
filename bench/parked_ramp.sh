#!/usr/bin/env bash
# Issue 12's parked hour: `headingd simulate --scenario parked-ramp` (parked 1 h, the temperature
# ramping 10 C/h through 0.005 dps/C on every axis) replayed on seeds 1..N (default 8): the share
# of still segments accepted and the heading at the end (the truth stays at 0).
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
headingd="$HEADINGD_ROOT/build/default/app/headingd"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for seed in $(seq 1 "${1:-8}"); do
  "$headingd" simulate --scenario parked-ramp --seed "$seed" --output-dir "$work/s" 2>/dev/null
  "$headingd" replay --no-dds "$work/s/imu.csv" -o "$work/est.csv" 2>"$work/summary.txt"
  awk -v seed="$seed" '
    /accepted as still/ { accepted = $8; rejected = $12 }
    / heading / { heading = $2 }
    END { printf "seed %d: %d of %d still segments accepted (%.2f %%), heading at the end %s deg (truth 0)\n",
                 seed, accepted, accepted + rejected, 100 * accepted / (accepted + rejected), heading }' "$work/summary.txt"
done
