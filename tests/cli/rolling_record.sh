#!/usr/bin/env bash
# The rolling recording, `run --record-dir`: files split by sample time, each replays on its own
# (zstd checks it), together they hold every sample of the run; a second run (a restart) adds
# files and leaves the first run's untouched; with --record-keep-hours 0 only the file being
# written is kept; --record and --record-dir together are refused.
set -uo pipefail
headingd="$1"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cd "$dir" || exit 1

rolling_run() {  # rolling_run SEED EXTRA...: 30 s of the simulated chip, a file per 10.8 s
  local seed="$1"
  shift
  "$headingd" run --simulated-chip agv --sim-seed "$seed" --duration 30 --no-dds --state "state$seed" \
    --record-dir rec --record-split-hours 0.003 "$@" 2>"run$seed.log" || fail "run $seed: $(cat "run$seed.log")"
}
samples_of() { sed -n 's/^  samples      \([0-9]*\) over.*/\1/p' "$1"; }

rolling_run 1
files=(rec/headingd-*.csv.zst)
[ "${#files[@]}" -eq 3 ] || fail "expected 3 files, found: ${files[*]}"
total=0
for f in "${files[@]}"; do
  zstd -q -t "$f" || fail "$f: zstd refuses it"
  "$headingd" replay --no-dds "$f" -o /dev/null 2>one.log || fail "replay $f: $(cat one.log)"
  total=$((total + $(samples_of one.log)))
done
run_samples=$(samples_of run1.log)
[ "$total" -eq "$run_samples" ] || fail "the files hold $total samples, the run had $run_samples"
grep -q "continued in $(basename "${files[1]}")" <(zstd -dc "${files[0]}") || fail "the first file does not name the next"
echo "ok: 3 files, each replays, together the run's $run_samples samples"

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
