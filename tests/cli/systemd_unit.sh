#!/usr/bin/env bash
# The unit passes `systemd-analyze verify` and rates an exposure of 2.0 or lower with
# `systemd-analyze security --offline=yes`. ExecStart points at the built binary for the check.
set -uo pipefail
headingd="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
sed "s#/usr/bin/headingd#$headingd#" "$root/systemd/headingd.service" >"$dir/headingd.service"
out=$(systemd-analyze verify "$dir/headingd.service" 2>&1)
rc=$?
# verify complains about the example man page and missing users on a build machine; nothing else may.
problems=$(grep -v -E "man:headingd|Failed to resolve|Unit configured to use|^$" <<<"$out")
if [ "$rc" -ne 0 ] && [ -n "$problems" ]; then
  echo "FAIL: systemd-analyze verify: $out"; exit 1
fi
[ -z "$problems" ] || { echo "FAIL: systemd-analyze verify said: $problems"; exit 1; }
echo "ok: systemd-analyze verify"
security=$(systemd-analyze security --offline=yes "$dir/headingd.service" 2>&1)
score=$(sed -n 's/.*Overall exposure level for headingd.service: \([0-9.]*\).*/\1/p' <<<"$security")
[ -n "$score" ] || { echo "FAIL: no exposure score: $security"; exit 1; }
echo "exposure: $score"
awk -v s="$score" 'BEGIN { exit !(s <= 2.0) }' || { echo "FAIL: exposure $score above 2.0"; grep "✗" <<<"$security" | head -20; exit 1; }
echo "ok: exposure $score <= 2.0"
grep -q 'MODE="0660"' "$root/config/99-headingd.rules" && ! grep -v '^#' "$root/config/99-headingd.rules" | grep -q '0666' ||
  { echo "FAIL: udev rule modes"; exit 1; }
echo "ok: udev rules give 0660 to groups i2c and gpio"
grep -q '^SUBSYSTEM=="iio", KERNEL=="iio:device\[0-9\]\*", GROUP="iio", MODE="0660"' "$root/config/99-headingd.rules" ||
  { echo "FAIL: no udev rule for IIO devices"; exit 1; }
# The IIO drop-in: the unit with it still verifies, and only ProtectKernelTunables changes.
mkdir -p "$dir/iio" && cat "$dir/headingd.service" "$root/systemd/headingd-iio.conf" >"$dir/iio/headingd.service"
out=$(systemd-analyze verify "$dir/iio/headingd.service" 2>&1)
problems=$(grep -v -E "man:headingd|Failed to resolve|Unit configured to use|^$" <<<"$out")
[ -z "$problems" ] || { echo "FAIL: verify with the IIO drop-in: $problems"; exit 1; }
iio_score=$(systemd-analyze security --offline=yes "$dir/iio/headingd.service" 2>&1 |
  sed -n 's/.*Overall exposure level for headingd.service: \([0-9.]*\).*/\1/p')
echo "ok: with the IIO drop-in the unit verifies; exposure $iio_score (without: $score)"
