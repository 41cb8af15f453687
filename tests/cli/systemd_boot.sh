#!/usr/bin/env bash
# The package's unit under a real systemd — Debian 12's, as PID 1 of a container that
# systemd-nspawn boots from this machine's own root (a throw-away overlay, a network of its own,
# only loopback) — rather than under our own notify listener:
#  A. installed with dpkg and started with the shipped configuration on a machine without the
#     sensor: the error reaches the journal at priority err, the unit tries again every 5 s
#     and starts by itself once the sensor is there;
#  B. a configuration error, and a wrong option in ExecStart: no restart (a restart cannot mend
#     them), the error at priority err;
#  C. the simulated chip (a drop-in replaces ExecStart, every other setting of the unit kept):
#     `systemctl start` returns once READY=1 came, STATUS= and the watchdog pings reach systemd,
#     a Cyclone DDS ROS 2 peer in the container's network reads Imu, Orientation and
#     /diagnostics through the unit's sandbox (system-call filter, address families, no
#     capabilities), `systemctl reload` reloads, `systemctl stop` ends it with status 0 and the
#     state and a rolling recording are written as user headingd under the state directory; a
#     second start restores the state;
#  D. a sensor that dies while running: the watchdog kills the daemon and systemd restarts it;
#  E. [sensor] kind = "iio" on a fake IIO tree put where the kernel's would be (/sys/bus/iio under a
#     tmpfs in the container, /dev/iio:device0), its permissions set as the udev rule and the
#     packaged helper set them: without the packaged drop-in the unit's read-only /sys stops it
#     (exit 78, not restarted) with a message that names the drop-in; with it, it runs;
#  F. the package's own scripts with the service running: an upgrade (the same package again)
#     restarts it onto the new binary, removal stops it, purge removes the state.
# Needs root and systemd-nspawn (scripts/lib.sh installs systemd-container); exits 77 otherwise.
# Arguments: BUILD_DIR SOURCE_DIR ROS_PEER IIO_FEEDER
set -uo pipefail
build="$1"
root="$2"
peer="$3"
feeder="$4"
[ "$(id -u)" -eq 0 ] || { echo "skipped: needs root"; exit 77; }
command -v systemd-nspawn >/dev/null || { echo "skipped: no systemd-nspawn (package systemd-container)"; exit 77; }
# The bind mount of / below lives and dies with a mount namespace of this test's own.
if [ -z "${HEADINGD_OWN_MOUNTS:-}" ]; then
  exec env HEADINGD_OWN_MOUNTS=1 unshare --mount --propagation private bash "$0" "$@"
fi
domain=71
dir="$(mktemp -d)"
nspawn_pid=
cleanup() {
  if [ -n "$nspawn_pid" ]; then
    kill "$nspawn_pid" 2>/dev/null # nspawn asks the container's systemd to power off
    for _ in $(seq 50); do kill -0 "$nspawn_pid" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$nspawn_pid" 2>/dev/null
    [ -n "${leader:-}" ] && kill -9 "$leader" 2>/dev/null # the container's PID 1, and with it all inside
  fi
  # shellcheck disable=SC2046  # job ids, one word each
  kill $(jobs -p) 2>/dev/null # the IIO feeder's nsenter, when a check failed while it ran
  umount "$dir/root" 2>/dev/null
  if [ -n "${KEEP:-}" ]; then echo "kept $dir"; else rm -rf "$dir"; fi
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  [ -n "${leader:-}" ] && nsenter -t "$leader" -a journalctl -u headingd --no-pager -n 15 -o cat 2>/dev/null
  exit 1
}
mkdir -p "$dir/root" "$dir/share"
(cd "$build" && cpack -G DEB -B "$dir/deb" >/dev/null 2>&1) || fail "cpack"
cp "$dir"/deb/headingd_*.deb "$dir/share/headingd.deb" || fail "no package built"
cp "$root/config/fastdds-loopback.xml" "$dir/share/" || fail "no loopback profile"
mount --bind / "$dir/root" || fail "bind mount of /"

# Boot. The overlay keeps every write in memory; --private-network leaves only loopback.
systemd-nspawn --quiet --register=no --keep-unit --link-journal=no --volatile=overlay --private-network \
  --console=passive -D "$dir/root" --bind-ro="$dir/share:/mnt/headingd-check" --bind-ro="$(dirname "$feeder"):/mnt/headingd-feeder" --boot >"$dir/boot.log" 2>&1 &
