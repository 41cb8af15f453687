#!/usr/bin/env bash
# DDS Security across two implementations: headingd (Fast DDS) with the PKI and documents that
# scripts/make-dds-security.sh makes, and the Cyclone DDS ROS 2 peer (tests/interop/ros_peer.c)
# with Cyclone's own builtin security plugins, configured from the same files:
#  - the peer as `navigation` authenticates, and reads the Imu, /diagnostics and the Orientation,
#    encrypted, at the publishing rate; its heading fix is taken;
#  - the peer as `observer` is refused a command writer by Cyclone's reading of our permissions;
#  - the same peer without credentials reads nothing;
#  - with subjects named as ROS 2's sros2 names enclaves (CN=/navigation), headingd's GUID is the
#    lower and it begins the handshake, with DH+MODP-2048-256 (all Debian 12's Fast DDS 2.9.1
#    offers), whose key Cyclone cannot read: the peer reads nothing and says why. A known limit of
#    Fast DDS 2.9 (Fast-DDS issue 3802), checked so that a newer Fast DDS shows up here;
#    scripts/dds-security-order.sh tells an integrator which side begins.
# Cyclone 0.10 refuses a governance or permissions document naming a domain id above 230 (its
# parser's bound), which our documents did until 2026-12-07 (232): a secured Cyclone participant
# could not even start with them.
source "$(dirname "$0")/ros2_common.sh"
domain=69
pki="$dir/pki"
bash "$root/scripts/make-dds-security.sh" "$pki" >/dev/null || fail "making the test PKI"
order=$(bash "$root/scripts/dds-security-order.sh" "$pki/headingd.pem" "$pki/navigation.pem") || fail "dds-security-order.sh: $order"
grep -q "navigation.pem begins" <<<"$order" || fail "with our subjects the Cyclone peer should begin: $order"
plugin=$(find /usr/lib -name libdds_security_auth.so -print -quit)
[ -n "$plugin" ] || fail "Cyclone DDS's security plugins are not installed (libddsc0debian)"
plugins=$(dirname "$plugin")

headingd_config() {  # pki: headingd's configuration with that PKI's security
  printf '[dds]\ndomain_id = %d\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n[dds.security]\nenabled = true\nidentity_ca = "%s/ca.pem"\ncertificate = "%s/headingd.pem"\nprivate_key = "%s/headingd.key"\npermissions_ca = "%s/ca.pem"\ngovernance = "%s/governance.p7s"\npermissions = "%s/permissions.p7s"\n' \
    "$domain" "$root" "$1" "$1" "$1" "$1" "$1" "$1"
}
headingd_config "$pki" >"$dir/headingd.toml"

cyclone_config() {  # who [pki]: that identity's security, a second document beside the loopback one
  local pki="${2:-$pki}"
  cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<CycloneDDS xmlns="https://cdds.io/config">
  <Domain Id="any">
    <Security>
      <Authentication>
        <Library path="$plugins/libdds_security_auth.so"/>
        <IdentityCA>file:$pki/ca.pem</IdentityCA>
        <IdentityCertificate>file:$pki/$1.pem</IdentityCertificate>
        <PrivateKey>file:$pki/$1.key</PrivateKey>
      </Authentication>
      <AccessControl>
        <Library path="$plugins/libdds_security_ac.so"/>
        <PermissionsCA>file:$pki/ca.pem</PermissionsCA>
        <Governance>file:$pki/governance.p7s</Governance>
        <Permissions>file:$pki/permissions.p7s</Permissions>
      </AccessControl>
      <Cryptographic>
        <Library path="$plugins/libdds_security_crypto.so"/>
      </Cryptographic>
    </Security>
  </Domain>
</CycloneDDS>
XML
}
# Cyclone reads a comma-separated list of documents: the loopback settings all peers share
# (tests/interop/cyclone.xml, from ros2_common.sh), then the identity's.
loopback="$CYCLONEDDS_URI"
cyclone_config navigation >"$dir/navigation.xml"
cyclone_config observer >"$dir/observer.xml"

CYCLONEDDS_URI="$loopback,file://$dir/navigation.xml" "$peer" listen $domain 24 >"$dir/navigation.out" 2>"$dir/navigation.err" &
pids+=($!)
"$peer" listen $domain 24 >"$dir/plain.out" 2>"$dir/plain.err" &  # ros2_common.sh's plain loopback configuration
pids+=($!)
sleep 1
"$headingd" run --simulated-chip still --sim-realtime --duration 20 -c "$dir/headingd.toml" -o /dev/null 2>"$dir/run.err" &
run_pid=$!
pids+=("$run_pid")
sleep 8
CYCLONEDDS_URI="$loopback,file://$dir/observer.xml" "$peer" set-heading $domain 2.0 0 >"$dir/observer.cmd" 2>&1 &&
  fail "the observer, who may not publish commands, sent one: $(cat "$dir/observer.cmd")"
