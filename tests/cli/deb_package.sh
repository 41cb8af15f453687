#!/usr/bin/env bash
# `cpack -G DEB` builds a package with the expected files that lintian (Debian's checker) passes without
# an error or a warning; `dpkg -i` installs it on this machine (user, groups, conffile, unit, udev rule),
# the binary and its manual page work, and removal and purge are clean.
# Needs root (CI runs as root); exits 77 (skipped) otherwise.
set -uo pipefail
build="$1"
[ "$(id -u)" -eq 0 ] || { echo "skipped: needs root"; exit 77; }
fail() { echo "FAIL: $*"; dpkg -P headingd >/dev/null 2>&1; exit 1; }
cd "$build" || exit 1
rm -f headingd_*.deb
cpack -G DEB >/dev/null 2>&1 || fail "cpack"
deb=$(ls headingd_*.deb)
listing=$(dpkg-deb -c "$deb")
for f in ./usr/bin/headingd ./usr/lib/systemd/system/headingd.service ./usr/lib/udev/rules.d/99-headingd.rules \
         ./etc/headingd/headingd.toml ./usr/share/doc/headingd/README.md ./usr/lib/headingd/iio-permissions \
         ./usr/share/headingd/headingd-iio.conf; do
  grep -q " $f\$" <<<"$listing" || fail "package lacks $f"
done
dpkg-deb -I "$deb" conffiles | grep -q '^/etc/headingd/headingd.toml$' || fail "config is not a conffile"
echo "ok: $deb holds binary, unit, udev rule, conffile, docs"

# Debian's own package checker: no error or warning (its informational tags are printed).
for f in ./usr/share/doc/headingd/copyright ./usr/share/doc/headingd/changelog.gz ./usr/share/man/man1/headingd.1.gz; do
  grep -q " $f\$" <<<"$listing" || fail "package lacks $f"
done
if command -v lintian >/dev/null; then
  findings=$(lintian --tag-display-limit 0 -I "$deb" 2>&1 | grep -v 'running with root privileges')
  grep -E '^[EW]: ' <<<"$findings" && fail "lintian: $findings"
  echo "ok: lintian finds no error or warning ($(grep -c '^I: ' <<<"$findings") informational tags)"
else
  fail "lintian is not installed (scripts/lib.sh installs it)"
fi

dpkg -i "$deb" >/dev/null 2>&1 || fail "dpkg -i: $(dpkg -i "$deb" 2>&1 | tail -3)"
/usr/bin/headingd --version | grep -q 0.1.0 || fail "installed binary does not run"
getent passwd headingd >/dev/null || fail "no headingd user"
if command -v man >/dev/null; then
  man -P cat headingd 2>/dev/null | grep -q "gyro heading daemon" || fail "man headingd: $(man -P cat headingd 2>&1 | head -3)"
fi
for g in i2c gpio iio; do id -nG headingd | grep -qw $g || fail "headingd not in $g: $(id -nG headingd)"; done
[ -x /usr/lib/headingd/iio-permissions ] || fail "the udev helper is not executable"
/usr/bin/headingd replay --no-dds /usr/share/doc/headingd/README.md -q -o /dev/null 2>/dev/null; [ $? -eq 65 ] || fail "installed replay"
out=$(/usr/bin/headingd run -c /etc/headingd/headingd.toml --no-dds --duration 1 2>&1); [ $? -eq 66 ] && grep -q "/dev/i2c-1" <<<"$out" ||
  fail "installed run with the shipped config: $out"
echo "ok: installed; user headingd in i2c, gpio and iio; the shipped config loads and names the missing /dev/i2c-1"

dpkg -r headingd >/dev/null 2>&1 || fail "dpkg -r"
[ ! -e /usr/bin/headingd ] || fail "binary left after remove"
[ -e /etc/headingd/headingd.toml ] || fail "conffile should survive remove"
dpkg -P headingd >/dev/null 2>&1 || fail "dpkg -P"
[ ! -e /etc/headingd/headingd.toml ] || fail "conffile left after purge"
dpkg -s headingd >/dev/null 2>&1 && fail "still registered"
echo "ok: removed (conffile kept) and purged cleanly"
