#!/usr/bin/env bash
# `headingd run` against the simulated chip, recording as it goes: the recording replays to
# the very same estimates, sample for sample, through `replay` and through `run --recording`
# (run's own path with the pacer at max). `record` alone writes the same file. Missing
# hardware gives clear errors.
source "$(dirname "$0")/cli_common.sh"

"$headingd" run --simulated-chip agv --sim-seed 5 --sim-rate-error 0.03 --duration 60 \
  --output "$dir/live.csv" --output-rate 0 --record "$dir/rec.csv" 2>"$dir/run.log" || fail "run: $(cat "$dir/run.log")"
"$headingd" replay --no-dds "$dir/rec.csv" --output-rate 0 --output "$dir/replay.csv" --quiet || fail "replay of the recording"
rows=$(($(wc -l <"$dir/live.csv") - 1))
[ "$rows" -gt 20000 ] || fail "only $rows live estimates"
cmp -s "$dir/live.csv" "$dir/replay.csv" || fail "replay differs from the live run: $(diff "$dir/live.csv" "$dir/replay.csv" | head -3)"
echo "ok: $rows live estimates equal the replay of the recording, byte for byte"

# The recording through run's own path (run --recording, pacer at max): the same estimates as
# replay, byte for byte, and as the live run that made it.
"$headingd" run --no-dds --recording "$dir/rec.csv" --speed max --output-rate 0 --output "$dir/run-rec.csv" \
  2>"$dir/run-rec.log" || fail "run --recording: $(cat "$dir/run-rec.log")"
cmp -s "$dir/run-rec.csv" "$dir/replay.csv" || fail "run --recording differs from replay: $(diff "$dir/run-rec.csv" "$dir/replay.csv" | head -3)"
grep -q "(end of input)" "$dir/run-rec.log" || fail "run --recording did not end at the end of input: $(cat "$dir/run-rec.log")"
echo "ok: run --recording --speed max equals replay, byte for byte"

"$headingd" record --simulated-chip agv --sim-seed 5 --sim-rate-error 0.03 --duration 60 --output "$dir/rec2.csv" 2>/dev/null ||
  fail "record"
cmp -s <(grep -v '^#' "$dir/rec.csv") <(grep -v '^#' "$dir/rec2.csv") || fail "record differs from run --record"
echo "ok: record writes the same samples"

out=$("$headingd" run --bus /dev/i2c-9 --duration 1 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "cannot open I2C adapter /dev/i2c-9: No such file or directory" <<<"$out" || fail "missing bus: exit $rc: $out"
echo "ok: missing bus -> exit 66: $out"
out=$("$headingd" record --gpio-chip gpiochip7 --bus /dev/null --output "$dir/x.csv" 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "/dev/null is not an I2C adapter" <<<"$out" || fail "not an adapter: exit $rc: $out"
echo "ok: not an adapter -> exit 66: $out"

# A kernel driver bound to the chip (a fake sysfs tree: st_gyro's I2C driver on client 1-006b):
# run and record refuse before opening the bus, naming the driver and the fix. The "adapter"
# is a plain file here, so an open or a write would show (it would fail as "not an I2C adapter").
mkdir -p "$dir/sys/bus/i2c/devices/1-006b" "$dir/sys/bus/i2c/drivers/st-gyro-i2c"
ln -s ../../../../bus/i2c/drivers/st-gyro-i2c "$dir/sys/bus/i2c/devices/1-006b/driver"
printf 'untouched' >"$dir/i2c-1"
for cmd in "run --no-dds --duration 1" "record --output $dir/never.csv --duration 1"; do
  # shellcheck disable=SC2086
  out=$(HEADINGD_SYSFS_ROOT="$dir/sys" "$headingd" $cmd --bus "$dir/i2c-1" 2>&1); rc=$?
  [ "$rc" -eq 66 ] && grep -q "bound to the kernel driver 'st-gyro-i2c' (I2C client 1-006b)" <<<"$out" &&
    grep -q "/sys/bus/i2c/drivers/st-gyro-i2c/unbind" <<<"$out" || fail "bound driver, ${cmd%% *}: exit $rc: $out"
  [ "$(cat "$dir/i2c-1")" = untouched ] || fail "bound driver, ${cmd%% *}: the adapter was written"
done
[ ! -e "$dir/never.csv" ] || fail "record created its output despite the bound driver"
out=$(HEADINGD_SYSFS_ROOT="$dir/sys" "$headingd" run --no-dds --duration 1 --bus "$dir/i2c-1" --address 0x6A 2>&1)
grep -q "not an I2C adapter" <<<"$out" || fail "a driver on 0x6B must not block 0x6A: $out"
echo "ok: a bound kernel driver is refused by name with the fix; the adapter untouched"
