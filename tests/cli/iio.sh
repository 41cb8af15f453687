#!/usr/bin/env bash
# [sensor] kind = "iio" on a fake IIO tree (tests/iio_feeder: sysfs attributes in a directory, a
# FIFO for /dev/iio:device0, the simulator's agv scenario as st_gyro lays out its scans):
# `run --record` and `replay` of that recording give the same estimates byte for byte; `record`
# writes the same samples; the errors an integrator meets say what to do.
set -uo pipefail
headingd="$1" feeder="$2" root="$3"
dir="$(mktemp -d)"
chmod 755 "$dir"
feeder_pid=""
trap '[ -n "$feeder_pid" ] && kill "$feeder_pid" 2>/dev/null; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# Starts the feeder on a fresh tree and waits until the tree exists.
start_feeder() {  # layout seconds
  rm -rf "$dir/root" "$dir/feeder.out"
  "$feeder" "$dir/root" "$1" agv 5 "$2" >"$dir/feeder.out" 2>&1 &
  feeder_pid=$!
  for _ in $(seq 100); do grep -qs ready "$dir/feeder.out" && return 0; sleep 0.05; done
  fail "the feeder did not start: $(cat "$dir/feeder.out")"
}

cat >"$dir/iio.toml" <<TOML
[sensor]
kind = "iio"
[sensor.iio]
root = "$dir/root"
device = "l3gd20h"
sampling_frequency_hz = 400
[state]
path = ""
TOML

start_feeder st16 70
"$headingd" run -c "$dir/iio.toml" --no-dds --duration 60 --output "$dir/live.csv" --output-rate 0 \
  --record "$dir/rec.csv" 2>"$dir/run.log" || fail "run: $(cat "$dir/run.log")"
wait "$feeder_pid"; feeder_pid=""
grep -q "IIO gyro iio:device0 (l3gd20h)" "$dir/run.log" || fail "the summary does not name the IIO gyro: $(cat "$dir/run.log")"
grep -q "^# sensor: Linux IIO iio:device0 (l3gd20h)" "$dir/rec.csv" || fail "the recording's head: $(head -3 "$dir/rec.csv")"
grep -q "^# settings: sampling_frequency 380 Hz, trigger l3gd20h-trigger" "$dir/rec.csv" ||
  fail "the recording's settings: $(grep '^# settings' "$dir/rec.csv")"
"$headingd" replay --no-dds "$dir/rec.csv" --output-rate 0 --output "$dir/replay.csv" --quiet || fail "replay of the recording"
rows=$(($(wc -l <"$dir/live.csv") - 1))
[ "$rows" -gt 20000 ] || fail "only $rows live estimates"
cmp -s "$dir/live.csv" "$dir/replay.csv" || fail "replay differs from the live run: $(diff "$dir/live.csv" "$dir/replay.csv" | head -3)"
echo "ok: kind = iio: $rows live estimates equal the replay of the recording, byte for byte"

start_feeder st16 70
"$headingd" record -c "$dir/iio.toml" --duration 60 --output "$dir/rec2.csv" 2>"$dir/record.log" ||
  fail "record: $(cat "$dir/record.log")"
wait "$feeder_pid"; feeder_pid=""
# --duration ends at the end of a read, and how many scans a read gets depends on the pipe's
# timing: the shorter recording must be the start of the longer one, and both over 60 s.
grep -v '^#' "$dir/rec.csv" >"$dir/a"; grep -v '^#' "$dir/rec2.csv" >"$dir/b"
n=$(( $(wc -l <"$dir/a") < $(wc -l <"$dir/b") ? $(wc -l <"$dir/a") : $(wc -l <"$dir/b") ))
[ "$n" -gt 24000 ] || fail "only $n samples recorded"
cmp -s <(head -n "$n" "$dir/a") <(head -n "$n" "$dir/b") || fail "record differs from run --record"
echo "ok: record -c (kind = iio) writes the same samples as run --record ($n compared)"

