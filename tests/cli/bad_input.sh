#!/usr/bin/env bash
# Bad input through the real binary: each case must exit with the documented code and a
# message naming the file, the line and the problem, within a time limit (no hang).
set -uo pipefail
headingd="$1"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
failures=0

# expect NAME EXIT_CODE PATTERN -- ARGS...
expect() {
  local name="$1" code="$2" pattern="$3"
  shift 4
  local out rc
  out="$(timeout 10 "$headingd" "$@" 2>&1 >/dev/null)"
  rc=$?
  if [ "$rc" -ne "$code" ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL $name: exit $rc (want $code), stderr:"
    echo "$out" | sed 's/^/    /'
    echo "    wanted: $pattern"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(head -n 1 <<<"$out")"
  fi
}

hdr='time_s,gx_dps,gy_dps,gz_dps'
printf '%s\n0,1,2,3\n0.1,1,2\n' "$hdr" >"$dir/malformed.csv"
printf '%s\n0,1,2,3\n0.1,1,x2,3\n' "$hdr" >"$dir/nonnumeric.csv"
printf 'time_s,gx_dps,gz_dps\n0,1,3\n' >"$dir/missing.csv"
printf '%s\n0,1,2,3\n0.1,1,2,3\n0.05,1,2,3\n' "$hdr" >"$dir/backwards.csv"
: >"$dir/empty.csv"
printf '\x00\x01\xff garbage\n' >"$dir/binary.csv"
printf '[estimator]\nk_range = "7"\n' >"$dir/bad.toml"

mkfifo "$dir/fifo.toml"
expect config-directory 78 "config $dir is a directory, not a configuration file" -- replay --no-dds -c "$dir" "$dir/malformed.csv"
expect config-fifo 78 "config $dir/fifo.toml is a FIFO, not a configuration file" -- run --no-dds --simulated-chip still --duration 1 -c "$dir/fifo.toml"
expect config-device 78 "config /dev/zero is a device, not a configuration file" -- run --no-dds --simulated-chip still --duration 1 -c /dev/zero
expect malformed-line 65 "$dir/malformed.csv:3: expected 4 fields, found 3" -- replay --no-dds "$dir/malformed.csv" -o "$dir/o.csv"
expect non-numeric 65 "$dir/nonnumeric.csv:3: field 'gy_dps' (column 3): 'x2' is not a finite number" -- replay --no-dds "$dir/nonnumeric.csv" -o "$dir/o.csv"
expect missing-column 65 "$dir/missing.csv:1: missing column 'gy_dps'" -- replay --no-dds "$dir/missing.csv" -o "$dir/o.csv"
expect time-backwards 65 "$dir/backwards.csv:4: time goes backwards" -- replay --no-dds "$dir/backwards.csv" -o "$dir/o.csv"
expect empty-file 65 "$dir/empty.csv: file is empty" -- replay --no-dds "$dir/empty.csv" -o "$dir/o.csv"
expect binary-file 65 "$dir/binary.csv:1: missing column 'time_s'" -- replay --no-dds "$dir/binary.csv" -o "$dir/o.csv"
expect no-such-file 66 "cannot open $dir/none.csv: No such file or directory" -- replay --no-dds "$dir/none.csv"
expect bad-config 78 "$dir/bad.toml:2:" -- replay --no-dds "$dir/malformed.csv" --config "$dir/bad.toml"
printf '[sensor]\nrate_hz = 300\n' >"$dir/bad-sensor.toml"
printf '[state]\npath = 5\n' >"$dir/bad-state.toml"
printf '[dds]\ndomain_id = 9999\n' >"$dir/bad-dds.toml"
printf '[sensor]\nbuss = "/dev/i2c-1"\n' >"$dir/unknown-sensor.toml"
expect run-bad-rate 78 "$dir/bad-sensor.toml:2:11: 'sensor.rate_hz' is 300, allowed 100, 200, 400 or 800" -- run --no-dds -c "$dir/bad-sensor.toml"
expect run-bad-type 78 "$dir/bad-state.toml:2:8: 'state.path' must be a string, found 5" -- run --no-dds -c "$dir/bad-state.toml"
expect run-bad-domain 78 "$dir/bad-dds.toml:2:13: 'dds.domain_id' is 9999, allowed [0, 232]" -- run --no-dds -c "$dir/bad-dds.toml"
expect run-unknown-key 78 "$dir/unknown-sensor.toml:2:8: 'sensor.buss' is not a known key" -- run --no-dds -c "$dir/unknown-sensor.toml"
expect bad-method 64 "'q' is not a method" -- replay --no-dds "$dir/malformed.csv" --method q
expect unwritable-output 73 "cannot create /nonexistent/o.csv" -- replay --no-dds "$dir/malformed.csv" -o /nonexistent/o.csv
expect allan-bad-axis 64 "'q' is not x, y, z or all" -- allan "$dir/malformed.csv" --axis q
printf "%s\n0,1,2,3\n0.1,1,2,3\n" "$hdr" >"$dir/short.csv"
expect allan-too-short 65 "too few samples for an Allan analysis" -- allan "$dir/short.csv" --axis z
expect unknown-scenario 64 "unknown scenario 'moon'" -- simulate --scenario moon --output-dir "$dir/sim"

# Finite as read, absurd as physics (issue 15 item 3): refused at the estimator's door with file and
# line, never a NaN heading with sigma 0.
printf '%s\n0,1,2,3\n0.0025,1,2,1e308\n' "$hdr" >"$dir/huge.csv"
expect huge-rate 65 "$dir/huge.csv:3: rate z = 1e+308 dps is beyond +-10000 dps" -- replay --no-dds "$dir/huge.csv" -o "$dir/o.csv"
printf '#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]\n0,0,0,0\n2500000,0,0,1e307\n' >"$dir/euroc.csv"
expect euroc-overflow 65 "$dir/euroc.csv:3: rate z = inf dps is beyond +-10000 dps" -- replay --no-dds "$dir/euroc.csv" -o "$dir/o.csv"
printf '%s,temp_c\n0,1,2,3,25\n0.0025,1,2,3,900\n' "$hdr" >"$dir/hot.csv"
expect hot-chip 65 "$dir/hot.csv:3: temperature 900 degC is outside -60..150 degC" -- replay --no-dds "$dir/hot.csv" -o "$dir/o.csv"
# replay X -o X (item 7): the recording is never truncated.
printf '%s\n0,1,2,3\n0.0025,1,2,3\n' "$hdr" >"$dir/keep.csv"
cp "$dir/keep.csv" "$dir/keep.orig"
ln -s keep.csv "$dir/alias.csv"
expect output-is-input 64 "is the input $dir/keep.csv itself: refusing to overwrite it" -- replay --no-dds "$dir/keep.csv" -o "$dir/keep.csv"
expect output-is-input-link 64 "is the input $dir/keep.csv itself" -- replay --no-dds "$dir/keep.csv" -o "$dir/alias.csv"
# A link planted where an output goes (estimates, a recording) is refused, never followed.
printf 'untouched\n' >"$dir/victim.txt"
ln -s "$dir/victim.txt" "$dir/planted.csv"
expect output-planted-link 73 "cannot create $dir/planted.csv: it is a symbolic link" -- replay --no-dds "$dir/keep.csv" -o "$dir/planted.csv"
expect record-planted-link 73 "cannot create $dir/planted.csv: it is a symbolic link" -- run --no-dds --simulated-chip still --duration 1 --record "$dir/planted.csv"
[ "$(cat "$dir/victim.txt")" = untouched ] || { echo "FAIL planted-link: the link's target was written"; failures=$((failures + 1)); }
expect record-is-input 64 "the recording $dir/keep.csv is the input" -- run --no-dds --recording "$dir/keep.csv" --speed max --record "$dir/keep.csv"
expect output-is-record 64 "the estimates output and the recording are one file" -- run --no-dds --simulated-chip still --duration 1 -o "$dir/new.csv" --record "$dir/./new.csv"
if cmp -s "$dir/keep.csv" "$dir/keep.orig"; then echo "ok   input-untouched: the recording is as it was"; else
  echo "FAIL input-untouched: the recording changed"; failures=$((failures + 1)); fi

# Item 8: score, echo and the readers held to replay's standards.
printf '\xef\xbb\xbftime_s,heading_deg\n0,0\n1,1\n' >"$dir/bom.csv"
printf 'time_s,heading_deg,heading_deg\n0,0,1\n' >"$dir/dup.csv"
printf 'time_s,heading_deg\n0,0\n1,1' >"$dir/trunc.csv"
printf 'time_s,heading_deg\n0,0\n2,1\n1,1\n' >"$dir/order.csv"
printf 't\x1b[31mime,x\n0,0\n' >"$dir/ctl.csv"
printf '\xef\xbb\xbf%s\n0,1,2,3\n0.0025,1,2,3\n' "$hdr" >"$dir/bom-rec.csv"
printf 'time_s,gx_dps,gy_dps,gz_dps,gz_dps\n0,1,2,3,4\n' >"$dir/dup-rec.csv"
printf '%s\n0,1,2,3\n0.0025,1,2,3' "$hdr" >"$dir/trunc-rec.csv"
expect score-duplicate-column 65 "$dir/dup.csv:1: column 'heading_deg' appears twice in the header (columns 2 and 3)" -- score "$dir/dup.csv" "$dir/bom.csv"
expect replay-duplicate-column 65 "$dir/dup-rec.csv:1: column 'gz_dps' appears twice in the header (columns 4 and 5)" -- replay --no-dds "$dir/dup-rec.csv" -o "$dir/o.csv"
expect score-truncated 65 "$dir/trunc.csv:3: the last line has no newline" -- score "$dir/trunc.csv" "$dir/bom.csv"
expect replay-truncated 65 "$dir/trunc-rec.csv:3: the last line has no newline" -- replay --no-dds "$dir/trunc-rec.csv" -o "$dir/o.csv"
expect score-time-order 65 "$dir/order.csv:4: time does not advance" -- score "$dir/order.csv" "$dir/bom.csv"
expect score-directory 66 "cannot read $dir: it is a directory" -- score "$dir" "$dir/bom.csv"
# A directory is a fleet of recordings to replay (each to its own file): -o cannot name one output.
expect replay-directory 64 "with several recordings, -o and --plot do not apply" -- replay --no-dds "$dir" -o "$dir/o.csv"
mkdir "$dir/empty"
expect replay-empty-directory 66 "no recordings (*.csv, *.csv.zst, *.csv.gz) in $dir/empty" -- replay --no-dds "$dir/empty"
expect run-recording-directory 66 "cannot read $dir: it is a directory" -- run --no-dds --recording "$dir"
expect control-bytes-escaped 65 'found: t\x1b[31mime,x' -- replay --no-dds "$dir/ctl.csv" -o "$dir/o.csv"
if "$headingd" score "$dir/bom.csv" "$dir/bom.csv" >/dev/null 2>&1 && "$headingd" replay --no-dds "$dir/bom-rec.csv" -o /dev/null 2>/dev/null; then
  echo "ok   bom-accepted: a UTF-8 byte-order mark before the header is skipped"
else
  echo "FAIL bom-accepted"; failures=$((failures + 1))
fi
out="$("$headingd" score "$dir/bom.csv" "$dir/bom.csv" 2>&1 >/dev/full)"; rc=$?
if [ $rc -eq 73 ]; then echo "ok   score-stdout-full: exit 73 ($out)"; else echo "FAIL score-stdout-full: exit $rc"; failures=$((failures + 1)); fi
# The state path: "" is a usage error, a FIFO or a device is refused at once (no hang, no endless read).
expect state-empty-path 64 "--state needs a file name" -- run --no-dds --simulated-chip still --duration 1 --state ""
mkfifo "$dir/state.fifo"
expect state-fifo 0 "state.fifo: not a regular file; starting without saved state" -- run --no-dds --simulated-chip still --duration 1 --state "$dir/state.fifo" -o /dev/null
expect state-device 0 "/dev/zero: not a regular file" -- run --no-dds --simulated-chip still --duration 1 --state /dev/zero -o /dev/null
[ -e "$dir/.tmp" ] || [ -e ./.tmp ] && { echo "FAIL stray .tmp"; failures=$((failures + 1)); }
printf '[dds]\nprofiles_xml = "%s/none.xml"\n' "$dir" >"$dir/noxml.toml"
expect profiles-xml-unreadable 78 "noxml.toml:2:16: 'dds.profiles_xml' is '$dir/none.xml': cannot read it" -- run --simulated-chip still --duration 1 -c "$dir/noxml.toml"
# The simulator's hidden fault switches: a time that is no time (its nanoseconds were an unchecked
# int64 cast) and a rate error that stops the simulated clock (it hung) are refused by name.
for bad in nan 1e30 inf; do
  expect "sim-dead-after-$bad" 66 "--sim-dead-after must be a time in seconds up to a year" -- run --no-dds --simulated-chip still --duration 1 --sim-dead-after "$bad" -o /dev/null
done
expect sim-stuck-at-huge 66 "--sim-stuck-at must be a time in seconds up to a year" -- run --no-dds --simulated-chip still --duration 1 --sim-stuck-at 1e12 -o /dev/null
expect sim-rate-error 66 "--sim-rate-error must lie within -0.5..0.5" -- run --no-dds --simulated-chip still --duration 1 --sim-rate-error -1 -o /dev/null

# allan --emit-config prints only what --config accepts, even for a noiseless (constant) recording.
awk 'BEGIN { print "time_s,gx_dps,gy_dps,gz_dps"; for (k = 0; k < 40000; ++k) printf "%.4f,0.5,0.5,0.5\n", k / 400 }' >"$dir/const.csv"
"$headingd" allan "$dir/const.csv" --emit-config 2>/dev/null | sed -n '/^# headingd estimator settings/,$p' >"$dir/emitted.toml"
if grep -q '^\[estimator\]' "$dir/emitted.toml" && "$headingd" replay --no-dds "$dir/const.csv" -c "$dir/emitted.toml" -o /dev/null 2>"$dir/emitted.err"; then
  echo "ok   allan-emit-config: what it prints for a noiseless recording is a valid config ($(grep -c '^#' "$dir/emitted.toml") lines explain what it cannot give)"
else
  echo "FAIL allan-emit-config: $(cat "$dir/emitted.err")"; cat "$dir/emitted.toml"; failures=$((failures + 1))
fi

# Estimates before a bad line are kept: the malformed file's first sample was written.
"$headingd" replay --no-dds "$dir/malformed.csv" -o "$dir/kept.csv" -q 2>/dev/null
if [ "$(wc -l <"$dir/kept.csv")" -ne 2 ]; then
  echo "FAIL kept-before-error: expected header + 1 row in output"; failures=$((failures + 1))
else
  echo "ok   kept-before-error: header + 1 row written before the bad line"
fi

# The priority prefix journald reads ("<3>" = err) only where stderr is the journal's stream, which
# systemd names in $JOURNAL_STREAM (device:inode); on a terminal or in a file, none.
printf '[estimator]\nsegment_s = -3\n' >"$dir/broken.toml"
"$headingd" run -c "$dir/broken.toml" --no-dds 2>"$dir/plain.err"
: >"$dir/journal.err"
JOURNAL_STREAM="$(stat -c '%d:%i' "$dir/journal.err")" "$headingd" run -c "$dir/broken.toml" --no-dds 2>>"$dir/journal.err"
JOURNAL_STREAM="$(stat -c '%d:%i' "$dir/plain.err")" "$headingd" run -c "$dir/broken.toml" --no-dds 2>"$dir/other.err"
if grep -q '^headingd: .*broken.toml' "$dir/plain.err" && grep -q '^<3>headingd: .*broken.toml' "$dir/journal.err" &&
  grep -q '^headingd: ' "$dir/other.err"; then
  echo "ok   journal-priority: <3> where stderr is the stream \$JOURNAL_STREAM names, none elsewhere"
else
  echo "FAIL journal-priority: $(cat "$dir/plain.err" "$dir/journal.err" "$dir/other.err")"; failures=$((failures + 1))
fi

[ "$failures" -eq 0 ]
