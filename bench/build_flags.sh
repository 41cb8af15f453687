#!/usr/bin/env bash
# What the default preset's hardening flags (-D_FORTIFY_SOURCE=2 -fstack-protector-strong,
# -z relro -z now) cost: the same sources built without them (once, in build/plain-flags), and
# both daemons timed in pairs, one right after the other, so that the shared machine's drift hits
# both alike. Prints the median of the pairs' ratios for a 2 h replay and for a start-up
# (`headingd --version`, where binding every symbol at load shows).
# Usage: bash bench/build_flags.sh [PAIRS]
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
pairs="${1:-7}"
hardened="$HEADINGD_ROOT/build/default/app/headingd"
plain_dir="$HEADINGD_ROOT/build/plain-flags"
plain="$plain_dir/app/headingd"
if [ ! -x "$plain" ] || [ "$plain" -ot "$hardened" ]; then
  echo "building headingd without the hardening flags in $plain_dir (log in $plain_dir.log)" >&2
  { cmake -S "$HEADINGD_ROOT" -B "$plain_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHEADINGD_WERROR=ON \
      -DHEADINGD_BUILD_TESTS=OFF -DHEADINGD_BUILD_BENCH=OFF -DCMAKE_C_FLAGS= -DCMAKE_CXX_FLAGS= \
      -DCMAKE_EXE_LINKER_FLAGS= && cmake --build "$plain_dir" --target headingd; } >"$plain_dir.log" 2>&1
fi
readelf -d "$plain" | grep -q BIND_NOW && { echo "$plain has BIND_NOW: not a plain build" >&2; exit 1; }
data="$HEADINGD_ROOT/build/bench/agv-2h"
[ -f "$data/imu.csv" ] || "$hardened" simulate --scenario agv --seed 1 --hours 2 --output-dir "$data" >/dev/null
cat "$data/imu.csv" >/dev/null  # in the page cache for both

seconds() { # command...: wall seconds of one run
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }'
}
startup() { # binary: wall seconds of 20 starts
  local start end
  start=$(date +%s.%N)
  for _ in $(seq 20); do "$1" --version >/dev/null; done
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }'
}
report() { # what: lines of "ratio hardened plain", printed as a median and all ratios
  sort -n | awk -v what="$1" '{ r[NR] = $1; line[NR] = $0 } END {
    m = int((NR + 1) / 2); split(line[m], f, " ")
    printf "%s, hardened / plain, median of %d pairs: %.3f (that pair: %.3f s vs %.3f s; all ratios", what, NR, f[1], f[2], f[3]
    for (i = 1; i <= NR; i++) printf " %.3f", r[i]; print ")" }'
}
echo "machine: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores"
for _ in $(seq "$pairs"); do
  h=$(seconds "$hardened" replay --no-dds --quiet "$data/imu.csv" -o "$data/h.est")
  p=$(seconds "$plain" replay --no-dds --quiet "$data/imu.csv" -o "$data/p.est")
  awk -v h="$h" -v p="$p" 'BEGIN { printf "%.4f %.4f %.4f\n", h / p, h, p }'
done | report "replay of a 2 h agv recording ($(grep -vc '^#' "$data/imu.csv") lines)"
cmp -s "$data/h.est" "$data/p.est" && echo "estimates of both builds identical, byte for byte" ||
  echo "estimates differ between the builds"
for _ in $(seq "$pairs"); do
  h=$(startup "$hardened")
  p=$(startup "$plain")
  awk -v h="$h" -v p="$p" 'BEGIN { printf "%.4f %.4f %.4f\n", h / p, h, p }'
done | report "20 start-ups (headingd --version)"
