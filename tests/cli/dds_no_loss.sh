#!/usr/bin/env bash
# Best-effort Orientation at 50 Hz from a 400 Hz run, for 60 s: a local subscriber that keeps up
# receives at least 99.9 % of the messages (by sequence number). A FIFO wake-up makes two or
# three messages due back to back; the writer keeps a burst of them (kOrientationBurst).
# Usage: dds_no_loss.sh HEADINGD SOURCE_ROOT [SECONDS]
source "$(dirname "$0")/cli_common.sh"
root="$2"
seconds="${3:-60}"
printf '[dds]\ndomain_id = 54\nprofiles_xml = "%s/config/fastdds-loopback.xml"\n' "$root" >"$dir/cfg.toml"
"$headingd" run --simulated-chip agv --sim-realtime --duration $((seconds + 4)) -c "$dir/cfg.toml" 2>"$dir/run.err" &
pid=$!
sleep 2
"$headingd" echo orientation -c "$dir/cfg.toml" --timeout "$seconds" >"$dir/echo.txt" 2>&1
wait "$pid" || fail "run: $(tail -3 "$dir/run.err")"
seqs=$(sed -n 's/^orientation .* seq=\([0-9]*\) .*/\1/p' "$dir/echo.txt")
received=$(grep -c . <<<"$seqs")
[ "$received" -gt 0 ] || fail "nothing received: $(head -3 "$dir/echo.txt")"
expected=$(($(tail -1 <<<"$seqs") - $(head -1 <<<"$seqs") + 1))
awk -v r="$received" -v e="$expected" 'BEGIN { exit !(r >= 0.999 * e) }' ||
  fail "$received of $expected orientation messages ($(awk -v r="$received" -v e="$expected" 'BEGIN { printf "%.2f", 100 * r / e }') %)"
echo "ok: $received of $expected best-effort orientation messages in ${seconds} s"
