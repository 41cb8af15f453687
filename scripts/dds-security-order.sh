#!/usr/bin/env bash
# Which of two DDS Security participants starts their handshake, from their identity certificates.
# Under DDS Security a participant's GUID prefix begins with the SHA-256 of its certificate's
# subject (DER), and the participant with the lower GUID begins the handshake (Fast DDS 2.9,
# PKIDH.cpp; Cyclone DDS alike). It matters across implementations: the one that begins chooses
# the key agreement, and Debian 12's Fast DDS 2.9.1 always chooses DH+MODP-2048-256, whose public
# key Cyclone DDS 0.10 cannot read (Fast-DDS issue 3802; Fast DDS 3.2 begins with ECDH). So
# headingd meets a Cyclone DDS peer only where the peer begins.
# Usage: scripts/dds-security-order.sh HEADINGD_CERT PEER_CERT...
#   prints, for each peer, "PEER begins" or "headingd begins", with the digests.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: dds-security-order.sh HEADINGD_CERT PEER_CERT..." >&2; exit 64; }

# The first 12 hex digits of the SHA-256 of the certificate's subject, as DER (what
# X509_NAME_digest hashes): the subject is the tbsCertificate's fifth element, or sixth after an
# explicit version.
subject_digest() {
  local der offset header length
  der=$(mktemp)
  openssl x509 -in "$1" -outform DER -out "$der" || { rm -f "$der"; return 1; }
  read -r offset header length < <(openssl asn1parse -inform DER -in "$der" | awk -F'[:= ]+' '
    /:d=2 / {
      n++
      if (n == 1) want = ($0 ~ /cont \[ 0 \]/) ? 6 : 5
      if (n == want) {
        for (i = 1; i <= NF; i++) { if ($i == "hl") hl = $(i + 1); if ($i == "l") l = $(i + 1) }
        print $2, hl, l
        exit
      }
    }')
  [ -n "${length:-}" ] || { echo "dds-security-order.sh: no subject found in $1" >&2; rm -f "$der"; return 1; }
  dd if="$der" bs=1 skip="$offset" count=$((header + length)) 2>/dev/null | sha256sum | cut -c1-12
  rm -f "$der"
}

ours=$(subject_digest "$1")
shift
for peer in "$@"; do
  theirs=$(subject_digest "$peer")
  if [[ "$theirs" < "$ours" ]]; then
    echo "$peer begins (its subject digest $theirs, headingd's $ours)"
  else
    echo "headingd begins (its subject digest $ours, $peer's $theirs)"
  fi
done
