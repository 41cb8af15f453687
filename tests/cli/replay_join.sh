#!/usr/bin/env bash
# A fleet's rolling recordings replayed a row per run (`replay -r --join`): vehicle-1's folder holds
# two runs of the recorder (a restart: the second run's sample clock starts again), vehicle-2's
# one. Each run's row and estimates equal the replay of that run's files joined on their own;
# a run cut short (its last file truncated and without its closing line, as a crash leaves it)
# still ends its row there, the damage named (exit 65), and the next run gets its own row, also
# when the restart was on the same boot (the clock going on: the run named in each file). And a
# real BROAD recording cut in three and joined equals the whole. Usage: replay_join.sh HEADINGD [DATA_ROOT]
source "$(dirname "$0")/cli_common.sh"
cd "$dir" || exit 1

record() {  # record VEHICLE SEED SECONDS: a run of the simulated chip, a file per 10.8 s
  "$headingd" run --simulated-chip agv --sim-seed "$2" --duration "$3" --no-dds --state "state-$1-$2" \
    --record-dir "fleet/$1" --record-split-hours 0.003 2>"run-$1-$2.log" || fail "run $1 $2: $(cat "run-$1-$2.log")"
}
record vehicle-1 1 30
run1=(fleet/vehicle-1/*)
sleep 1.1  # the second run's files start a second later: their names sort after the first's
record vehicle-1 2 20
run2=()
for f in fleet/vehicle-1/*; do [[ " ${run1[*]} " == *" $f "* ]] || run2+=("$f"); done
record vehicle-2 3 25
[ "${#run1[@]}" -eq 3 ] && [ "${#run2[@]}" -eq 2 ] || fail "files: ${run1[*]} | ${run2[*]}"

"$headingd" replay -r --join fleet --output-rate 0 --output-dir out --summary-csv table.csv >table.txt 2>err ||
  fail "replay -r --join: $(cat table.txt err)"
[ "$(grep -c '^fleet/' table.txt)" -eq 3 ] || fail "rows: $(cat table.txt)"
grep -q "^fleet/vehicle-1/ run 1 from $(basename "${run1[0]}")" table.txt &&
  grep -q "^fleet/vehicle-1/ run 2 from $(basename "${run2[0]}")" table.txt &&
  grep -q "^fleet/vehicle-2/ (3 joined)" table.txt || fail "row names: $(cat table.txt)"
check_run() {  # check_run ESTIMATES FILE...: the row's estimates equal the run's own files joined
  local est="$1"
  shift
  "$headingd" replay --no-dds --join "$@" --output-rate 0 -o alone.est 2>alone.log || fail "--join $*: $(cat alone.log)"
  cmp -s alone.est "$est" || fail "$est differs from the replay of $* joined on their own"
}
check_run "out/vehicle-1/$(basename "${run1[0]%.csv.zst}").estimates.csv" "${run1[@]}"
check_run "out/vehicle-1/$(basename "${run2[0]%.csv.zst}").estimates.csv" "${run2[@]}"
check_run "out/vehicle-2/$(basename "$(ls fleet/vehicle-2 | head -1)" .csv.zst).estimates.csv" fleet/vehicle-2/*
echo "ok: a row per run (two in vehicle-1's folder, one in vehicle-2's), each equal to its own files joined"

# One folder of two runs asked for one replay: the restart is named, the first run's estimates kept.
"$headingd" replay --no-dds --join fleet/vehicle-1 -o one.est 2>one.log
rc=$?
[ "$rc" -eq 65 ] && grep -q "another run, after the machine restarted" one.log || fail "one replay of two runs: exit $rc: $(head -2 one.log)"
echo "ok: --join -o over two runs stops at the restart, saying so (65)"

# The wall clock stepped back an hour mid-run (a clock ahead, corrected): vehicle-2's last file is
# named before its first. --join DIR follows the run and number each file's header gives, and
# the estimates are the run's as before; the files named one by one, in name order, are refused.
v2=(fleet/vehicle-2/*)
"$headingd" replay --no-dds --join fleet/vehicle-2 --output-rate 0 -o v2-before.est 2>/dev/null || fail "vehicle-2 joined"
stepped="fleet/vehicle-2/headingd-20000101T000000Z.csv.zst"
mv "${v2[2]}" "$stepped"
"$headingd" replay --no-dds --join fleet/vehicle-2 --output-rate 0 -o v2-stepped.est 2>stepped.log ||
  fail "--join over a clock stepped back: $(cat stepped.log)"
cmp -s v2-before.est v2-stepped.est || fail "the series' order after the clock stepped back is not its header's"
"$headingd" replay --no-dds --join fleet/vehicle-2/* -o /dev/null 2>/dev/null && fail "files named in name order were not refused"
mv "$stepped" "${v2[2]}"
echo "ok: --join DIR orders a series by its files' headers: a wall clock stepped back mid-run changes nothing"

# A crash: run 1's last file cut short, without its closing line. The row of run 1 ends with the
# damage named; run 2 still has its row.
last="${run1[2]}"
zstd -dc "$last" | head -n -1 | head -c -20 | zstd -q -o cut.zst && mv cut.zst "$last"
"$headingd" replay -r --join fleet/vehicle-1 --output-rate 0 --output-dir out2 >crash.txt 2>crash.err
rc=$?
[ "$rc" -eq 65 ] || fail "a crashed run: exit $rc: $(cat crash.txt crash.err)"
grep "run 1 from" crash.txt | grep -q "damaged part passed: .*$(basename "$last")" || fail "run 1's row: $(cat crash.txt)"
grep "run 2 from" crash.txt | grep -q "  -$" || fail "run 2's row: $(cat crash.txt)"
echo "ok: a run cut short by a crash: its row names the damage, the next run has its own row (65)"

# The same crash with the daemon restarted on the same boot (systemd's Restart=): the sample clock
# goes on (CLOCK_MONOTONIC), so only the files' own words tell the runs apart, the name of the run
# each file's header carries. Run 2's times shifted 1000 s on by awk, as that restart gives them.
for f in "${run2[@]}"; do
  zstd -dc "$f" | awk -F, -v OFS=, '/^#/ || $1 == "time_s" { print; next } { $1 = sprintf("%.9f", $1 + 1000); print }' |
    zstd -q -f -o "$f.tmp" && mv "$f.tmp" "$f" || fail "shifting $f"
done
grep -q "^# rolling series run $(basename "${run2[0]%.csv.zst}"), file 2$" <(zstd -dc "${run2[1]}") ||
  fail "run 2's second file does not name its run: $(zstd -dc "${run2[1]}" | grep 'series run')"
"$headingd" replay -r --join fleet/vehicle-1 --output-rate 0 --output-dir out3 >same-boot.txt 2>same-boot.err
rc=$?
[ "$rc" -eq 65 ] && [ "$(grep -c '^fleet/vehicle-1/ run' same-boot.txt)" -eq 2 ] ||
  fail "a crash and a restart on the same boot: exit $rc: $(cat same-boot.txt same-boot.err)"
grep "run 1 from" same-boot.txt | grep -q "damaged part passed: .*$(basename "$last")" || fail "run 1's row: $(cat same-boot.txt)"
check_run "out3/$(basename "${run2[0]%.csv.zst}").estimates.csv" "${run2[@]}"
echo "ok: a crash and a restart on the same boot: two rows, the second equal to its own files joined (65)"

# A real recording we did not write (BROAD trial 05, EuRoC layout), cut into three parts by awk,
# one left plain, one zstd, one gzip: joined, its estimates equal the whole file's byte for byte.
broad="${2:-}/broad-05/imu.csv"
if [ -f "$broad" ]; then
  awk -v part=1 'NR == 1 { header = $0; print > "p1.csv"; next }
    NR == 20001 || NR == 40001 { part++; print header > ("p" part ".csv") } { print > ("p" part ".csv") }' "$broad"
  zstd -q --rm p2.csv && gzip p3.csv
  "$headingd" replay --no-dds "$broad" --output-rate 0 -o broad-whole.est 2>/dev/null || fail "replay $broad"
  "$headingd" replay --no-dds --join p1.csv p2.csv.zst p3.csv.gz --output-rate 0 -o broad-joined.est 2>bj.log ||
    fail "--join of the parts: $(cat bj.log)"
  cmp -s broad-whole.est broad-joined.est || fail "BROAD trial 05 in three parts joined differs from the whole"
  echo "ok: BROAD trial 05 cut in three (plain, zstd, gzip) and joined equals the whole, byte for byte"
else
  echo "note: $broad not found: the real recording's check was not run"
fi
