#!/usr/bin/env bash
# `headingd replay` on the shared real recording (or the bundled excerpt when the shared
# folder is absent) writes exactly the contract header and sane rows.
set -euo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
input="$root/../shared/data/broad-05/imu.csv"
[ -f "$input" ] || input="$root/tests/data/broad-05-excerpt/imu.csv"

"$headingd" replay --no-dds "$input" --method c --output "$dir/est.csv"
want='time_s,heading_deg,qw,qx,qy,qz,bias_x_dps,bias_y_dps,bias_z_dps,heading_sigma_deg,still'
got="$(head -n 1 "$dir/est.csv")"
[ "$got" = "$want" ] || { echo "header is '$got'"; exit 1; }
rows=$(($(wc -l <"$dir/est.csv") - 1))
echo "rows: $rows"
[ "$rows" -gt 300 ] || { echo "too few rows"; exit 1; }
# 10 Hz by default: consecutive rows 0.1 s apart to within one sample period (3.5 ms for
# the real recording); the still column is 0 or 1.
awk -F, 'NR > 2 { dt = $1 - prev; if (dt < 0.096 || dt > 0.104) { print "bad spacing at row " NR ": " dt; bad = 1 } }
         NR > 1 { prev = $1; if ($11 != 0 && $11 != 1) { print "bad still at row " NR; bad = 1 } }
         END { exit bad }' "$dir/est.csv"
# --output-rate 0 writes every sample.
"$headingd" replay --no-dds "$input" --output-rate 0 --output "$dir/all.csv" --quiet
all=$(($(wc -l <"$dir/all.csv") - 1))
samples=$(grep -vc '^#' "$input")
[ "$all" -eq "$samples" ] || { echo "every-sample output has $all rows for $samples samples"; exit 1; }
echo "ok: contract header, $rows rows at 10 Hz, $all rows at --output-rate 0"