nspawn_pid=$!
leader=
for _ in $(seq 100); do
  leader=$(pgrep -P "$nspawn_pid" | head -1)
  [ -n "$leader" ] && nsenter -t "$leader" -a true 2>/dev/null && break
  leader=
  sleep 0.2
done
[ -n "$leader" ] || fail "the container did not start: $(tail -5 "$dir/boot.log")"
inside() { nsenter -t "$leader" -a "$@"; }
# PID 1 listens on its bus a moment after it starts; then wait for the boot to finish.
for _ in $(seq 150); do
  inside test -S /run/systemd/private 2>/dev/null && break
  sleep 0.2
done
state=$(inside timeout 90 systemctl is-system-running --wait 2>&1)
case "$state" in running | degraded) ;; *) fail "the container's systemd did not finish booting: $state" ;; esac
echo "ok: booted systemd $(inside systemctl --version | sed -n '1s/systemd \([0-9]*\).*/\1/p') as PID 1 of a container ($state)"

inside dpkg -i /mnt/headingd-check/headingd.deb >"$dir/dpkg.log" 2>&1 || fail "dpkg -i in the container: $(tail -3 "$dir/dpkg.log")"
# The asan preset packages a sanitized binary: the unit gets the suite's sanitizer options (the
# service does not inherit ours), less LeakSanitizer, which stops the world through ptrace, which
# the unit's system-call filter refuses (~@debug); its fatal error turned every exit into 1.
# Leaks are left to the rest of the suite.
if grep -qa __asan_init "$build/app/headingd"; then
  inside mkdir -p /etc/systemd/system/headingd.service.d
  printf '[Service]\nEnvironment="ASAN_OPTIONS=%s:detect_leaks=0" "UBSAN_OPTIONS=%s"\n' "${ASAN_OPTIONS:-}" \
    "${UBSAN_OPTIONS:-}" |
    inside tee /etc/systemd/system/headingd.service.d/asan.conf >/dev/null
  inside systemctl daemon-reload
fi
show() { inside systemctl show headingd -p "$1" --value; }
# wait_for PROPERTY VALUE SECONDS
wait_for() {
  for _ in $(seq $(($3 * 5))); do [ "$(show "$1")" = "$2" ] && return 0; sleep 0.2; done
  return 1
}
journal_since() { inside journalctl -u headingd --no-pager -o cat --since "@$1" "${@:2}"; }
# A line at exactly priority PRIORITY (a number, or "all") since a time, matching a pattern; waits
# up to 5 s for journald, which takes messages from the daemon and from PID 1 in its own time.
said_at() {
  local priority=(-p "$2..$2")
  [ "$2" = all ] && priority=()
  for _ in $(seq 25); do
    journal_since "$1" "${priority[@]}" | grep -q -- "$3" && return 0
    sleep 0.2
  done
  return 1
}

dropin() { # the unit's own settings, its ExecStart replaced
  inside mkdir -p /etc/systemd/system/headingd.service.d
  printf '[Service]\nExecStart=\nExecStart=/usr/bin/headingd run --config %s %s\n' "$1" "${2:-}" |
    inside tee /etc/systemd/system/headingd.service.d/check.conf >/dev/null
  inside systemctl daemon-reload
}

# The shipped configuration with a domain, the loopback profile and a rolling recording of its own.
inside cp /etc/headingd/headingd.toml /etc/headingd/check.toml
inside sed -i -e "s|^domain_id = 0\$|domain_id = $domain\nprofiles_xml = \"/etc/headingd/fastdds-loopback.xml\"|" \
  -e 's|^dir = ""$|dir = "/var/lib/headingd/recordings"|' /etc/headingd/check.toml
inside grep -q "^domain_id = $domain\$" /etc/headingd/check.toml || fail "shipped config has no 'domain_id = 0' line"
inside grep -q '^dir = "/var/lib/headingd/recordings"$' /etc/headingd/check.toml || fail "shipped config has no '[record] dir' line"
inside install -m 644 /mnt/headingd-check/fastdds-loopback.xml /etc/headingd/fastdds-loopback.xml

