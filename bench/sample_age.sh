#!/usr/bin/env bash
# Sample age at a subscriber (chip sampling instant -> Orientation received) and the publisher's CPU
# share for FIFO watermarks 1..16 at 400 Hz, over Fast DDS on loopback: three 15 s runs per
# watermark, interleaved so that the machine's load drifts over all of them alike; medians
# (about 8 minutes); the CPU share after the first second. Usage: bench/sample_age.sh [ROUNDS [SECONDS]]
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
rounds="${1:-3}"
seconds="${2:-15}"
watermarks=(1 2 4 6 8 10 16)
default_watermark="$(sed -n 's/^watermark = \([0-9]*\).*/\1/p' "$HEADINGD_ROOT/config/headingd.toml" | head -1)"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "L3GD20H simulated in real time at 400 Hz (378.8 Hz), I2C at 400 kHz, Orientation at 50 Hz;" \
  "$rounds runs of $seconds s per watermark, medians; the shipped default is $default_watermark"
runs="$(mktemp)"
trap 'rm -f "$runs"' EXIT
for ((round = 1; round <= rounds; ++round)); do
  for watermark in "${watermarks[@]}"; do
    "$HEADINGD_ROOT/build/default/bench/sample_age" "$watermark" "$HEADINGD_ROOT/config/fastdds-loopback.xml" \
      "$seconds" >>"$runs"
  done
done
# field VALUE of every run of one watermark, sorted; the median of an odd count is the middle one.
field() { grep "^watermark=$1 " "$runs" | tr ' ' '\n' | sed -n "s/^$2=//p" | sort -g; }
median() { field "$1" "$2" | awk '{v[NR] = $1} END {if (NR == 0) print "nan"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
for watermark in "${watermarks[@]}"; do
  mark=""
  [[ "$watermark" == "$default_watermark" ]] && mark="  <- default"
  printf "watermark %2d: %s Hz, sample age p50 %.1f ms, p99 %.1f ms (max of runs %.1f ms); publisher %.2f %% of one core (runs: %s)%s\n" \
    "$watermark" "$(median "$watermark" rate_hz)" "$(median "$watermark" age_p50_ms)" \
    "$(median "$watermark" age_p99_ms)" "$(field "$watermark" age_max_ms | tail -1)" \
    "$(median "$watermark" cpu_pct)" "$(field "$watermark" cpu_pct | xargs printf '%.2f ' | sed 's/ $//')" "$mark"
done
