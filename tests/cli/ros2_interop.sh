#!/usr/bin/env bash
# headingd as a ROS 2 node, seen by a ROS 2 peer on another DDS implementation (Cyclone DDS,
# types from the public .msg definitions; tests/interop/ros_peer.c):
#  A. simulated chip standing still, a set-heading at 6 s, bus errors at 5 s, output stuck at
#     8 s: the Imu per REP-145 (-1 where nothing is provided, during start-up and after), a
#     yaw-only quaternion equal to the heading and continuous across the set-heading,
#     /diagnostics with its keys and levels going to WARN and ERROR, the Temperature, and
#     ros_discovery_info naming our node with the GIDs of our endpoints;
#  B. a restart from the state file: heading and yaw go on where they stopped;
#  C. the Imu's angular velocity is the mean of the samples of its interval, to 1e-9 rad/s, and
#     a ROS-default reliable reader and a sensor-data reader both get it with the documented
#     setting (orientation_reliable = true); with the default, the sensor-data reader only.
source "$(dirname "$0")/ros2_common.sh"
domain=61
config() { # config FILE [extra lines...]
  local file="$1"
  shift
  printf '[dds]\ndomain_id = %d\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$domain" "$root" >"$file"
  for line in "$@"; do printf '%s\n' "$line" >>"$file"; done
}
# field NAME LINE...: the value of NAME=... on each line (stdin)
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }

# ---- A. live, simulated chip ---------------------------------------------------------------
config "$dir/a.toml"
"$peer" listen $domain 14 >"$dir/a.peer" 2>"$dir/a.peer.err" &
pids+=($!)
sleep 1
"$headingd" run --simulated-chip still --sim-realtime --sim-nack-at 5 --sim-stuck-at 8 --duration 12 \
  -c "$dir/a.toml" -o /dev/null 2>"$dir/a.err" &
pids+=($!)
sleep 6
"$headingd" command set-heading --heading-deg 90 -c "$dir/a.toml" --wait 5 >/dev/null 2>&1 || fail "set-heading not sent"
wait "${pids[1]}" || fail "run: $(tail -3 "$dir/a.err")"
wait "${pids[0]}"

n_imu=$(grep -c '^imu_sensor_data' "$dir/a.peer")
[ "$n_imu" -ge 400 ] || fail "only $n_imu Imu messages reached the sensor-data reader"
n_reliable=$(grep -c '^imu_reliable' "$dir/a.peer")
[ "$n_reliable" -eq 0 ] || fail "a reliable reader matched the default best-effort Imu writer ($n_reliable)"

# Covariances, per message: start-up first (rate not provided), then known.
awk -v pi2=9.869604401089358 '
  /^imu_sensor_data/ {
    for (i = 2; i <= NF; ++i) { split($i, kv, "="); v[kv[1]] = kv[2] }
    split(v["wcov"], w, ","); split(v["ocov"], o, ","); split(v["acov"], a, ",")
    if (a[1] != -1) { print "linear_acceleration_covariance[0] is " a[1] ", not -1"; bad = 1 }
    if (o[1] != pi2 || o[5] != pi2 || !(o[9] > 0) || o[2] != 0 || o[4] != 0) { print "orientation covariance " v["ocov"]; bad = 1 }
    if (w[1] == -1) {
      if (known) { print "rate marked not provided after it was known"; bad = 1 }
      ++startup; next
    }
    known = 1
    if (!(w[1] > 0 && w[5] > 0 && w[9] > 0) || w[2] != 0 || w[3] != 0) { print "rate covariance " v["wcov"]; bad = 1 }
    ++after
  }
  END {
    if (startup < 50) { print "only " startup " start-up messages with angular_velocity_covariance[0] = -1"; bad = 1 }
    if (after < 300) { print "only " after " messages with a known rate covariance"; bad = 1 }
    printf "covariances: %d start-up messages with the rate not provided (-1), %d after with it known\n", startup, after
    exit bad
  }' "$dir/a.peer" || fail "Imu covariances are not what REP-145 says"

