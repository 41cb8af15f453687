#!/usr/bin/env bash
# Sample age at a subscriber (chip sampling instant -> Orientation received) and the publisher's CPU
# share for FIFO watermarks 1..16 at 400 Hz, over Fast DDS on loopback (about 2 minutes).
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "L3GD20H simulated in real time at 400 Hz (378.8 Hz), I2C at 400 kHz, 15 s per watermark, Orientation at 50 Hz"
for watermark in 1 2 4 6 8 16; do
  "$HEADINGD_ROOT/build/default/bench/sample_age" "$watermark" "$HEADINGD_ROOT/config/fastdds-loopback.xml"
done
