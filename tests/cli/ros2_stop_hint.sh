#!/usr/bin/env bash
# The vehicle's odometry as the "stopped" hint, from a ROS 2 peer on another DDS implementation
# (Cyclone DDS, nav_msgs/Odometry from the public definitions). The recording: a platform that
# stands still for 90 s while, from 30 s on, its gyro bias drifts 0.006 dps/s (thermal creep
# the mean test cannot tell from a slow turn, so it rejects those stops).
#   no odometry:           the creep's segments are rejected;
#   odometry "stopped":    they are accepted (the vehicle knows its wheels stand still);
#   odometry "moving":     nothing is accepted after the start-up;
#   NaN or stale odometry: ignored, counted as refused, the same verdicts as with none.
set -uo pipefail
headingd="$1"
peer="$2"
root="$3"
dir="$(mktemp -d)"
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
export CYCLONEDDS_URI="file://$root/tests/interop/cyclone.xml"
domain=62
awk 'BEGIN { srand(11); print "time_s,gx_dps,gy_dps,gz_dps,temp_c"
  for (k = 0; k < 18000; ++k) {
    t = k / 200.0; creep = t > 30 ? 0.006 * (t - 30) : 0
    u = rand(); v = rand(); w = rand(); x = rand()   # Box-Muller: 0.1 dps white noise
    r1 = sqrt(-2 * log(u + 1e-12)); r2 = sqrt(-2 * log(w + 1e-12))
    printf "%.6f,%.6f,%.6f,%.6f,25.0\n", t, 0.2 + 0.1 * r1 * cos(6.283185307 * v), -0.1 + 0.1 * r1 * sin(6.283185307 * v),
      0.3 + creep + 0.1 * r2 * cos(6.283185307 * x) } }' >"$dir/rec.csv"
printf '[dds]\ndomain_id = %d\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n[ros.stop_hint]\ntopic = "odom"\nhold_s = 0.0\nstale_s = 0.5\n' \
  "$domain" "$root" >"$dir/cfg.toml"

accepted() { sed -n 's/.*segments up to [0-9.]* s: \([0-9]*\) accepted as still.*/\1/p' "$1"; }

"$headingd" replay "$dir/rec.csv" --no-dds -o /dev/null 2>"$dir/none.err" || fail "replay"
none=$(accepted "$dir/none.err")

# The replay runs at 15x; the hint counts from the peer's first message, which may follow the
# orientation subscriber's match (what --wait-subscribers waits for) by a few tenths of a second.
# "moving" must block the second segment, which closes 6 s into the recording: that run goes at
# 5x, so the hint has 1.2 s of wall time instead of 0.4 s (a one-off failure under ctest -j2).
with_odometry() { # with_odometry MODE [odom|twist] [SPEED]
  local kind=${2:-odom} speed=${3:-15} cfg="$dir/cfg.toml"
  if [ "$kind" = twist ]; then
    cfg="$dir/twist.toml"
    sed 's/^topic = "odom"$/topic = "cmd_twist"\ntype = "twist"/' "$dir/cfg.toml" >"$cfg"
  fi
  "$peer" "$kind" $domain "rt/$([ "$kind" = twist ] && echo cmd_twist || echo odom)" "$1" 60 >"$dir/$1.peer" 2>&1 &
  local peer_pid=$!
  "$headingd" replay "$dir/rec.csv" --speed "$speed" --wait-subscribers 15 -c "$cfg" -o /dev/null 2>"$dir/$1.err" ||
    fail "replay with $1 odometry: $(tail -3 "$dir/$1.err")"
  kill $peer_pid 2>/dev/null
  wait $peer_pid 2>/dev/null
  motion=$(sed -n 's/.*vehicle motion messages \([0-9]*\) accepted, \([0-9]*\) refused.*/\1 \2/p' "$dir/$1.err")
  echo "$1: $(accepted "$dir/$1.err") accepted as still; motion messages accepted/refused: $motion"
}
with_odometry stopped
stopped=$(accepted "$dir/stopped.err")
read -r stopped_ok _ <<<"$motion"
with_odometry moving odom 5
moving=$(accepted "$dir/moving.err")
with_odometry nan
nan=$(accepted "$dir/nan.err")
read -r nan_ok nan_refused <<<"$motion"
with_odometry stale
stale=$(accepted "$dir/stale.err")
read -r stale_ok stale_refused <<<"$motion"
echo "no odometry: $none accepted as still"
cp "$dir/stopped.err" "$dir/stopped-odometry.err"
with_odometry stopped twist
twist=$(accepted "$dir/stopped.err")

[ "$none" -le 12 ] || fail "the creep's segments were accepted without a hint ($none): the scenario tests nothing"
[ "$stopped" -ge $((none + 12)) ] || fail "stopped odometry: $stopped accepted, not well above $none"
[ "${stopped_ok:-0}" -ge 50 ] || fail "stopped odometry: only ${stopped_ok:-0} messages accepted"
[ "$twist" -ge $((none + 12)) ] || fail "stopped geometry_msgs/Twist: $twist accepted, not well above $none"
[ "$moving" -le 1 ] || fail "moving odometry: $moving accepted (only the start-up may be)"
[ "$nan" -eq "$none" ] || fail "NaN odometry changed the verdicts ($nan vs $none)"
[ "${nan_ok:-1}" -eq 0 ] && [ "${nan_refused:-0}" -ge 50 ] || fail "NaN odometry not refused and counted"
[ "$stale" -eq "$none" ] || fail "stale odometry changed the verdicts ($stale vs $none)"
[ "${stale_ok:-1}" -eq 0 ] && [ "${stale_refused:-0}" -ge 50 ] || fail "stale odometry not refused and counted"
grep -q "vehicle motion message refused: a speed is not a finite number" "$dir/nan.err" || fail "no log line for NaN odometry"
lines=$(grep -c "vehicle motion message refused" "$dir/nan.err")
[ "$lines" -le 12 ] || fail "$lines log lines for refused odometry: not rate-limited"
echo "ok: odometry 'stopped' accepts the creeping stops ($none -> $stopped; as a Twist: $twist), 'moving' blocks them ($moving), NaN and stale odometry are refused, counted and logged $lines times"