# Yaw-only quaternion = heading - yaw_offset, matched by stamp with the Orientation message; the
# yaw is continuous across the set-heading while the heading jumps by it.
awk '
  function val(line, name,   m) { return match(line, " " name "=[^ ]*") ? substr(line, RSTART + length(name) + 2, RLENGTH - length(name) - 2) : "" }
  FNR == NR { if (/^orientation/) { h[val($0, "stamp")] = val($0, "heading"); off[val($0, "stamp")] = val($0, "yaw_offset") }; next }
  /^orientation/ { fixes = val($0, "fixes") + 0; if (fixes > maxfix) maxfix = fixes; if (val($0, "yaw_offset") + 0 != 0) jump = val($0, "yaw_offset") }
  /^imu_sensor_data/ {
    split(val($0, "q"), q, ",")
    if (q[1] != 0 || q[2] != 0) { print "roll/pitch in a yaw-only quaternion"; bad = 1 }
    yaw = 2 * atan2(q[3], q[4]); s = val($0, "stamp")
    if (s in h) {
      d = h[s] - off[s] - yaw; d -= 2 * 3.141592653589793 * int(d / (2 * 3.141592653589793) + (d < 0 ? -0.5 : 0.5))
      if (d > 1e-9 || d < -1e-9) { printf "yaw %.12f vs heading - offset %.12f at %s\n", yaw, h[s] - off[s], s; bad = 1 }
      ++matched
    }
    if (n++ > 0) { step = yaw - last; if (step < 0) step = -step; if (step > maxstep) maxstep = step }
    last = yaw
  }
  END {
    printf "yaw: %d Imu matched to Orientation by stamp (|yaw - (heading - offset)| <= 1e-9), fixes %d, offset %s rad, largest yaw step %.2e rad\n", matched, maxfix, jump, maxstep
    if (matched < 300 || maxfix != 1 || jump + 0 < 1.5 || maxstep > 1e-2) bad = 1
    exit bad
  }' "$dir/a.peer" "$dir/a.peer" || fail "the Imu yaw is not the continuous heading"

# /diagnostics: keys, levels, and the injected faults.
grep -q '^diagnostic .*name=headingd: sensor|hardware_id=L3GD20H' "$dir/a.peer" || fail "no sensor status with a hardware_id"
for key in state rate_hz nominal_rate_hz samples samples_dropped bus_errors fifo_overruns recoveries stuck_samples temperature_c; do
  grep '^diagnostic .*name=headingd: sensor' "$dir/a.peer" | tail -1 | grep -q "|.*[|;]$key=" || fail "sensor status lacks $key"
done
for key in method heading_deg heading_sigma_deg heading_fixes bias_dps bias_sigma_dps last_still_age_s accepted_segments bias_restarts returns_mended temperature_model temperature_models_refuted rejected_rate_changing motion_hint hint_conflicts commands_rejected; do
  grep '^diagnostic .*name=headingd: estimator' "$dir/a.peer" | tail -1 | grep -q "[|;]$key=" || fail "estimator status lacks $key"
done
grep -q '^diagnostic .*level=1 name=headingd: estimator|.*message=start-up' "$dir/a.peer" || fail "no WARN during start-up"
grep -q '^diagnostic .*level=0 name=headingd: estimator' "$dir/a.peer" || fail "the estimator never OK"
grep -q '^diagnostic .*level=0 name=headingd: sensor' "$dir/a.peer" || fail "the sensor never OK"
grep -Eq '^diagnostic .*level=1 name=headingd: sensor\|.*message=(bus errors|recovering)' "$dir/a.peer" || fail "no WARN after the bus errors"
grep -q '^diagnostic .*level=2 name=headingd: sensor|.*message=output stuck' "$dir/a.peer" || fail "no ERROR while the output was stuck"
echo "diagnostics: sensor OK -> WARN (bus errors) -> ERROR (stuck output); estimator WARN (start-up) -> OK; keys present"

n_temp=$(grep -c '^temperature .*frame=imu_link celsius=[0-9]' "$dir/a.peer")
[ "$n_temp" -ge 8 ] || fail "only $n_temp Temperature messages"

# ros_discovery_info: our node, and every endpoint of ours among its GIDs.
disc=$(grep -m1 '^discovery' "$dir/a.peer")
[ -n "$disc" ] || fail "no ros_discovery_info"
echo "$disc" | grep -q ' node=/|headingd ' || fail "ros_discovery_info does not name node /headingd: $disc"
writers=$(echo "$disc" | field writers)
readers=$(echo "$disc" | field readers)
prefix=$(echo "$disc" | field gid | cut -c1-24)
ours=0
while read -r kind guid; do
  case "$kind" in
    publication) list="$writers" ;;
    *) list="$readers" ;;
  esac
  [[ ",$list," == *",$guid,"* ]] || fail "our $kind $guid is not in ros_discovery_info"
  ours=$((ours + 1))
done < <(grep -E '^(publication|subscription) ' "$dir/a.peer" | sort -u | awk -v p="$prefix" '{ g = $NF; sub("guid=", "", g); if (substr(g, 1, 24) == p && $2 != "topic=ros_discovery_info") print $1, g }')
[ "$ours" -ge 7 ] || fail "only $ours of our endpoints discovered"
echo "ros_discovery_info: node /headingd with the GIDs of all $ours of our endpoints"

