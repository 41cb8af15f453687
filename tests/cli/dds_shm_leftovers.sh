#!/usr/bin/env bash
# Nothing of ours stays in /dev/shm (shared memory on, in a /dev/shm of the test's own):
#  - `headingd replay ... | head -1`: the closed pipe ends the run quietly (exit 0, no error),
#    through the usual shutdown, and leaves nothing;
#  - after a SIGKILL, the next start removes the dead process's segments.
# Usage: dds_shm_leftovers.sh HEADINGD SOURCE_ROOT
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
printf '[dds]\ndomain_id = 55\ntransport = "shm"\nprofiles_xml = "%s/config/fastdds-loopback-shm.xml"\n' "$root" >"$dir/cfg.toml"
# shellcheck disable=SC2016
unshare --mount --propagation private bash -s -- "$headingd" "$root" "$dir" <<'SCRIPT'
set -uo pipefail
headingd="$1"; root="$2"; dir="$3"
fail() { echo "FAIL: $*"; exit 1; }
mount -t tmpfs headingd-test /dev/shm || fail "cannot mount a private /dev/shm (needs root)"

"$headingd" replay "$root/tests/data/agv-1min/imu.csv" --output-rate 0 --speed 20 -c "$dir/cfg.toml" 2>"$dir/pipe.err" | head -1 >"$dir/first"
rc=${PIPESTATUS[0]}
[ "$rc" -eq 0 ] || fail "replay | head -1: exit $rc: $(cat "$dir/pipe.err")"
grep -q '^time_s,heading_deg' "$dir/first" || fail "head got: $(cat "$dir/first")"
grep -q "output closed by its reader" "$dir/pipe.err" || fail "summary does not say why it ended: $(cat "$dir/pipe.err")"
! grep -qiE "error|cannot|broken" "$dir/pipe.err" || fail "not quiet: $(cat "$dir/pipe.err")"
[ -z "$(ls -A /dev/shm)" ] || fail "replay | head -1 left: $(ls -A /dev/shm)"
echo "ok: replay | head -1 exits 0 quietly and leaves nothing in /dev/shm"

"$headingd" run --simulated-chip still --sim-realtime -c "$dir/cfg.toml" 2>/dev/null &
pid=$!
sleep 2
kill -KILL "$pid"
wait "$pid" 2>/dev/null
left=$(ls -A /dev/shm | wc -l)
[ "$left" -gt 0 ] || fail "SIGKILL left nothing: the test proves nothing"
"$headingd" run --simulated-chip still --duration 4 -c "$dir/cfg.toml" 2>"$dir/next.err" ||
  fail "next start: $(tail -3 "$dir/next.err")"
grep -q "removed $left shared-memory files" "$dir/next.err" || fail "next start did not remove the $left files: $(head -3 "$dir/next.err")"
[ -z "$(ls -A /dev/shm)" ] || fail "left after the next run: $(ls -A /dev/shm)"
echo "ok: the $left files a SIGKILL left were removed by the next start; nothing left after it"
SCRIPT