# ---- A. the shipped configuration, no sensor ------------------------------------------------
t0=$(inside date +%s)
inside systemctl start headingd 2>/dev/null && fail "A: started without a sensor"
sleep 12
restarts=$(show NRestarts)
[ "$(show ActiveState)" = activating ] && [ "$restarts" -ge 1 ] && [ "$restarts" -le 3 ] ||
  fail "A: after 12 s without a sensor: $(show ActiveState)/$(show SubState) ($(show Result)), $restarts restarts (want 1-3, still trying)"
said_at "$t0" 3 "cannot open I2C adapter /dev/i2c-1" || fail "A: the missing adapter is not in the journal at priority err"
echo "ok: without a sensor: $restarts restarts in 12 s, still trying; the journal at err says:"
journal_since "$t0" -p err..err | grep -m1 'i2c' | sed 's/^/    /'
# The sensor "appears": the unit takes it at its next try, without anyone starting it again.
dropin /etc/headingd/check.toml "--simulated-chip still --sim-realtime"
wait_for ActiveState active 15 || fail "A: the sensor there, but the unit is $(show ActiveState)/$(show SubState)"
echo "ok: once the sensor was there the next try started it ($(show NRestarts) restarts in all)"
inside systemctl stop headingd

# ---- B. a configuration error -----------------------------------------------------------------
printf '[estimator]\nsegment_s = -3\n' | inside tee /etc/headingd/broken.toml >/dev/null
dropin /etc/headingd/broken.toml
# refused WHAT STATUS PATTERN: the start fails with STATUS, no restart follows, the error is at err.
refused() {
  local t0
  t0=$(inside date +%s)
  inside systemctl start headingd 2>/dev/null && fail "B: started with $1"
  sleep 6 # past RestartSec=5s: a restart would have come by now
  [ "$(show NRestarts)" = 0 ] && [ "$(show ActiveState)" = failed ] && [ "$(show ExecMainStatus)" = "$2" ] ||
    fail "B: $1: $(show NRestarts) restarts, $(show ActiveState), status $(show ExecMainStatus) (want 0, failed, $2)"
  said_at "$t0" 3 "$3" || fail "B: $1 is not in the journal at priority err"
  echo "ok: $1: exit $2, no restart; at err: $(journal_since "$t0" -p err..err | grep -m1 -- "$3")"
  inside systemctl reset-failed headingd
}
refused "a broken configuration" 78 broken.toml
dropin /etc/headingd/check.toml "--no-such-option"
refused "a wrong option in ExecStart" 64 no-such-option

# ---- C. the simulated chip under the unit's sandbox --------------------------------------------
dropin /etc/headingd/check.toml "--simulated-chip still --sim-realtime"
t0=$(inside date +%s)
timeout 60 nsenter -t "$leader" -a systemctl start headingd || fail "C: systemctl start: $(show Result)"
[ "$(show ActiveState)" = active ] || fail "C: $(show ActiveState) after start"
export CYCLONEDDS_URI="file://$root/tests/interop/cyclone.xml"
nsenter -t "$leader" -n "$peer" listen $domain 12 >"$dir/peer.out" 2>"$dir/peer.err" || fail "peer: $(tail -3 "$dir/peer.err")"
n_imu=$(grep -c '^imu_sensor_data' "$dir/peer.out")
n_orientation=$(grep -c '^orientation' "$dir/peer.out")
n_diagnostics=$(grep -c '^diagnostic' "$dir/peer.out")
[ "$n_imu" -ge 300 ] && [ "$n_orientation" -ge 300 ] && [ "$n_diagnostics" -ge 5 ] ||
  fail "C: the peer read $n_imu Imu, $n_orientation Orientation, $n_diagnostics /diagnostics messages"