# ---- B. restart from the state file ---------------------------------------------------------
mkdir -m 700 "$dir/state"
config "$dir/b.toml"
run_b() { # run_b OUT SECONDS [set-heading at 4 s]
  "$peer" listen $domain $(($2 + 3)) >"$dir/$1" 2>/dev/null &
  local peer_pid=$!
  sleep 1
  "$headingd" run --simulated-chip still --sim-realtime --duration "$2" --state "$dir/state/state" -c "$dir/b.toml" \
    -o /dev/null 2>"$dir/$1.err" &
  local run_pid=$!
  if [ $# -ge 3 ]; then
    sleep 4
    "$headingd" command set-heading --heading-deg 45 -c "$dir/b.toml" --wait 5 >/dev/null 2>&1 || fail "set-heading"
  fi
  wait $run_pid || fail "run: $(tail -3 "$dir/$1.err")"
  wait $peer_pid
}
run_b b1.peer 7 fix
run_b b2.peer 4
yaw_of() { awk '/^imu_sensor_data/ { if (match($0, " q=[^ ]*")) { split(substr($0, RSTART + 3, RLENGTH - 3), q, ","); printf "%.9f\n", 2 * atan2(q[3], q[4]) } }' "$1"; }
heading_of() { grep '^orientation' "$1" | field heading; }
last_yaw=$(yaw_of "$dir/b1.peer" | tail -1)
first_yaw=$(yaw_of "$dir/b2.peer" | head -1)
last_heading=$(heading_of "$dir/b1.peer" | tail -1)
first_heading=$(heading_of "$dir/b2.peer" | head -1)
awk -v a="$last_yaw" -v b="$first_yaw" -v c="$last_heading" -v d="$first_heading" 'BEGIN {
  printf "restart: yaw %.6f -> %.6f rad, heading %.6f -> %.6f rad\n", a, b, c, d
  exit !(a != "" && b != "" && (a - b) ^ 2 < 1e-6 && (c - d) ^ 2 < 1e-6 && c > 0.7) }' || fail "yaw or heading not continuous across the restart"
grep '^imu_sensor_data' "$dir/b2.peer" | head -1 | grep -q ' wcov=-1,' && fail "after a restart with a saved bias the rate is known"

# ---- C. the mean rate, and both kinds of reader ---------------------------------------------
# Method a without a start-up segment keeps the bias at zero, so the bias-corrected rate is the
# recorded rate itself: the expected means come from the file alone.
awk 'BEGIN { srand(7); print "time_s,gx_dps,gy_dps,gz_dps,temp_c"
  for (k = 0; k < 2000; ++k) printf "%.6f,%.6f,%.6f,%.6f,25.0\n", k / 400.0, rand() - 0.5, rand() - 0.5, 3 * sin(k / 50.0) + rand() - 0.5 }' >"$dir/c.csv"
config "$dir/c.toml" 'orientation_reliable = true' 'orientation_rate_hz = 50.0' '[estimator]' 'method = "a"' \
  'still_at_start = false' 'sigma_still_dps = [0.3, 0.3, 0.3]'
"$peer" listen $domain 9 >"$dir/c.peer" 2>/dev/null &
pids+=($!)
"$headingd" replay "$dir/c.csv" --speed 2 --wait-subscribers 10 -c "$dir/c.toml" -o /dev/null \
  2>"$dir/c.err" || fail "replay: $(tail -3 "$dir/c.err")"
wait "${pids[-1]}"
# The publish rule: the first sample, then every sample at or past next = max(next + 1/50, t).
# Each message carries the samples up to and including the one that made it due.
awk -F, 'NR > 1 { t = $1; sx += $2; sy += $3; sz += $4; ++c
    if (n == 0 || t >= next_t) {
      printf "%.17g %.17g %.17g\n", sx / c * r, sy / c * r, sz / c * r
      sx = 0; sy = 0; sz = 0; c = 0
      next_t = n == 0 ? t + 0.02 : (next_t + 0.02 > t ? next_t + 0.02 : t); ++n
    } }
  BEGIN { r = 3.141592653589793 / 180 }' "$dir/c.csv" >"$dir/c.expected"
for reader in imu_reliable imu_sensor_data; do
  grep "^$reader" "$dir/c.peer" | sed -n 's/.* w=\([^ ]*\) .*/\1/p' | tr ',' ' ' >"$dir/c.$reader"
done
n_expected=$(wc -l <"$dir/c.expected")
n_reliable=$(wc -l <"$dir/c.imu_reliable")
n_sensor=$(wc -l <"$dir/c.imu_sensor_data")
[ "$n_reliable" -eq "$n_expected" ] || fail "reliable reader got $n_reliable of $n_expected Imu messages"
[ "$n_sensor" -ge $((n_expected * 9 / 10)) ] || fail "sensor-data reader got $n_sensor of $n_expected"
paste -d' ' "$dir/c.expected" "$dir/c.imu_reliable" | awk '
  { for (a = 1; a <= 3; ++a) { d = $a - $(a + 3); if (d < 0) d = -d; if (d > worst) worst = d } ++n }
  END { printf "mean rate: %d messages, largest |Imu - mean of its samples| %.2e rad/s\n", n, worst; exit !(n > 0 && worst <= 1e-9) }' ||
  fail "the Imu rate is not the mean of its interval's samples"
echo "QoS: with orientation_reliable = true a reliable (ROS default) reader got $n_reliable of $n_expected and a sensor-data reader $n_sensor; with the default, the sensor-data reader only (A)"
echo "ok: headingd is a REP-145 Imu, a REP-107 diagnostics publisher and a ROS 2 node to a Cyclone DDS peer"
