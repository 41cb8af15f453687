#!/usr/bin/env bash
# 10,000 refused HeadingCommands from another DDS implementation (Cyclone) while headingd runs:
# every one is counted (Status, the run summary), the log gets a handful of lines per 10 s
# through log.cpp's per-kind limit, and the estimator is untouched (issue 15 item 5).
source "$(dirname "$0")/ros2_common.sh"
domain=64
n=10000
printf '[dds]\ndomain_id = %d\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$domain" "$root" >"$dir/cfg.toml"
"$headingd" run --simulated-chip still --sim-realtime --duration 16 -c "$dir/cfg.toml" -o /dev/null 2>"$dir/run.err" &
run=$!
# Meanwhile: echo --count 1 on three topics at once prints exactly one line (it printed two).
"$headingd" echo orientation bias status --count 1 --timeout 15 -c "$dir/cfg.toml" >"$dir/echo.out" 2>"$dir/echo.err" &
echo_pid=$!
"$peer" bad-commands $domain $n 2000 >"$dir/peer.out" 2>&1 || fail "peer: $(cat "$dir/peer.out")"
wait $echo_pid || fail "echo: $(cat "$dir/echo.err")"
[ "$(wc -l <"$dir/echo.out")" -eq 1 ] || fail "echo --count 1 printed $(wc -l <"$dir/echo.out") lines"
wait $run || fail "run: $(tail -3 "$dir/run.err")"
refused=$(sed -n 's/.*commands \([0-9]*\) accepted, \([0-9]*\) refused.*/\2/p' "$dir/run.err")
accepted=$(sed -n 's/.*commands \([0-9]*\) accepted, \([0-9]*\) refused.*/\1/p' "$dir/run.err")
lines=$(grep -c "HeadingCommand refused\|inbound messages refused" "$dir/run.err")
echo "$n bad commands: $accepted accepted, $refused refused and counted, $lines log lines in 16 s"
[ "$refused" = "$n" ] && [ "$accepted" = 0 ] || fail "not every command was refused and counted"
[ "$lines" -ge 1 ] && [ "$lines" -le 12 ] || fail "$lines log lines: the refusals are not rate-limited (or not logged)"
grep -q "HeadingCommand refused: heading is not a finite number\|HeadingCommand refused: .*finite" "$dir/run.err" ||
  fail "no refusal names its reason: $(grep -m1 refused "$dir/run.err")"
echo "ok: $n refused commands, all counted, $lines log lines"
