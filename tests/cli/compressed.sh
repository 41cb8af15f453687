#!/usr/bin/env bash
# Compressed recordings, against the reference tools: a recording compressed by the `zstd` and
# `gzip` programs replays (and feeds allan and score) exactly as the plain file; `run --record
# X.csv.zst` writes a file `zstd -t` accepts and `zstd -d` turns into the plain recording; a
# truncated or corrupted file is an error naming the file and the uncompressed line (exit 65),
# with the estimates before it kept.
source "$(dirname "$0")/cli_common.sh"

"$headingd" simulate --scenario agv --seed 3 --hours 0.2 --output-dir "$dir/sim" >/dev/null || fail "simulate"
plain="$dir/sim/imu.csv"
zstd -q -3 "$plain" -o "$dir/imu.csv.zst" && gzip -c "$plain" >"$dir/imu.csv.gz" || fail "compressing with zstd/gzip"
cp "$dir/imu.csv.zst" "$dir/imu-named-plainly.csv"  # the magic number decides, not the name
"$headingd" replay --no-dds "$plain" --output-rate 0 -o "$dir/plain.est" --quiet || fail "plain replay"
for f in imu.csv.zst imu.csv.gz imu-named-plainly.csv; do
  "$headingd" replay --no-dds "$dir/$f" --output-rate 0 -o "$dir/$f.est" --quiet 2>"$dir/err" || fail "replay $f: $(cat "$dir/err")"
  cmp -s "$dir/plain.est" "$dir/$f.est" || fail "$f replays differently from the plain file"
done
"$headingd" replay --no-dds - --output-rate 0 -o "$dir/pipe.est" --quiet <"$dir/imu.csv.zst" 2>"$dir/err" &&
  cmp -s "$dir/plain.est" "$dir/pipe.est" || fail "a .zst on standard input ('-') replays differently: $(cat "$dir/err")"
echo "ok: zstd and gzip recordings (made by the zstd and gzip programs) replay byte for byte as the plain one, from a file or on standard input ($(($(wc -l <"$dir/plain.est") - 1)) rows)"

"$headingd" allan "$plain" --axis z >"$dir/allan.plain" 2>&1 || fail "allan plain"
"$headingd" allan "$dir/imu.csv.gz" --axis z >"$dir/allan.gz" 2>&1 || fail "allan gz"
cmp -s <(grep -v imu "$dir/allan.plain") <(grep -v imu "$dir/allan.gz") || fail "allan differs on the gz file"
zstd -q "$dir/sim/truth.csv" -o "$dir/truth.csv.zst"
gzip -c "$dir/plain.est" >"$dir/plain.est.gz"
"$headingd" score "$dir/plain.est" "$dir/sim/truth.csv" --label same >"$dir/score.plain" || fail "score plain"
"$headingd" score "$dir/plain.est.gz" "$dir/truth.csv.zst" --label same >"$dir/score.z" || fail "score compressed"
cmp -s "$dir/score.plain" "$dir/score.z" || fail "score differs on compressed inputs"
echo "ok: allan and score read compressed files the same"

# Writing: run --record to .csv.zst, checked by the zstd program, replays to the live estimates.
"$headingd" run --simulated-chip agv --sim-seed 4 --duration 60 --no-dds --output "$dir/live.csv" --output-rate 0 \
  --record "$dir/rec.csv.zst" 2>"$dir/run.log" || fail "run --record .zst: $(cat "$dir/run.log")"
zstd -q -t "$dir/rec.csv.zst" || fail "zstd -t refuses our file"
zstd -q -d -c "$dir/rec.csv.zst" >"$dir/rec.csv" || fail "zstd -d"
head -1 "$dir/rec.csv" | grep -q "^# sensor: ST L3GD20H" || fail "the decompressed recording's head: $(head -1 "$dir/rec.csv")"
"$headingd" replay --no-dds "$dir/rec.csv.zst" --output-rate 0 -o "$dir/rec.est" --quiet || fail "replay of our .zst"
cmp -s "$dir/live.csv" "$dir/rec.est" || fail "the .zst recording does not replay to the live estimates"
echo "ok: run --record X.csv.zst: zstd -t accepts it, $(($(wc -l <"$dir/rec.csv"))) lines, replays to the live estimates byte for byte"

# Damage: truncated in the middle, and bytes flipped: exit 65, file and line named, estimates kept.
size=$(stat -c %s "$dir/imu.csv.zst")
head -c $((size / 2)) "$dir/imu.csv.zst" >"$dir/cut.csv.zst"
out=$("$headingd" replay --no-dds "$dir/cut.csv.zst" --output-rate 0 -o "$dir/cut.est" 2>&1); rc=$?
[ "$rc" -eq 65 ] && grep -q "cut.csv.zst:[0-9]*: truncated zstd stream" <<<"$out" || fail "truncated .zst: exit $rc: $out"
[ "$(wc -l <"$dir/cut.est")" -gt 1000 ] || fail "estimates before the cut were not kept"
echo "ok: truncated .zst -> exit 65: $(head -1 <<<"$out")"
head -c $((size / 2)) "$dir/imu.csv.gz" >"$dir/cut.csv.gz"
out=$("$headingd" replay --no-dds "$dir/cut.csv.gz" --output-rate 0 -o "$dir/cutgz.est" 2>&1); rc=$?
[ "$rc" -eq 65 ] && grep -q "cut.csv.gz:[0-9]*: truncated gzip stream" <<<"$out" || fail "truncated .gz: exit $rc: $out"
echo "ok: truncated .gz -> exit 65: $(head -1 <<<"$out")"
cp "$dir/imu.csv.zst" "$dir/flipped.csv.zst"
printf '\xff\x00\xff\x00\xff\x00\xff\x00' | dd of="$dir/flipped.csv.zst" bs=1 seek=$((size / 3)) conv=notrunc status=none
out=$("$headingd" replay --no-dds "$dir/flipped.csv.zst" --output-rate 0 -o "$dir/flip.est" 2>&1); rc=$?
[ "$rc" -eq 65 ] && grep -q "flipped.csv.zst:[0-9]*: " <<<"$out" || fail "flipped bytes: exit $rc: $out"
[ "$(wc -l <"$dir/flip.est")" -gt 1000 ] || fail "estimates before the damage were not kept"
echo "ok: flipped bytes in a .zst -> exit 65: $(head -1 <<<"$out")"

# A bomb: 300 MB of newlines compress to a few KB; the reader refuses the run of blank lines at once
# instead of reading them for seconds (found by fuzz_csv: 649 bytes of zstd, 9.5 million blank lines).
head -c 300000000 /dev/zero | tr '\0' '\n' | zstd -q -o "$dir/bomb.csv.zst"
start=$(date +%s%N)
out=$("$headingd" replay --no-dds "$dir/bomb.csv.zst" -o "$dir/bomb.est" 2>&1); rc=$?
ms=$((($(date +%s%N) - start) / 1000000))
[ "$rc" -eq 65 ] && grep -q "bomb.csv.zst:100001: more than 100000 blank or comment lines in a row" <<<"$out" ||
  fail "newline bomb: exit $rc: $out"
echo "ok: a $(stat -c %s "$dir/bomb.csv.zst")-byte .zst of 300 MB of newlines -> exit 65 after ${ms} ms: $out"
