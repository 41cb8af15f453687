#!/usr/bin/env bash
# `headingd allan` on a short simulated still recording: noise terms printed, a config
# fragment that headingd itself accepts, and a PNG plot.
set -euo pipefail
headingd="$1"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
"$headingd" simulate --scenario still --seed 5 --hours 0.1 --output-dir "$dir" 2>/dev/null
"$headingd" allan "$dir/imu.csv" --emit-config --plot "$dir/allan.png" >"$dir/out.txt"
grep -q "^z: angle random walk 0.01" "$dir/out.txt" || { cat "$dir/out.txt"; echo "z ARW not near 0.011"; exit 1; }
sed -n '/^\[estimator\]/,$p' "$dir/out.txt" >"$dir/fragment.toml"
"$headingd" replay --no-dds "$dir/imu.csv" --config "$dir/fragment.toml" --output /dev/null --quiet
[ "$(head -c 4 "$dir/allan.png" | od -An -c | tr -d ' ')" = "211PNG" ] || { echo "no PNG written"; exit 1; }
echo "ok: noise terms, config fragment accepted, PNG plot written"
