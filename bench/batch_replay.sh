#!/usr/bin/env bash
# Many recordings at once: 20 simulated agv recordings (15 min each at 400 Hz) replayed as one
# directory with --jobs 1 and --jobs 2, wall time median of 3 each, in one run.
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
bin="$HEADINGD_ROOT/build/default/app/headingd"
fleet="$HEADINGD_ROOT/build/bench/fleet20"
if [ ! -f "$fleet/vehicle20.csv" ]; then
  mkdir -p "$fleet"
  for i in $(seq 1 20); do
    "$bin" simulate --scenario agv --seed "$i" --hours 0.25 --output-dir "$fleet/sim$i" >/dev/null 2>&1
    mv "$fleet/sim$i/imu.csv" "$fleet/vehicle$i.csv" && rm -rf "$fleet/sim$i"
  done
fi
wall() {  # jobs -> median wall seconds of 3
  local times=()
  for _ in 1 2 3; do
    local start end
    start=$(date +%s.%N)
    "$bin" replay "$fleet" --jobs "$1" --output-dir "$fleet/out" >"$fleet/table-$1.txt" || {
      echo "replay failed: $(cat "$fleet/table-$1.txt")" >&2
      exit 1
    }
    end=$(date +%s.%N)
    times+=("$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')")
  done
  printf '%s\n' "${times[@]}" | sort -n | sed -n 2p
}
one=$(wall 1)
two=$(wall 2)
awk -v a="$one" -v b="$two" -v n="$(nproc)" 'BEGIN {
  printf "20 recordings, 5 h of 400 Hz data (7.2 million samples): --jobs 1 %.2f s, --jobs 2 %.2f s (%.2fx of one by one; %d cores)\n", a, b, b / a, n }'
