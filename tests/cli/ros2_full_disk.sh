#!/usr/bin/env bash
# A disk that fills and has room again under a live rolling recording, watched by a ROS 2 peer
# on another DDS implementation (tests/interop/ros_peer.c, Cyclone DDS): the kernel's own ENOSPC
# from a tmpfs of 256 kB in a mount namespace made here, all but 8 kB of it taken by a filler.
#  - the first file is lost when the disk is full (it keeps what fit), the Imu goes on;
#  - the peer's /diagnostics: the sensor WARN, naming the output, with file_outputs_failing=1,
#    while nothing is written; OK again with file_outputs_failing=0 and file_outputs_dropped=1
#    once the new file (one split, 7.2 s of samples, after the loss) has written 10 s;
#  - the files written after the disk had room pass zstd's check and replay; the last one's
#    closing line counts the run's samples; `replay --join` replays what the lost file kept and
#    everything after it, naming the damage (65).
source "$(dirname "$0")/ros2_common.sh"
domain=68
cd "$dir" || exit 1
printf '[dds]\ndomain_id = %d\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$domain" "$root" >dds.toml
samples_of() { sed -n 's/^  samples      \([0-9]*\) over.*/\1/p' "$1"; }

"$peer" listen $domain 38 >peer.out 2>peer.err &
pids+=($!)
sleep 1
# shellcheck disable=SC2016
unshare --mount --propagation private bash -c '
  mkdir -p full && mount -t tmpfs -o size=256k rolling-test full || exit 90
  dd if=/dev/zero of=full/filler bs=1k count=248 status=none 2>/dev/null
  "$1" run -c dds.toml --simulated-chip agv --sim-seed 4 --sim-realtime --duration 32 --state state-full \
    --record-dir full/rec --record-split-hours 0.002 2>full.log &
  pid=$!
  for _ in $(seq 200); do grep -q "could not be written" full.log && break; sleep 0.1; done
  rm -f full/filler
  wait "$pid"; rc=$?
  cp -r full/rec rec-full
  exit "$rc"' -- "$headingd"
rc=$?
wait "${pids[0]}"
[ "$rc" -ne 90 ] || fail "cannot mount a tmpfs (needs root)"
[ "$rc" -eq 0 ] || fail "full disk: exit $rc: $(tail -5 full.log)"
grep -q "No space left on device" full.log || fail "the disk never filled: $(grep -i record full.log)"
grep -q "recording again in" full.log || fail "the series did not resume: $(grep -i record full.log)"
grep -q "file output(s) dropped, the run went on publishing" full.log || fail "no drop in the summary"
grep -q "1 lost to write errors" full.log || fail "the summary does not count the lost file: $(grep recording full.log)"

# What the peer saw: the sensor's status over the run, and the Imu through it.
awk '
  function val(line, name,   m) { return match(line, "[|;]" name "=[^;|]*") ? substr(line, RSTART + length(name) + 2, RLENGTH - length(name) - 2) : "" }
  /^diagnostic .*name=headingd: sensor\|/ {
    split($2, s, "="); t = s[2] + 0; split($3, l, "="); level = l[2] + 0
    failing = val($0, "file_outputs_failing"); dropped = val($0, "file_outputs_dropped")
    if (failing == "1") {
      if (level != 1 || $0 !~ /message=a file output cannot be written: /) { print "failing but: " $0; bad = 1 }
      if (!warn_from) warn_from = t
      warn_to = t
    } else if (warn_from && failing == "0") {
      if (dropped != "1") { print "after the loss file_outputs_dropped=" dropped; bad = 1 }
      if (level == 0 && !ok_at) ok_at = t
    }
  }
  /^imu_sensor_data/ { split($2, s, "="); stamps[++n] = s[2] + 0 }
  END {
    if (!warn_from) { print "the peer never saw file_outputs_failing=1"; exit 1 }
    if (!ok_at) { print "the peer never saw the sensor OK again after the loss"; exit 1 }
    for (i = 1; i <= n; ++i) {
      if (stamps[i] >= warn_from && stamps[i] <= ok_at) ++during
      if (i > 1 && stamps[i] - stamps[i - 1] > gap) gap = stamps[i] - stamps[i - 1]
    }
    rate = (n - 1) / (stamps[n] - stamps[1])
    printf "peer: sensor WARN with file_outputs_failing=1 for %.1f s, OK %.1f s after it began; %d Imu messages in between (%.1f Hz; %.1f Hz over the run), longest gap %.3f s\n", warn_to - warn_from, ok_at - warn_from, during, during / (ok_at - warn_from), rate, gap
    if (warn_to - warn_from < 5) { print "WARN for under 5 s"; bad = 1 }
    if (during < rate * (ok_at - warn_from) * 0.9) { print "the Imu thinned while the disk was full"; bad = 1 }
    if (gap > 0.5) { print "the Imu stopped for " gap " s"; bad = 1 }
    exit bad
  }' peer.out || fail "what the peer saw over the full disk"

files=(rec-full/headingd-*.csv.zst)
[ "${#files[@]}" -ge 2 ] || fail "expected the lost file and the resumed ones: ${files[*]}"
[ -s "${files[0]}" ] || fail "the lost file holds nothing"
resumed=0
for f in "${files[@]:1}"; do
  zstd -q -t "$f" || fail "$f: zstd refuses it"
  "$headingd" replay --no-dds "$f" -o /dev/null 2>one.log || fail "replay $f: $(cat one.log)"
  resumed=$((resumed + $(samples_of one.log)))
done
[ "$resumed" -gt 3000 ] || fail "the resumed files hold $resumed samples"
zstd -dc "${files[-1]}" | tail -1 | grep -q "the run: [0-9]* samples, 0 lost; this file: [0-9]*" ||
  fail "the last file's closing line: $(zstd -dc "${files[-1]}" | tail -1)"
echo "ok: a full disk lost one file; after room came back the series resumed ($resumed samples in $((${#files[@]} - 1)) files), exit 0"

"$headingd" replay --no-dds --join rec-full --output-rate 0 -o full.est 2>full-join.log
rc=$?
[ "$rc" -eq 65 ] && grep -qF -- "--join: ${files[0]}" full-join.log || fail "--join over the lost file: exit $rc: $(cat full-join.log)"
rows=$(grep -c '^[0-9]' full.est)
[ "$rows" -gt "$resumed" ] || fail "--join gave $rows rows, the resumed files alone hold $resumed"
echo "ok: --join over the lost file: its $((rows - resumed)) samples and the rest replayed, the damage named, exit 65"
