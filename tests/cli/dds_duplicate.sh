#!/usr/bin/env bash
# Two instances on one domain and prefix: subscribers would get both streams interleaved.
#  - on_duplicate = "warn" (default): the second logs the conflict within 5 s, naming the other
#    participant; both go on, and Status counts the other publisher;
#  - on_duplicate = "refuse": the one that started later exits 75 (EX_TEMPFAIL) within 5 s, the
#    first logs the conflict and goes on.
# Usage: dds_duplicate.sh HEADINGD SOURCE_ROOT
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for policy in warn refuse; do
  printf '[dds]\ndomain_id = 57\nprofiles_xml = "%s/config/fastdds-loopback.xml"\non_duplicate = "%s"\n' \
    "$root" "$policy" >"$dir/$policy.toml"
done

"$headingd" run --simulated-chip still --sim-realtime --duration 14 -c "$dir/warn.toml" 2>"$dir/first.err" &
first=$!
sleep 2
"$headingd" run --simulated-chip still --sim-realtime --duration 10 -c "$dir/warn.toml" 2>"$dir/second.err" &
second=$!
"$headingd" echo status -c "$dir/warn.toml" --timeout 8 >"$dir/status.txt" 2>&1
for _ in $(seq 50); do grep -q "another publisher of our topics" "$dir/second.err" && break; sleep 0.1; done
grep -q "another publisher of our topics on this domain and prefix: participant 'headingd', GUID prefix .*, started before this one" \
  "$dir/second.err" || fail "warn: the second instance did not log the conflict within 5 s: $(head -3 "$dir/second.err")"
wait "$second" || fail "warn: the second instance exited $?"
wait "$first" || fail "warn: the first instance exited $?"
grep -q "started after this one" "$dir/first.err" || fail "warn: the first instance did not log the second"
grep -qE '^status .*other_publishers=[1-9]' "$dir/status.txt" || fail "warn: Status does not count the other publisher: $(tail -1 "$dir/status.txt")"
echo "ok: warn: both instances log the conflict and run on; Status counts the other publisher"

"$headingd" run --simulated-chip still --sim-realtime --duration 12 -c "$dir/refuse.toml" 2>"$dir/first.err" &
first=$!
sleep 2
start=$(date +%s%N)
timeout 20 "$headingd" run --simulated-chip still --sim-realtime --duration 10 -c "$dir/refuse.toml" 2>"$dir/second.err"
rc=$?
elapsed_ms=$((($(date +%s%N) - start) / 1000000))
[ "$rc" -eq 75 ] || fail "refuse: the second instance exited $rc, not 75: $(head -3 "$dir/second.err")"
[ "$elapsed_ms" -le 5000 ] || fail "refuse: took ${elapsed_ms} ms"
grep -q "on_duplicate = refuse: this one stops" "$dir/second.err" || fail "refuse: no reason given"
wait "$first" || fail "refuse: the first instance exited $?"
grep -q "started after this one" "$dir/first.err" || fail "refuse: the first instance did not log the second"
echo "ok: refuse: the later instance exits 75 after ${elapsed_ms} ms; the first logs it and runs on"
