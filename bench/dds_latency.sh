#!/usr/bin/env bash
# DDS sample-to-subscriber latency (p50/p99) at 400 Hz on loopback, and the publisher's CPU share.
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
"$HEADINGD_ROOT/build/default/bench/dds_latency" "$HEADINGD_ROOT/config/fastdds-loopback.xml"
