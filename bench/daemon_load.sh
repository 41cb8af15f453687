#!/usr/bin/env bash
# The daemon at 400 Hz for 60 s against the simulated chip paced in real time, publishing over
# DDS (loopback profile) with a subscriber attached: CPU share of one core and peak RSS.
# The simulator runs inside the daemon, so both figures are upper bounds for real hardware.
set -euo pipefail
source "$(dirname "$0")/../scripts/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}" time
build_preset default quiet
headingd="$HEADINGD_ROOT/build/default/app/headingd"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
printf '[dds]\ndomain_id = 48\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$HEADINGD_ROOT" >"$dir/cfg.toml"
"$headingd" echo orientation -c "$dir/cfg.toml" --timeout 70 >"$dir/echo.txt" 2>&1 &
echo_pid=$!
/usr/bin/time -f "%e %U %S %M" -o "$dir/time.txt" \
  "$headingd" run --simulated-chip agv --sim-realtime --duration 60 -c "$dir/cfg.toml" 2>"$dir/run.err"
kill -INT "$echo_pid" 2>/dev/null || true
wait "$echo_pid" 2>/dev/null || true
read -r wall user sys rss_kb <"$dir/time.txt"
awk -v w="$wall" -v u="$user" -v s="$sys" -v r="$rss_kb" -v n="$(grep -c '^orientation' "$dir/echo.txt")" 'BEGIN {
  printf "daemon at 400 Hz for %.0f s (simulated chip, DDS publishing, %d messages to a subscriber):\n", w, n
  printf "  CPU %.2f %% of one core (user %.2f s + system %.2f s), peak RSS %.1f MB\n", 100 * (u + s) / w, u, s, r / 1024 }'