status=$(show StatusText)
grep -q '^heading .* samples, 0 bus errors$' <<<"$status" || fail "C: STATUS= '$status'"
watchdog=$(show WatchdogTimestampMonotonic)
[ "$watchdog" -gt 0 ] 2>/dev/null || fail "C: no watchdog ping reached systemd"
sleep 3
[ "$(show WatchdogTimestampMonotonic)" -gt "$watchdog" ] || fail "C: the watchdog pings stopped"
[ "$(show NRestarts)" = 0 ] || fail "C: restarted $(show NRestarts) times"
echo "ok: active after READY=1; a Cyclone peer read $n_imu Imu, $n_orientation Orientation, $n_diagnostics /diagnostics messages; STATUS=\"$status\"; watchdog pinged"
inside systemctl reload headingd || fail "C: systemctl reload"
sleep 1
said_at "$t0" 5 "configuration reloaded from /etc/headingd/check.toml" || fail "C: no reload in the journal at notice"
inside systemctl stop headingd
[ "$(show Result)" = success ] && [ "$(show ExecMainStatus)" = 0 ] || fail "C: stop: $(show Result), status $(show ExecMainStatus)"
owner=$(inside stat -c '%U %a' /var/lib/headingd/state 2>&1) || fail "C: no state file: $owner"
[ "$owner" = "headingd 600" ] || fail "C: state file is '$owner', want 'headingd 600'"
recording=$(inside find /var/lib/headingd/recordings -name '*.csv.zst' -user headingd -size +0 | head -1)
[ -n "$recording" ] || fail "C: no rolling recording under /var/lib/headingd/recordings: $(inside ls -lR /var/lib/headingd)"
inside zstd -t -q "$recording" || fail "C: $recording is damaged"
echo "ok: reloaded; stopped with status 0; state (mode 600) and $recording written as headingd"
t0=$(inside date +%s)
inside systemctl start headingd || fail "C: second start"
said_at "$t0" 6 "bias and heading restored from /var/lib/headingd/state" || fail "C: the second start did not restore the state"
inside systemctl stop headingd
echo "ok: the second start restored the saved bias and heading"

# ---- D. the sensor dies: the watchdog ---------------------------------------------------------
dropin /etc/headingd/check.toml "--simulated-chip still --sim-realtime --sim-dead-after 3"
t0=$(inside date +%s)
inside systemctl start headingd || fail "D: start"
for _ in $(seq 100); do [ "$(show NRestarts)" -ge 1 ] && break; sleep 0.2; done
[ "$(show NRestarts)" -ge 1 ] || fail "D: no restart 20 s after the sensor died"
said_at "$t0" all 'Watchdog timeout' || fail "D: restarted, but not by the watchdog"
said_at "$t0" 4 "sensor dead" || fail "D: the dead sensor is not in the journal at priority warning"
inside systemctl stop headingd
echo "ok: a dead sensor: the watchdog killed and systemd restarted the daemon ($(journal_since "$t0" | grep -m1 'Watchdog timeout'))"

# ---- E. an IIO gyro: the unit's /sys is read-only; the packaged drop-in opens it ------------------
inside mount -t tmpfs -o mode=755 headingd-fake-sysfs /sys/bus || fail "E: tmpfs over the container's /sys/bus"
inside mkdir -p /sys/bus/iio/devices
inside cp /etc/headingd/check.toml /etc/headingd/iio.toml
inside sed -i -e 's|^kind = "l3gd20h"$|kind = "iio"|' /etc/headingd/iio.toml
inside grep -q '^kind = "iio"$' /etc/headingd/iio.toml || fail "E: shipped config has no 'kind = \"l3gd20h\"' line"
# feed SECONDS: the simulated gyro behind the fake tree, permissions as udev and the helper give them.
feed() {
  inside "/mnt/headingd-feeder/$(basename "$feeder")" / st16 still 5 "$1" paced >"$dir/feeder.out" 2>&1 &
  for _ in $(seq 300); do grep -qs ready "$dir/feeder.out" && break; sleep 0.05; done
  grep -qs ready "$dir/feeder.out" || fail "E: the feeder did not start: $(cat "$dir/feeder.out")"
  inside chgrp iio /dev/iio:device0 && inside chmod 0660 /dev/iio:device0 || fail "E: the device node's group"
  inside /usr/lib/headingd/iio-permissions /bus/iio/devices/iio:device0
}
dropin /etc/headingd/iio.toml
# One feeder for both tries: the first fails before it opens the FIFO, so the feeder waits for
# the second (a feeder killed and started again here once missed its 5 s under the asan preset).
feed 60
t0=$(inside date +%s)
inside systemctl start headingd 2>/dev/null && fail "E: started an IIO gyro with /sys read-only"
said_at "$t0" 3 "headingd-iio.conf" || fail "E: without the drop-in, the error does not name it: $(journal_since "$t0" -p err..err | tail -2)"
sleep 2 # no restart comes: the sandbox is the unit's configuration, which a restart meets again
[ "$(show ExecMainStatus)" = 78 ] && [ "$(show NRestarts)" = 0 ] && [ "$(show ActiveState)" = failed ] ||
  fail "E: without the drop-in: status $(show ExecMainStatus), $(show NRestarts) restarts, $(show ActiveState) (want 78, 0, failed)"
