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
# The floor (map the file, parse every field, nothing else) against `headingd replay` (estimates
# at 10 Hz to a file), in pairs one after the other so that the shared machine's drift hits
# both alike; the median of the pairs' ratios.
cat "$data/imu.csv" >/dev/null  # in the page cache for both
ratios=()
for _ in 1 2 3 4 5; do
  baseline_s=$("$bin/bench/parse_baseline" "$data/imu.csv" 1 | sed -n 's/.*: \([0-9.]*\) s for.*/\1/p')
  start=$(date +%s.%N)
  "$bin/app/headingd" replay --no-dds --quiet "$data/imu.csv" -o "$data/pair.est"
  end=$(date +%s.%N)
  ratios+=("$(awk -v a="$start" -v b="$end" -v base="$baseline_s" 'BEGIN { printf "%.3f %.2f %.2f", (b - a) / base, b - a, base }')")
done
printf '%s\n' "${ratios[@]}" | sort -n | awk '{ r[NR] = $1; line[NR] = $0 } END {
  m = int((NR + 1) / 2); split(line[m], f, " ")
  printf "replay / baseline parse, median of %d pairs: %.2f (that pair: replay %.2f s, baseline %.2f s; all ratios", NR, f[1], f[2], f[3]
  for (i = 1; i <= NR; i++) printf " %.2f", r[i]; print ")" }'

# The same recording compressed (zstd -3 and gzip -6, by the reference programs): byte-identical
# estimates, and the replay time beside the plain file's (median of 3 each, one run).
[ -f "$data/imu.csv.zst" ] || zstd -q -3 -T0 "$data/imu.csv" -o "$data/imu.csv.zst"
[ -f "$data/imu.csv.gz" ] || gzip -c "$data/imu.csv" >"$data/imu.csv.gz"
echo "compressed: $(du -h "$data/imu.csv.zst" | cut -f1) as .zst, $(du -h "$data/imu.csv.gz" | cut -f1) as .gz"
replay_seconds() {  # file output -> median wall seconds of 3 replays
  local times=()
  for _ in 1 2 3; do
    local start end
    start=$(date +%s.%N)
    "$bin/app/headingd" replay --no-dds --quiet "$1" -o "$2"
    end=$(date +%s.%N)
    times+=("$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')")
  done
  printf '%s\n' "${times[@]}" | sort -n | sed -n 2p
}
plain_s=$(replay_seconds "$data/imu.csv" "$data/plain.est")
zst_s=$(replay_seconds "$data/imu.csv.zst" "$data/zst.est")
gz_s=$(replay_seconds "$data/imu.csv.gz" "$data/gz.est")
cmp -s "$data/plain.est" "$data/zst.est" && cmp -s "$data/plain.est" "$data/gz.est" && same=identical || same=DIFFERENT
awk -v p="$plain_s" -v z="$zst_s" -v g="$gz_s" -v same="$same" 'BEGIN {
  printf "replay of the 12 h file (median of 3): plain %.2f s, .zst %.2f s (%.2fx), .gz %.2f s (%.2fx); estimates %s\n",
    p, z, z / p, g, g / p, same }'
