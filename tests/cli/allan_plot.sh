#!/usr/bin/env bash
# `headingd allan` on a short simulated still recording: noise terms printed, a config
# fragment that headingd itself accepts, and a PNG plot.
set -euo pipefail
headingd="$(realpath "$1")"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
"$headingd" simulate --scenario still --seed 5 --hours 0.1 --output-dir "$dir" 2>/dev/null
"$headingd" allan "$dir/imu.csv" --emit-config --plot "$dir/allan.png" >"$dir/out.txt"
grep -q "^z: angle random walk 0.01" "$dir/out.txt" || { cat "$dir/out.txt"; echo "z ARW not near 0.011"; exit 1; }
sed -n '/^\[estimator\]/,$p' "$dir/out.txt" >"$dir/fragment.toml"
"$headingd" replay --no-dds "$dir/imu.csv" --config "$dir/fragment.toml" --output /dev/null --quiet
[ "$(head -c 4 "$dir/allan.png" | od -An -c | tr -d ' ')" = "211PNG" ] || { echo "no PNG written"; exit 1; }
echo "ok: noise terms, config fragment accepted, PNG plot written"

# A recording that mostly moves: the curve is the motion's, and allan says so (not on the still one
# above, nor with --still-only).
"$headingd" allan "$dir/imu.csv" >/dev/null 2>"$dir/err.txt"
[ ! -s "$dir/err.txt" ] || { cat "$dir/err.txt"; echo "FAIL: a still recording drew a warning"; exit 1; }
"$headingd" simulate --scenario agv --seed 2 --hours 0.1 --output-dir "$dir/agv" 2>/dev/null
"$headingd" allan "$dir/agv/imu.csv" --axis z >/dev/null 2>"$dir/err.txt"
grep -q "% of the samples lie outside the segments the auto estimator took for still; motion shapes the curve" \
  "$dir/err.txt" || { cat "$dir/err.txt"; echo "FAIL: no warning on a moving recording"; exit 1; }
"$headingd" allan "$dir/agv/imu.csv" --axis z --still-only >/dev/null 2>"$dir/err.txt"
[ ! -s "$dir/err.txt" ] || { cat "$dir/err.txt"; echo "FAIL: --still-only drew a warning"; exit 1; }
echo "ok: a moving recording's curve is called motion, a still one's and --still-only's are not"

# Hostile names (issue 15, item 1): an input and a plot path that would close a gnuplot string and
# run a command, and a link planted where a careless writer would put its temporary. Nothing runs,
# nothing outside the named output changes, and the PNG lands exactly at the odd path.
mkdir "$dir/hostile" && cd "$dir/hostile"
f="x';system 'touch pwned';print '.csv"
cp "$dir/imu.csv" "$f"
p="p';system 'touch pwned2';print '.png"
printf 'victim' >"$dir/victim"
ln -s "$dir/victim" "/tmp/headingd-allan-$$.dat" 2>/dev/null || true
"$headingd" allan "$f" --plot "$p" >/dev/null 2>"$dir/hostile.err" || { cat "$dir/hostile.err"; echo "FAIL: allan on a hostile name"; exit 1; }
rm -f "/tmp/headingd-allan-$$.dat"
[ ! -e pwned ] && [ ! -e pwned2 ] && [ -z "$(find "$dir" /tmp -maxdepth 1 -name 'pwned*' 2>/dev/null)" ] ||
  { echo "FAIL: a command ran from a file name"; exit 1; }
[ "$(head -c 4 "$p" | od -An -c | tr -d ' ')" = "211PNG" ] || { echo "FAIL: no PNG at the hostile path"; exit 1; }
[ "$(cat "$dir/victim")" = victim ] || { echo "FAIL: a planted link was written through"; exit 1; }
[ "$(ls -A | wc -l)" -eq 2 ] || { echo "FAIL: stray files: $(ls -A)"; exit 1; }
echo "ok: hostile input and plot names run nothing; the PNG is written where asked, nothing else touched"
