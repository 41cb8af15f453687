#!/usr/bin/env bash
# [sensor] kind = "iio" read against a second reader we did not write: on each of the fake's three
# scan layouts (st_gyro's 16-bit little-endian; a 20-bit big-endian gyro in 32-bit words with a
# shift, channels out of order, offsets and the timestamp after padding, in buffer0/ beside the
# legacy names; a BMI160-like one with a mount matrix) the same simulated scans are read once by
# `headingd record` and once by libiio (tests/interop/iio_libiio_reader.c, libiio's own layout and
# decoding), each sample compared. libiio reads only /sys/bus/iio and /dev, so its run is in a mount
# namespace made here, with the fake tree bound over both; nothing outside it sees the mounts.
#   iio_libiio.sh HEADINGD IIO_FEEDER IIO_LIBIIO_READER
# shellcheck source=cli_common.sh
source "$(dirname "$0")/cli_common.sh"
feeder="$2" reader="$3"
[ "$(id -u)" -eq 0 ] || { echo "skipped: a mount namespace needs root"; exit 77; }
feeder_pid=""
trap '[ -n "$feeder_pid" ] && kill "$feeder_pid" 2>/dev/null; [ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
compare_rows=3000

start_feeder() {  # root layout
  rm -rf "$1"
  "$feeder" "$1" "$2" agv 5 12 >"$1.feeder" 2>&1 &
  feeder_pid=$!
  for _ in $(seq 100); do grep -qs ready "$1.feeder" && return 0; sleep 0.05; done
  fail "the feeder did not start: $(cat "$1.feeder")"
}

for case in st16:l3gd20h be32:fake32 swapped:bmi160; do
  layout=${case%%:*} name=${case#*:}
  root="$dir/$layout"
  cat >"$dir/$layout.toml" <<TOML
[sensor]
kind = "iio"
[sensor.iio]
root = "$root"
device = "$name"
sampling_frequency_hz = 400
[state]
path = ""
TOML

  start_feeder "$root" "$layout"
  "$headingd" record -c "$dir/$layout.toml" --duration 9 --output "$dir/$layout.ours.csv" 2>"$dir/$layout.record.log" ||
    fail "$layout: headingd record: $(cat "$dir/$layout.record.log")"
  kill "$feeder_pid" 2>/dev/null; wait "$feeder_pid" 2>/dev/null; feeder_pid=""

  start_feeder "$root" "$layout"
  # The paths go in as arguments, never into the command's text.
  timeout 60 unshare --mount --propagation private -- sh -c \
    'mount --bind "$1/sys" /sys && mount --bind "$1/dev" /dev && exec "$2" "$3" "$4"' \
    sh "$root" "$reader" "$name" "$compare_rows" >"$dir/$layout.libiio.csv" 2>"$dir/$layout.libiio.log" ||
    fail "$layout: libiio's reader: $(cat "$dir/$layout.libiio.log")"
  kill "$feeder_pid" 2>/dev/null; wait "$feeder_pid" 2>/dev/null; feeder_pid=""

  # Row by row: the time to the nanosecond, each rate to 1e-12 of its size (both are doubles from
  # the same integers; only the order of the arithmetic may differ).
  result=$(awk -F, -v rows="$compare_rows" '
    function abs(v) { return v < 0 ? -v : v }
    FNR == NR { if ($0 !~ /^#/ && $1 != "time_s") ours[++n] = $0; next }
    $1 == "time_s" { next }
    {
      ++m
      if (m > n) { print "headingd recorded only " n " rows"; bad = 1; exit }
      split(ours[m], o, ",")
      if (abs($1 - o[1]) > 1e-9) { print "row " m ": time " $1 " (libiio) vs " o[1]; bad = 1; exit }
      for (i = 2; i <= 4; ++i) {
        d = abs($i - o[i])
        if (d > 1e-12 * (abs(o[i]) + 1e-3)) { print "row " m " column " i ": " $i " (libiio) vs " o[i]; bad = 1; exit }
        if (d > worst) worst = d
        if (abs(o[i]) > largest) largest = abs(o[i])
      }
    }
    END {
      if (bad) exit 1
      if (m != rows) { print "libiio read " m " rows of " rows; exit 1 }
      if (largest < 1) { print "no rate above 1 dps: nothing was compared"; exit 1 }
      printf "%d scans agree, largest |rate| %.2f dps, largest difference %.1e dps", m, largest, worst
    }' "$dir/$layout.ours.csv" "$dir/$layout.libiio.csv") || fail "$layout ($name): $result"
  scan=$(grep -o '[0-9]* bytes per scan' "$dir/$layout.libiio.log")
  grep -q "($scan)" "$dir/$layout.ours.csv" || fail "$layout: libiio has $scan, headingd: $(grep '^# settings' "$dir/$layout.ours.csv")"
  echo "ok: $layout ($name): libiio and headingd read the same: $result; both $scan"
done
