#!/usr/bin/env bash
# Discovery through a Fast DDS Discovery Server (`fastdds discovery`, fastdds-tools) instead of
# multicast: with `discovery_server` set, replay and echo find each other only while the server
# runs. Without it they see nothing, which shows discovery really goes through the server.
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
pids=()
# `fastdds discovery` runs the server as a child of its own: each is started in a session of its
# own (setsid) and stopped as a whole group, or the server outlives the test.
stop_group() { kill -- "-$1" 2>/dev/null || kill "$1" 2>/dev/null; }
cleanup() { for p in "${pids[@]}"; do stop_group "$p"; done; wait 2>/dev/null; rm -rf "$dir"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v fastdds >/dev/null || fail "fastdds (fastdds-tools) is not installed"

port=$((20000 + $$ % 20000))
cat >"$dir/cfg.toml" <<TOML
[dds]
domain_id = 44
profiles_xml = "$root/config/fastdds-loopback.xml"
orientation_rate_hz = 20
orientation_reliable = true
discovery_server = "127.0.0.1:$port"
TOML
# The same recording in both phases: 12 s standing still.
"$headingd" simulate --scenario still --seed 4 --hours 0.0033333333 --output-dir "$dir" 2>/dev/null || fail "simulate"

publish_and_listen() {  # $1: output file; echo for up to 8 s while replay publishes
  "$headingd" echo orientation --reliable --json -c "$dir/cfg.toml" --count 20 --timeout 8 >"$1" 2>"$1.err" &
  local listener=$!
  "$headingd" replay "$dir/imu.csv" --speed realtime -c "$dir/cfg.toml" -o /dev/null -q 2>"$1.replay" &
  local publisher=$!
  wait "$listener"
  kill -INT "$publisher" 2>/dev/null
  wait "$publisher" 2>/dev/null
}

# Phase 1: no server. Clients talk only to their server, so nothing is discovered.
publish_and_listen "$dir/without.out"
without=$(grep -c '"topic":"orientation"' "$dir/without.out")
[ "$without" -eq 0 ] || fail "$without messages arrived with no Discovery Server running"
echo "ok: without the server, echo received nothing"

# Phase 2: the server runs on 127.0.0.1:$port (id 0, the prefix headingd asks for).
setsid fastdds discovery -i 0 -l 127.0.0.1 -p "$port" >"$dir/server.out" 2>&1 &
pids+=($!)
sleep 1
publish_and_listen "$dir/with.out"
with=$(grep -c '"topic":"orientation"' "$dir/with.out")
[ "$with" -eq 20 ] || fail "$with of 20 messages through the Discovery Server: $(head -3 "$dir/with.out.err") $(cat "$dir/server.out")"
awk -F'"seq":' '{ split($2, a, ","); s = a[1] + 0; if (NR > 1 && s != last + 1) { print "gap before seq " s; exit 1 }; last = s }' \
  "$dir/with.out" || fail "orientation stream has a gap"
echo "ok: with the server on 127.0.0.1:$port, echo received 20 Orientation messages in order"

# Phase 3: a server with id 1 only, named in the second place of a list (as ROS_DISCOVERY_SERVER does).
stop_group "${pids[0]}"; wait "${pids[0]}" 2>/dev/null
port1=$((port + 1))
sed -i "s/^discovery_server = .*/discovery_server = [\"\", \"127.0.0.1:$port1\"]/" "$dir/cfg.toml"
setsid fastdds discovery -i 1 -l 127.0.0.1 -p "$port1" >"$dir/server1.out" 2>&1 &
pids+=($!)
sleep 1
publish_and_listen "$dir/with1.out"
with1=$(grep -c '"topic":"orientation"' "$dir/with1.out")
[ "$with1" -eq 20 ] || fail "$with1 of 20 messages through Discovery Server id 1: $(head -3 "$dir/with1.out.err")"
echo "ok: through server id 1 (second in the list), echo received 20 Orientation messages"
