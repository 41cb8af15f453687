#!/usr/bin/env bash
# The paper's 12-hour experiment on the simulator: simulate paper12h, replay it with the
# paper's methods A, B and C and with headingd's auto, print max |E|, final |E|, RMS and drift side by side (per seed),
# and draw heading error against time like the paper's Fig. 7.
# Usage: bench/accuracy_report.sh [SEED...]   (default seeds: 1 2 3)
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}" gnuplot-nox
build_preset default quiet
headingd="$HEADINGD_ROOT/build/default/app/headingd"
out="$HEADINGD_ROOT/build/bench"
mkdir -p "$out"
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3)
methods=(a b c auto)

first=1
for seed in "${seeds[@]}"; do
  dir="$out/paper12h-s$seed"
  "$headingd" simulate --scenario paper12h --seed "$seed" --output-dir "$dir" 2>/dev/null
  for method in "${methods[@]}"; do
    "$headingd" replay --no-dds "$dir/imu.csv" --method "$method" --output "$dir/est-$method.csv" --quiet
    header=()
    [ "$first" -eq 1 ] && header=(--header) && first=0
    "$headingd" score "$dir/est-$method.csv" "$dir/truth.csv" --label "$method seed $seed" \
      --errors "$dir/error-$method.csv" "${header[@]}"
  done
done
echo "(paper, real L3GD20H: A ~40 deg/h; B ~5 deg/h; C < 1 deg/h on average, max |E| < 8 deg)"

plot="$out/paper12h-error.png"
dir="$out/paper12h-s${seeds[0]}"
gnuplot <<GNUPLOT
set terminal pngcairo size 900,560 font ",10"
set output "$plot"
set title "paper12h, seed ${seeds[0]}: heading error E = truth - estimate (cf. the paper's Fig. 7)"
set xlabel "time [h]"
set ylabel "E [deg]"
set grid
set key top left
set datafile separator ","
set yrange [-30:30]
plot "$dir/error-a.csv" every ::1 using 1:2 with lines lw 1.5 title "A: start-up bias (clipped at 30 deg)", \
     "$dir/error-b.csv" every ::1 using 1:2 with lines lw 1.5 title "B: range criterion", \
     "$dir/error-c.csv" every ::1 using 1:2 with lines lw 1.5 title "C: range + mean criteria", \
     "$dir/error-auto.csv" every ::1 using 1:2 with lines lw 2 title "auto: headingd's estimator"
GNUPLOT
echo "plot: $plot"