# Errors, each with what to do.
sed 's/kind = "iio"/kind = "spi"/' "$dir/iio.toml" >"$dir/bad-kind.toml"
out=$("$headingd" run -c "$dir/bad-kind.toml" --no-dds --duration 1 2>&1); rc=$?
[ "$rc" -eq 78 ] && grep -q '\[sensor\] kind is "spi", allowed "l3gd20h", "iio"' <<<"$out" || fail "unknown kind: exit $rc: $out"
echo "ok: unknown kind -> exit 78: $out"

sed 's/device = "l3gd20h"/device = "bmi088"/' "$dir/iio.toml" >"$dir/no-device.toml"
start_feeder st16 1
out=$("$headingd" run -c "$dir/no-device.toml" --no-dds --duration 1 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "no IIO device 'bmi088' under .* (found: iio:device0 (l3gd20h)); is the kernel driver loaded" <<<"$out" ||
  fail "missing device: exit $rc: $out"
echo "ok: missing device -> exit 66: $out"

# Another Unix user without the udev rule's group: permission denied, naming the rule.
out=$(runuser -u nobody -- "$headingd" run -c "$dir/iio.toml" --no-dds --duration 1 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "Permission denied; give the service's group access with the udev rule" <<<"$out" ||
  fail "permission: exit $rc: $out"
echo "ok: permission denied (as nobody) -> exit 66: $out"

# The same user with what the udev rule does: the node to group iio 0660, and the attributes
# headingd writes to group iio by packaging/iio-permissions (run here on the fake tree).
getent group iio >/dev/null || groupadd --system iio
chgrp iio "$dir/root/dev/iio:device0" && chmod 0660 "$dir/root/dev/iio:device0"
HEADINGD_SYSFS_ROOT="$dir/root/sys" sh "$root/packaging/iio-permissions" /bus/iio/devices/iio:device0
kill "$feeder_pid" 2>/dev/null; wait "$feeder_pid" 2>/dev/null
"$feeder" "$dir/root" st16 agv 5 10 >/dev/null 2>&1 &  # the same tree, the permissions kept
feeder_pid=$!
out=$(runuser -u nobody -g nogroup -G iio -- "$headingd" run -c "$dir/iio.toml" --no-dds --duration 5 --output-rate 0 \
  --output - 2>"$dir/nobody.log" | wc -l); rc=$?
[ "$rc" -eq 0 ] && [ "$out" -gt 1900 ] || fail "as nobody in group iio: $out rows: $(cat "$dir/nobody.log")"
[ "$(stat -c %G "$dir/root/sys/bus/iio/devices/iio:device0/name")" = root ] || fail "iio-permissions touched 'name'"
echo "ok: another user in group iio runs on the tree after the udev helper ($out rows); nothing else changed group"
wait "$feeder_pid" 2>/dev/null; feeder_pid=""
start_feeder st16 1

echo 1 >"$dir/root/sys/bus/iio/devices/iio:device0/buffer/enable"
out=$("$headingd" run -c "$dir/iio.toml" --no-dds --duration 1 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "the buffer is already enabled by another consumer" <<<"$out" || fail "busy buffer: exit $rc: $out"
echo "ok: buffer enabled by another consumer -> exit 66: $out"
kill "$feeder_pid" 2>/dev/null; feeder_pid=""

# The device goes away for good while running: the run ends (give_up_s) with the cause, exit 74.
start_feeder st16 5
sed 's/sampling_frequency_hz = 400/sampling_frequency_hz = 400\ngive_up_s = 1/' "$dir/iio.toml" >"$dir/give-up.toml"
( sleep 1.5; rm -rf "$dir/root/sys/bus/iio/devices/iio:device0" "$dir/root/dev/iio:device0" ) &
out=$("$headingd" run -c "$dir/give-up.toml" --no-dds --output-rate 0 --output "$dir/gone.csv" 2>&1); rc=$?
[ "$rc" -eq 74 ] && grep -q "waiting for it to come back" <<<"$out" && grep -q "has been gone for 1 s" <<<"$out" ||
  fail "device gone: exit $rc: $out"
[ "$(wc -l <"$dir/gone.csv")" -gt 1000 ] || fail "the estimates before the device went were not kept"
echo "ok: a device gone for good ends the run with exit 74, estimates kept"
