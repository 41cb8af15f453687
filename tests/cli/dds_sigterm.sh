#!/usr/bin/env bash
# SIGTERM while publishing: headingd exits 0 within 1 s and leaves none of its Fast DDS
# shared-memory files in /dev/shm.
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
printf '[dds]\ndomain_id = 43\ntransport = "shm"\nprofiles_xml = "%s/config/fastdds-loopback-shm.xml"\n' "$root" >"$dir/cfg.toml"
ls /dev/shm | sort >"$dir/before"
"$headingd" replay "$root/tests/data/agv-1min/imu.csv" --speed realtime -c "$dir/cfg.toml" -o /dev/null -q &
pid=$!
sleep 2
ls /dev/shm | sort >"$dir/during"
start=$(date +%s%N)
kill -TERM "$pid"
wait "$pid"
rc=$?
elapsed_ms=$((($(date +%s%N) - start) / 1000000))
ls /dev/shm | sort >"$dir/after"
echo "exit $rc after ${elapsed_ms} ms; shm files while running: $(comm -13 "$dir/before" "$dir/during" | wc -l)"
[ "$rc" -eq 0 ] || { echo "FAIL: exit code $rc"; exit 1; }
[ "$elapsed_ms" -le 1000 ] || { echo "FAIL: took ${elapsed_ms} ms"; exit 1; }
left=$(comm -13 "$dir/before" "$dir/after")
[ -z "$left" ] || { echo "FAIL: left in /dev/shm: $left"; exit 1; }
echo "ok: exit 0 within 1 s, nothing left in /dev/shm"

# SIGTERM while waiting for a subscriber (--wait-subscribers, during discovery): the wait ends at once.
"$headingd" replay "$root/tests/data/agv-1min/imu.csv" --wait-subscribers 30 -c "$dir/cfg.toml" -o /dev/null -q &
pid=$!
sleep 1.5
start=$(date +%s%N)
kill -TERM "$pid"
wait "$pid"
rc=$?
elapsed_ms=$((($(date +%s%N) - start) / 1000000))
[ "$rc" -eq 0 ] && [ "$elapsed_ms" -le 1000 ] || { echo "FAIL: during discovery: exit $rc after ${elapsed_ms} ms"; exit 1; }
echo "ok: SIGTERM while waiting for subscribers: exit 0 after ${elapsed_ms} ms"
