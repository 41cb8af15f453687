#!/usr/bin/env bash
# The L3GD20H datasheet gives the zero-rate level's change with temperature as +-0.04 dps/C
# typical (Table 3, OffDr); issue 12's random worlds draw at most 0.01. Worlds of our simulator
# at the datasheet's figure (`simulate --bias-per-c`): a parked hour through a warm-up (`still`),
# a parked hour ramping 10 C/h (`parked-ramp`), and an AGV hour warming up while it drives and
# stops (`agv`), each replayed by auto, auto without its temperature model, and C. Printed: the
# still segments accepted and the max |excess| over the floor (`headingd score --recording`;
# parked, that is the heading error).
# Usage: bench/datasheet_tempco.sh [HEADINGD] [SEEDS]  (HEADINGD: the binary whose estimates are
# scored, default this checkout's build; the worlds always come from this checkout's simulator, which
# has --bias-per-c; 2 seeds)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"
build_preset default quiet
simulator="$HEADINGD_ROOT/build/default/app/headingd"
headingd="${1:-$simulator}"
seeds="${2:-2}"
out="$HEADINGD_ROOT/build/bench/datasheet-tempco"
mkdir -p "$out"
printf '[estimator.temperature]\nenabled = false\n' >"$out/notemp.toml"
printf '%-12s %4s %8s | %-22s | %-22s | %-22s\n' scenario seed "dps/C" "auto: still, max deg" \
  "no model: still, max" "C: still, max deg"
for scenario in still parked-ramp agv; do
  for seed in $(seq 1 "$seeds"); do
    for per_c in 0.005 0.01 0.02 0.03 0.04 -0.04; do
      "$simulator" simulate --scenario "$scenario" --seed "$seed" --hours 1 --bias-per-c "$per_c" \
        --output-dir "$out/world" 2>/dev/null
      row=$(printf '%-12s %4s %8s' "$scenario" "$seed" "$per_c")
      for method in auto notemp c; do
        case "$method" in
          auto) options=() ;;
          notemp) options=(--config "$out/notemp.toml") ;;
          c) options=(--method c) ;;
        esac
        "$headingd" replay --no-dds "$out/world/imu.csv" "${options[@]}" -o "$out/est.csv" 2>"$out/summary.txt"
        still=$(awk '/accepted as still/ { printf "%d/%d", $8, $8 + $12 }' "$out/summary.txt")
        excess=$("$simulator" score "$out/est.csv" "$out/world/truth.csv" --recording "$out/world/imu.csv" \
          --label est | awk '$1 == "est" && $2 == "excess" { print $3 }')
        row+=$(printf ' | %11s %10s' "$still" "$excess")
      done
      echo "$row"
    done
  done
done