echo "ok: IIO without the drop-in: exit 78, no restart: $(journal_since "$t0" -p err..err | grep -m1 headingd-iio.conf)"
inside systemctl stop headingd
inside install -m 644 /usr/share/headingd/headingd-iio.conf /etc/systemd/system/headingd.service.d/iio.conf
inside systemctl daemon-reload
t0=$(inside date +%s)
timeout 60 nsenter -t "$leader" -a systemctl start headingd || fail "E: with the drop-in: $(show Result)"
sleep 11
status=$(show StatusText)
# Standing still: the heading stays within a degree (a bias left at zero would turn it 0.45 deg/s).
heading=$(sed -n 's/^heading \([-0-9.]*\) deg.* \([0-9]*\) samples.*/\1 \2/p' <<<"$status")
awk -v h="${heading% *}" -v n="${heading#* }" 'BEGIN { exit !(n > 3000 && h > -1 && h < 1) }' </dev/null ||
  fail "E: STATUS= '$status'"
[ "$(show NRestarts)" = 0 ] || fail "E: restarted $(show NRestarts) times"
inside systemctl stop headingd
[ "$(show ExecMainStatus)" = 0 ] || fail "E: stop: status $(show ExecMainStatus)"
echo "ok: IIO with the packaged drop-in: runs under the unit as headingd; STATUS=\"$status\""

# ---- F. upgrade, removal and purge with the service running ---------------------------------------
inside rm -f /etc/systemd/system/headingd.service.d/iio.conf
dropin /etc/headingd/check.toml "--simulated-chip still --sim-realtime"
inside systemctl start headingd || fail "F: start"
before=$(show MainPID)
# Docker-made images (this machine's among them) carry a policy-rc.d that forbids packages any
# service action (exit 101); the scripts honour it, through deb-systemd-invoke. A vehicle's
# Debian has none: remove it, in the container only, and upgrade again.
if inside test -x /usr/sbin/policy-rc.d; then
  inside dpkg -i /mnt/headingd-check/headingd.deb >"$dir/upgrade.log" 2>&1 || fail "F: upgrade: $(tail -3 "$dir/upgrade.log")"
  [ "$(show MainPID)" = "$before" ] || fail "F: the upgrade restarted the service against policy-rc.d"
  echo "ok: with policy-rc.d forbidding it, an upgrade left the running service alone"
  inside rm /usr/sbin/policy-rc.d
fi
inside dpkg -i /mnt/headingd-check/headingd.deb >"$dir/upgrade.log" 2>&1 || fail "F: upgrade: $(tail -3 "$dir/upgrade.log")"
after=$(show MainPID)
[ "$(show ActiveState)" = active ] && [ "$after" != "$before" ] && [ "$after" != 0 ] ||
  fail "F: after the upgrade: $(show ActiveState), main PID $before -> $after (want a new one)"
echo "ok: an upgrade restarted the running service onto the new binary (PID $before -> $after)"
inside dpkg -r headingd >"$dir/remove.log" 2>&1 || fail "F: dpkg -r: $(tail -3 "$dir/remove.log")"
[ "$(show ActiveState)" = inactive ] && ! inside pgrep -x headingd >/dev/null || fail "F: still running after removal"
inside test -f /var/lib/headingd/state || fail "F: removal took the state (only purge may)"
inside dpkg -P headingd >"$dir/purge.log" 2>&1 || fail "F: dpkg -P: $(tail -3 "$dir/purge.log")"
inside test ! -e /var/lib/headingd || fail "F: the state directory outlived the purge"
echo "ok: removal stopped the service and kept its state; purge removed it"