grep -q "headingd/command writer: " "$dir/observer.cmd" ||
  fail "the observer's command failed for another reason than its permissions: $(cat "$dir/observer.cmd")"
CYCLONEDDS_URI="$loopback,file://$dir/navigation.xml" "$peer" set-heading $domain 1.0 0 >"$dir/navigation.cmd" 2>&1 ||
  fail "navigation's heading fix was not sent: $(cat "$dir/navigation.cmd")"
wait "$run_pid" || fail "headingd run: $(tail -3 "$dir/run.err")"
for p in "${pids[@]:0:2}"; do wait "$p"; done

grep -q '^end ' "$dir/navigation.out" || fail "the secured peer did not run: $(head -3 "$dir/navigation.err")"
imu=$(grep -c '^imu_sensor_data ' "$dir/navigation.out")
diagnostics=$(grep -c '^diagnostic ' "$dir/navigation.out")
orientation=$(grep -c '^orientation ' "$dir/navigation.out")
[ "$imu" -gt 600 ] && [ "$diagnostics" -gt 10 ] && [ "$orientation" -gt 600 ] ||
  fail "the secured peer read $imu Imu, $diagnostics /diagnostics, $orientation Orientation messages"
echo "ok: Cyclone DDS as navigation (its own security plugins, our PKI and documents) read $imu Imu, $diagnostics /diagnostics and $orientation Orientation messages from headingd on Fast DDS, encrypted"
last=$(grep '^orientation ' "$dir/navigation.out" | tail -1)
heading=$(sed -n 's/.* heading=\([^ ]*\) .*/\1/p' <<<"$last")
grep -q ' fixes=1 ' <<<"$last" && awk -v h="$heading" 'BEGIN { exit !(h > 0.99 && h < 1.01) }' ||
  fail "navigation's fix (1.0 rad) did not set the heading: $last"
echo "ok: navigation's heading fix over Cyclone set the heading ($heading rad, fixes=1); Cyclone refused the observer a command writer: $(tail -1 "$dir/observer.cmd")"
grep -q '^end ' "$dir/plain.out" || fail "the plain peer did not run: $(head -3 "$dir/plain.err")"
if grep -Eq '^(imu_|diagnostic|orientation|temperature|discovery)' "$dir/plain.out"; then
  fail "a Cyclone participant without credentials read: $(grep -E '^(imu_|diagnostic|orientation)' "$dir/plain.out" | head -2)"
fi
echo "ok: the same peer without credentials read nothing"

# Subjects as sros2 names them: headingd begins, and Cyclone cannot read its DH key.
pki2="$dir/pki-ros2"
bash "$root/scripts/make-dds-security.sh" --ros2-names "$pki2" >/dev/null || fail "making the sros2-style PKI"
order=$(bash "$root/scripts/dds-security-order.sh" "$pki2/headingd.pem" "$pki2/navigation.pem") || fail "dds-security-order.sh: $order"
grep -q "^headingd begins" <<<"$order" || fail "with sros2-style subjects headingd should begin: $order"
headingd_config "$pki2" >"$dir/headingd-ros2.toml"
cyclone_config navigation "$pki2" >"$dir/navigation-ros2.xml"
CYCLONEDDS_URI="$loopback,file://$dir/navigation-ros2.xml" "$peer" listen $domain 12 >"$dir/ros2names.out" 2>"$dir/ros2names.err" &
listener=$!
pids+=("$listener")
sleep 1
"$headingd" run --simulated-chip still --sim-realtime --duration 9 -c "$dir/headingd-ros2.toml" -o /dev/null 2>"$dir/run-ros2.err" ||
  fail "headingd run with the sros2-style PKI: $(tail -3 "$dir/run-ros2.err")"
wait "$listener"
if grep -q '^imu_' "$dir/ros2names.out"; then
  fail "headingd began the handshake and Cyclone read it: Fast DDS now offers ECDH? update README and dds-security-order.sh ($order)"
fi
grep -q "Failed to convert octet sequence to ASN1 integer" "$dir/ros2names.err" ||
  fail "the Cyclone peer read nothing, but not for the known reason: $(head -3 "$dir/ros2names.err")"
echo "ok: known limit: with sros2-style subjects $order, and Cyclone cannot read Fast DDS 2.9's DH+MODP key (nothing read)"
