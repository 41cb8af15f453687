#!/usr/bin/env bash
# DDS Security on: an authenticated, permitted subscriber receives; a participant without
# credentials can neither read the topics nor move the heading; an authenticated participant
# without the permission to publish commands cannot send one; the permitted one can.
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; rm -rf "$dir"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
bash "$root/scripts/make-dds-security.sh" "$dir/pki" >/dev/null || fail "making the test PKI"
config() {  # who -> config file
  printf '[dds]\ndomain_id = 50\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$root" >"$dir/$1.toml"
  [ "$1" = plain ] && return
  printf '[dds.security]\nenabled = true\nidentity_ca = "%s/ca.pem"\ncertificate = "%s/%s.pem"\nprivate_key = "%s/%s.key"\npermissions_ca = "%s/ca.pem"\ngovernance = "%s/governance.p7s"\npermissions = "%s/permissions.p7s"\n' \
    "$dir/pki" "$dir/pki" "$1" "$dir/pki" "$1" "$dir/pki" "$dir/pki" "$dir/pki" >>"$dir/$1.toml"
}
for who in headingd navigation observer plain; do config $who; done
"$headingd" simulate --scenario still --seed 3 --hours 0.0111111111 --output-dir "$dir" 2>/dev/null || fail "simulate"

"$headingd" echo orientation status --json -c "$dir/navigation.toml" --timeout 60 >"$dir/nav.out" 2>"$dir/nav.err" &
pids+=($!)
"$headingd" echo orientation status bias --json -c "$dir/plain.toml" --timeout 50 >"$dir/plain.out" 2>/dev/null &
pids+=($!)
"$headingd" replay "$dir/imu.csv" --speed realtime --wait-subscribers 15 --linger 3 -c "$dir/headingd.toml" -o /dev/null 2>"$dir/replay.err" &
replay=$!
pids+=("$replay")
sleep 6
"$headingd" command set-heading --heading-deg 45 -c "$dir/plain.toml" --wait 3 >/dev/null 2>&1 && fail "an unauthenticated command found a reader"
"$headingd" command set-heading --heading-deg 30 -c "$dir/observer.toml" >"$dir/observer.err" 2>&1 && fail "observer may not send commands"
"$headingd" command set-heading --heading-deg 90 -c "$dir/navigation.toml" --wait 15 || fail "the permitted command was not delivered"
wait "$replay" || fail "replay: $(tail -3 "$dir/replay.err")"
sleep 1
kill -INT "${pids[0]}" "${pids[1]}" 2>/dev/null; wait "${pids[0]}" "${pids[1]}" 2>/dev/null

n=$(grep -c '"topic":"orientation"' "$dir/nav.out")
[ "$n" -gt 500 ] || fail "authenticated subscriber got $n orientation messages: $(head -3 "$dir/nav.err")"
echo "ok: authenticated subscriber received $n Orientation messages (encrypted)"
[ ! -s "$dir/plain.out" ] || fail "a participant without credentials received: $(head -2 "$dir/plain.out")"
echo "ok: a participant without credentials received nothing"
last_status=$(grep '"topic":"status"' "$dir/nav.out" | tail -n 1)
grep -q '"commands_accepted":1,"commands_rejected":0' <<<"$last_status" || fail "command counts: $last_status"
heading=$(grep '"topic":"orientation"' "$dir/nav.out" | tail -n 1 | sed -n 's/.*"heading_rad":\([-0-9.e]*\).*/\1/p')
awk -v h="$heading" 'BEGIN { exit !(h > 1.5508 && h < 1.5908) }' || fail "heading $heading"
echo "ok: only the permitted command moved the heading (to $heading rad); the unauthenticated one found no reader, the observer's was refused"
