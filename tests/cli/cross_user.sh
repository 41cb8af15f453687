#!/usr/bin/env bash
# As deployed: the installed package runs `headingd run` as its system user `headingd` with the
# shipped configuration (plus a domain id of our own), and `headingd echo` subscribes as another
# user (nobody): at least 99 % of the Orientation messages it could have seen arrive (by their
# sequence numbers), and the latest GyroBias and Status. Then the same with the subscriber in an
# IPC namespace and /dev/shm of its own, as in a container that shares no IPC with the host.
# Needs root (CI runs as root); exits 77 (skipped) otherwise.
set -uo pipefail
build="$1"
[ "$(id -u)" -eq 0 ] || { echo "skipped: needs root"; exit 77; }
dir="$(mktemp -d)"
chmod 755 "$dir"
cleanup() { dpkg -P headingd >/dev/null 2>&1; rm -rf "$dir"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

cd "$build" || exit 1
rm -f headingd_*.deb
cpack -G DEB >/dev/null 2>&1 || fail "cpack"
dpkg -i headingd_*.deb >/dev/null 2>&1 || fail "dpkg -i"
sed 's/^domain_id = 0$/domain_id = 53/' /etc/headingd/headingd.toml >"$dir/headingd.toml"
grep -q '^domain_id = 53$' "$dir/headingd.toml" || fail "shipped config has no 'domain_id = 0' line to change"
chmod 644 "$dir/headingd.toml"
mkdir "$dir/state" && chown headingd:headingd "$dir/state"

# check NAME SUBSCRIBER_PREFIX...: publisher as headingd, subscriber as nobody under the prefix.
check() {
  local name="$1"
  shift
  runuser -u headingd -- /usr/bin/headingd run --simulated-chip agv --sim-realtime --duration 14 \
    -c "$dir/headingd.toml" --state "$dir/state/state" 2>"$dir/$name.run" &
  local pid=$!
  sleep 1
  "$@" runuser -u nobody -- /usr/bin/headingd echo orientation bias status -c "$dir/headingd.toml" --timeout 10 \
    >"$dir/$name.echo" 2>&1
  wait "$pid" || fail "$name: run as headingd: $(tail -3 "$dir/$name.run")"
  local seqs first last received expected
  seqs=$(sed -n 's/^orientation .* seq=\([0-9]*\) .*/\1/p' "$dir/$name.echo")
  received=$(grep -c . <<<"$seqs")
  [ -n "$seqs" ] && [ "$received" -gt 100 ] || fail "$name: $received orientation messages as nobody: $(head -3 "$dir/$name.echo")"
  first=$(head -1 <<<"$seqs")
  last=$(tail -1 <<<"$seqs")
  expected=$((last - first + 1))
  awk -v r="$received" -v e="$expected" 'BEGIN { exit !(r >= 0.99 * e) }' ||
    fail "$name: $received of $expected orientation messages"
  grep -q '^bias ' "$dir/$name.echo" || fail "$name: no GyroBias"
  grep -q '^status ' "$dir/$name.echo" || fail "$name: no Status"
  echo "ok: $name: $received of $expected orientation messages, GyroBias and Status, run as headingd, echo as nobody"
}
check other-user
check other-ipc unshare --ipc --mount bash -c 'mount -t tmpfs private-shm /dev/shm && exec "$@"' --

# For the record (not a pass/fail figure): the same with shared memory forced on, which is why it
# is off by default. Fast DDS 2.9 gives its segments to their owner only.
sed 's/^\[dds\]$/[dds]\ntransport = "shm"/' "$dir/headingd.toml" >"$dir/shm.toml" && chmod 644 "$dir/shm.toml"
runuser -u headingd -- /usr/bin/headingd run --simulated-chip agv --sim-realtime --duration 8 -c "$dir/shm.toml" \
  --state "$dir/state/state" 2>/dev/null &
pid=$!
sleep 1
shm_received=$(runuser -u nobody -- /usr/bin/headingd echo orientation -c "$dir/shm.toml" --timeout 5 2>/dev/null | grep -c '^orientation')
wait "$pid"
echo "for the record: transport = \"shm\": $shm_received orientation messages reached the other user in 5 s (about 250 sent)"
