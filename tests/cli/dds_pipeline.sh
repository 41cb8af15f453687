#!/usr/bin/env bash
# Two processes on loopback: `replay` publishes at real time, `echo` receives every Orientation
# at the configured rate, in order, with no gaps; GyroBias and Status arrive; a subscriber
# started late still gets the latest GyroBias (transient-local). HeadingCommands: a valid one
# moves the heading, a malformed and a stale one do not and are counted on Status.
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; rm -rf "$dir"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

cat >"$dir/cfg.toml" <<TOML
[dds]
domain_id = 42
profiles_xml = "$root/config/fastdds-loopback.xml"
orientation_reliable = true
orientation_rate_hz = 20
TOML
# 20 s of a platform standing still (the simulator, 400 Hz).
"$headingd" simulate --scenario still --seed 9 --hours 0.0055555556 --output-dir "$dir" 2>/dev/null || fail "simulate"

"$headingd" echo orientation bias status imu --reliable --json -c "$dir/cfg.toml" --timeout 60 >"$dir/a.out" 2>"$dir/a.err" &
pids+=($!)
"$headingd" replay "$dir/imu.csv" --speed realtime --wait-subscribers 10 --linger 10 -c "$dir/cfg.toml" -o /dev/null 2>"$dir/replay.err" &
replay=$!
replay_start=$(date +%s)
pids+=("$replay")
sleep 4
"$headingd" command set-heading --heading-deg 90 -c "$dir/cfg.toml" || fail "valid command not sent"
"$headingd" command set-heading --heading-rad nan -c "$dir/cfg.toml" || fail "NaN command not sent"
"$headingd" command set-heading --heading-deg 45 --stamp-offset -60 -c "$dir/cfg.toml" || fail "stale command not sent"
# The recording ends after 20 s; replay lingers 10 s more without publishing anything new.
while [ $(($(date +%s) - replay_start)) -lt 23 ]; do sleep 0.2; done
late_start=$(date +%s.%N)
"$headingd" echo bias status --json -c "$dir/cfg.toml" --count 2 --timeout 6 >"$dir/late.out" 2>&1
late_rc=$?
wait "$replay" || fail "replay exited $?: $(cat "$dir/replay.err")"
sleep 1
kill -INT "${pids[0]}"; wait "${pids[0]}"

grep -q '"topic":"orientation"' "$dir/a.out" || fail "no orientation: $(head -3 "$dir/a.err")"
# Orientation: seq 1..N without a gap, N = 20 s x 20 Hz.
awk -F'"seq":' '/"topic":"orientation"/ { split($2, a, ","); s = a[1] + 0; if (s != ++n) { print "gap at " n ": seq " s; bad = 1; exit } }
     END { print "orientation messages: " n; if (n < 395 || n > 405) { print "expected about 400"; bad = 1 }; exit bad }' "$dir/a.out" ||
  fail "orientation stream"
grep -q '"topic":"bias"' "$dir/a.out" || fail "no GyroBias"
# The recording has a temperature column (22 degC at the start): GyroBias carries it.
grep '"topic":"bias"' "$dir/a.out" | tail -n 1 | grep -q '"temperature_c":2[0-9.]*,' ||
  fail "GyroBias without the sensor temperature: $(grep '"topic":"bias"' "$dir/a.out" | tail -n 1)"
grep -q '"topic":"status"' "$dir/a.out" || fail "no Status"
# The platform stands still throughout: after the first segment's verdict, Orientation says so.
awk '/"topic":"orientation"/ { n++; if (/"still":true/) s++ } END { printf "still flag on %d of %d\n", s, n; exit !(s >= 0.9 * n) }' \
  "$dir/a.out" || fail "Orientation.still is not set while the platform stands still"
# Imu: the mean rate of the 20 samples a message covers carries their noise (sigma_still about
# 0.14 dps on z here, over 20) plus the bias variance in its covariance.
imu_cov_z=$(grep '"topic":"imu"' "$dir/a.out" | tail -n 1 | sed -n 's/.*"angular_velocity_covariance_diag":\[[^]]*,\([-0-9.e]*\)\].*/\1/p')
awk -v c="$imu_cov_z" 'BEGIN { exit !(c > 5e-8 && c < 5e-6) }' ||
  fail "Imu angular velocity variance on z is '$imu_cov_z' rad^2/s^2, expected the noise of the mean of the 20 samples each message covers (~3e-7)"
echo "ok: every Orientation in order at 20 Hz, GyroBias, Status and Imu arrived (Imu z rate variance $imu_cov_z)"

# The late subscriber came after the last message was published: what it got came from history.
grep -q '"topic":"status"' "$dir/late.out" || fail "late subscriber got no Status: $(cat "$dir/late.out")"
stamp=$(grep '"topic":"bias"' "$dir/late.out" | sed -n 's/.*"stamp":\([0-9.]*\).*/\1/p' | head -n 1)
[ -n "$stamp" ] || fail "late subscriber got no GyroBias: $(cat "$dir/late.out")"
awk -v s="$stamp" -v t="$late_start" 'BEGIN { exit !(s < t) }' || fail "late GyroBias stamped $stamp, after the subscriber started at $late_start"
[ "$late_rc" -eq 0 ] || fail "late subscriber: echo --count 2 exited $late_rc: $(cat "$dir/late.out")"
echo "ok: late subscriber got the latest GyroBias (stamped $stamp, before it started at $late_start)"

# Commands: heading now 90 deg (the platform stands still), one accepted, two refused.
last_heading=$(grep '"topic":"orientation"' "$dir/a.out" | tail -n 1 | sed -n 's/.*"heading_rad":\([-0-9.e]*\).*/\1/p')
awk -v h="$last_heading" 'BEGIN { exit !(h > 1.5508 && h < 1.5908) }' || fail "heading after the command is $last_heading rad"
last_status=$(grep '"topic":"status"' "$dir/a.out" | tail -n 1)
grep -q '"commands_accepted":1,"commands_rejected":2' <<<"$last_status" || fail "status counts: $last_status"
grep -q "HeadingCommand refused" "$dir/replay.err" || fail "refusals not logged"
echo "ok: set-heading moved the heading to $last_heading rad; NaN and stale commands refused and counted"

# Nobody publishes any more: echo --count 1 --timeout 2 says so and exits 69 (a health check's answer).
"$headingd" echo orientation -c "$dir/cfg.toml" --count 1 --timeout 2 >"$dir/none.out" 2>"$dir/none.err"
none_rc=$?
[ "$none_rc" -eq 69 ] && grep -q "echo: 0 of 1 messages within 2 s" "$dir/none.err" && [ ! -s "$dir/none.out" ] ||
  fail "echo with nothing to hear: exit $none_rc, '$(cat "$dir/none.err")', $(wc -l <"$dir/none.out") lines"
echo "ok: echo --count 1 with no publisher: exit 69 after its timeout, and says how many came"
