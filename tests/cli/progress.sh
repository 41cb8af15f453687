#!/usr/bin/env bash
# A replay longer than two seconds draws a progress line on a terminal (samples, rate, share done,
# time left) and erases it for the summary; with standard error not a terminal, no line at all.
source "$(dirname "$0")/cli_common.sh"
"$headingd" simulate --scenario agv --seed 1 --hours 0.05 --output-dir "$dir/sim" >/dev/null 2>&1 || fail "simulate"
# 180 s of data at 50x real time: 3.6 s, under a pseudo-terminal made by script(1).
script -qec "$headingd replay --no-dds --speed 50 $dir/sim/imu.csv -o $dir/est.csv" "$dir/tty.txt" >/dev/null ||
  fail "replay under script"
tr '\r' '\n' <"$dir/tty.txt" | grep -E '^  [0-9.]+ M samples, [0-9.]+ M/s, [0-9]+ % done, [0-9]+ s left' >"$dir/lines" ||
  fail "no progress line on the terminal: $(tr '\r' '\n' <"$dir/tty.txt" | head -5)"
grep -q "headingd replay: $dir/sim/imu.csv" "$dir/tty.txt" || fail "no summary after the progress"
echo "ok: $(wc -l <"$dir/lines") progress lines on a terminal, e.g.$(tail -1 "$dir/lines" | sed 's/\x1b\[K//')"
"$headingd" replay --no-dds --speed 50 "$dir/sim/imu.csv" -o "$dir/est2.csv" 2>"$dir/err" || fail "replay"
! grep -q "M samples" "$dir/err" || fail "a progress line went to a file: $(head -3 "$dir/err")"
echo "ok: none when standard error is a file"
