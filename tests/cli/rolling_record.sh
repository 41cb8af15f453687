#!/usr/bin/env bash
# The rolling recording, `run --record-dir`: files split by sample time, each replays on its own
# (zstd checks it), together they hold every sample of the run and `replay --join` gives the
# estimates of the run recorded whole; a second run (a restart) adds
# files and leaves the first run's untouched; with --record-keep-hours 0 only the file being
# written is kept; --record and --record-dir together are refused. A full disk under a rolling
# recording: tests/cli/ros2_full_disk.sh, beside a ROS 2 peer.
source "$(dirname "$0")/cli_common.sh"
cd "$dir" || exit 1

rolling_run() {  # rolling_run SEED EXTRA...: 30 s of the simulated chip, a file per 10.8 s
  local seed="$1"
  shift
  "$headingd" run --simulated-chip agv --sim-seed "$seed" --duration 30 --no-dds --state "state$seed" \
    --record-dir rec --record-split-hours 0.003 "$@" 2>"run$seed.log" || fail "run $seed: $(cat "run$seed.log")"
}
samples_of() { sed -n 's/^  samples      \([0-9]*\) over.*/\1/p' "$1"; }
# samples_in FILE...: each must pass zstd's check and replay; prints their samples together.
samples_in() {
  local f sum=0
  for f in "$@"; do
    zstd -q -t "$f" || fail "$f: zstd refuses it"
    "$headingd" replay --no-dds "$f" -o /dev/null 2>one.log || fail "replay $f: $(cat one.log)"
    sum=$((sum + $(samples_of one.log)))
  done
  echo "$sum"
}

rolling_run 1
files=(rec/headingd-*.csv.zst)
[ "${#files[@]}" -eq 3 ] || fail "expected 3 files, found: ${files[*]}"
total=$(samples_in "${files[@]}") || fail "$total"
run_samples=$(samples_of run1.log)
[ "$total" -eq "$run_samples" ] || fail "the files hold $total samples, the run had $run_samples"
grep -q "continued in $(basename "${files[1]}")" <(zstd -dc "${files[0]}") || fail "the first file does not name the next"
echo "ok: 3 files, each replays, together the run's $run_samples samples"

# The series replayed as one run (--join) gives the estimates of the same run recorded as one
# file, byte for byte: the estimator carries on across the splits as it did live.
"$headingd" run --simulated-chip agv --sim-seed 1 --duration 30 --no-dds --state state-whole --record whole.csv \
  2>whole-run.log || fail "the run recorded whole: $(cat whole-run.log)"
"$headingd" replay --no-dds whole.csv --output-rate 0 -o whole.est 2>/dev/null || fail "replay whole.csv"
"$headingd" replay --no-dds --join rec --output-rate 0 -o joined.est 2>joined.log || fail "--join: $(cat joined.log)"
cmp -s whole.est joined.est || fail "the joined series' estimates differ from the whole recording's"
grep -q "3 recordings joined" joined.log || fail "--join's summary: $(head -1 joined.log)"
"$headingd" replay --no-dds --join "${files[1]}" "${files[0]}" -o /dev/null 2>order.log
rc=$?
[ "$rc" -eq 65 ] && grep -q "is not after the last of ${files[1]}" order.log || fail "out of order: exit $rc: $(head -1 order.log)"
echo "ok: replay --join of the series equals the whole recording's estimates; out of order: 65"

sums=$(sha256sum rec/* | sort)
rolling_run 2
[ "$(ls rec | wc -l)" -eq 6 ] || fail "a second run: $(ls rec)"
grep -qF "$sums" <(sha256sum rec/* | sort) || fail "the second run changed the first run's files"
echo "ok: a restart adds its own files and leaves the earlier ones as they were"

rolling_run 3 --record-keep-hours 0
[ "$(ls rec | wc -l)" -eq 1 ] || fail "keep 0 h: $(ls rec)"
grep -q "the last of 3 started, 8 old ones deleted" run3.log || fail "keep 0 h: $(grep recording run3.log)"
echo "ok: --record-keep-hours 0 keeps only the file being written (8 deleted)"

out=$("$headingd" run --simulated-chip agv --duration 1 --no-dds --record x.csv --record-dir rec 2>&1); rc=$?
[ "$rc" -eq 64 ] && grep -q "choose one" <<<"$out" || fail "--record with --record-dir: exit $rc: $out"
echo "ok: --record with --record-dir refused (64)"
