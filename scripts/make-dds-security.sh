#!/usr/bin/env bash
# Makes a test PKI for DDS Security with openssl: a CA, identities (certificate + key) for
# `headingd`, `navigation` (may read everything and send HeadingCommands) and `observer` (may read,
# not command), and governance and permissions documents signed by the CA (S/MIME), as Fast DDS's
# builtin PKI-DH, Access-Permissions and AES-GCM-GMAC plugins want them. For tests and as a
# template: a fleet's real PKI belongs to its operator.
# Usage: scripts/make-dds-security.sh [--ros2-names] DIR
#   --ros2-names: subjects as ROS 2's sros2 names enclaves (CN=/headingd) instead of
#   CN=headingd,O=headingd test (which decides who begins a handshake: scripts/dds-security-order.sh).
set -euo pipefail
ros2_names=false
if [ "${1:-}" = "--ros2-names" ]; then
  ros2_names=true
  shift
fi
dir="${1:?usage: make-dds-security.sh [--ros2-names] DIR}"
mkdir -p "$dir"
cd "$dir"
days=3650
org="headingd test"

openssl ecparam -name prime256v1 -genkey -noout -out ca.key 2>/dev/null
openssl req -new -x509 -sha256 -key ca.key -out ca.pem -days "$days" -subj "/O=$org/CN=headingd test CA" 2>/dev/null

for who in headingd navigation observer; do
  openssl ecparam -name prime256v1 -genkey -noout -out "$who.key" 2>/dev/null
  if $ros2_names; then subject="/CN=\\/$who"; else subject="/O=$org/CN=$who"; fi
  openssl req -new -sha256 -key "$who.key" -out "$who.csr" -subj "$subject" 2>/dev/null
  openssl x509 -req -sha256 -in "$who.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -out "$who.pem" -days "$days" 2>/dev/null
  rm -f "$who.csr"
done

# Domains 0-230 in both documents: Cyclone DDS 0.10 refuses a document naming a higher id (its
# parser's bound), so a peer on Cyclone could not start with 232 (tests/cli/ros2_security.sh).
cat >governance.xml <<'XML'
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML

grant() {  # name, publish topics, subscribe topics (Fast DDS compares subjects in RFC 2253 order: CN first)
  cat <<XML
    <grant name="$1">
      <subject_name>$(if $ros2_names; then echo "CN=/$1"; else echo "CN=$1,O=$org"; fi)</subject_name>
      <validity><not_before>2020-01-01T00:00:00</not_before><not_after>2045-01-01T00:00:00</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        <publish><topics>$2</topics></publish>
        <subscribe><topics>$3</topics></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
XML
}
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  echo '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">'
  echo '  <permissions>'
  grant headingd '<topic>headingd/orientation</topic><topic>headingd/bias</topic><topic>headingd/status</topic><topic>rt/*</topic><topic>ros_discovery_info</topic>' \
    '<topic>headingd/command</topic><topic>rt/*</topic>'
  grant navigation '<topic>headingd/command</topic>' '<topic>*</topic>'
  grant observer '<topic>none</topic>' '<topic>*</topic>'
  echo '  </permissions>'
  echo '</dds>'
} >permissions.xml

for doc in governance permissions; do
  openssl smime -sign -in "$doc.xml" -text -out "$doc.p7s" -signer ca.pem -inkey ca.key 2>/dev/null
done
echo "DDS Security test PKI in $dir: ca.pem, {headingd,navigation,observer}.{pem,key}, governance.p7s, permissions.p7s"
