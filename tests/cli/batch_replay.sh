#!/usr/bin/env bash
# `replay` over many recordings (files, a directory, compressed ones) with --jobs 2: every row of
# the table equals what the single-file replay of that recording reports, the estimates files equal
# the single replay's byte for byte, a damaged recording is a row with its error (exit 65) while
# the others are done, and two recordings that would write one file are refused before starting.
source "$(dirname "$0")/cli_common.sh"
cd "$dir" || exit 1
mkdir fleet
for i in 1 2 3 4 5; do
  "$headingd" simulate --scenario agv --seed "$i" --hours 0.05 --output-dir "s$i" >/dev/null 2>&1 || fail "simulate $i"
  mv "s$i/imu.csv" "fleet/vehicle$i.csv"
done
zstd -q --rm fleet/vehicle4.csv && gzip fleet/vehicle5.csv
"$headingd" simulate --scenario creep --seed 9 --hours 0.05 --output-dir s6 >/dev/null 2>&1 && cp s6/imu.csv extra.csv

"$headingd" replay fleet extra.csv --jobs 2 --summary-csv table.csv >table.txt 2>err || fail "batch: $(cat err)"
"$headingd" replay fleet --output-dir new/dir >/dev/null 2>err && [ -s new/dir/vehicle1.estimates.csv ] ||
  fail "--output-dir that does not exist yet: $(cat err)"
[ "$(grep -c '^"' table.csv)" -eq 6 ] || fail "expected 6 rows: $(cat table.csv)"
for f in fleet/vehicle1.csv fleet/vehicle2.csv fleet/vehicle3.csv fleet/vehicle4.csv.zst fleet/vehicle5.csv.gz extra.csv; do
  "$headingd" replay --no-dds "$f" -o single.csv 2>single.log || fail "single replay of $f"
  samples=$(sed -n 's/^  samples      \([0-9]*\) over.*/\1/p' single.log)
  still=$(sed -n 's/.*: \([0-9]*\) accepted as still.*/\1/p' single.log)
  sigma=$(sed -n 's/.*sigma \([0-9.]*\) deg$/\1/p' single.log)
  bias_z=$(sed -n 's/^  bias .* z \([-+0-9.]*\) dps$/\1/p' single.log)
  row=$(grep "^$f " table.txt) || fail "no row for $f: $(cat table.txt)"
  read -r _ _ r_samples r_still r_sigma r_bias _ <<<"$row"
  [ "$r_samples $r_still $r_sigma $r_bias" = "$samples $still $sigma $bias_z" ] ||
    fail "$f: table '$r_samples $r_still $r_sigma $r_bias', single replay '$samples $still $sigma $bias_z'"
  out=$(sed -n "s|^\"$f\",\"\([^\"]*\)\".*|\1|p" table.csv)
  cmp -s single.csv "$out" || fail "$f: $out differs from the single replay's estimates"
done
echo "ok: 6 recordings (plain, .zst, .gz, a directory and a file) with --jobs 2: every row and estimates file equal the single replay's"
cat table.txt

# A damaged recording: its row says why, the others are done, exit 65.
head -c 100000 extra.csv >fleet/broken.csv
"$headingd" replay fleet --jobs 2 >table2.txt 2>err; rc=$?
[ "$rc" -eq 65 ] && grep -q "^fleet/broken.csv .*the last line has no newline" table2.txt &&
  [ "$(grep -c '^fleet/vehicle' table2.txt)" -eq 5 ] || fail "damaged recording: exit $rc: $(cat table2.txt err)"
echo "ok: a truncated recording is a row with its error, the five others done, exit 65"

# A link in the directory that leads nowhere is a row with its error too, not a vehicle left out;
# exit 66 as for any input that cannot be opened.
rm fleet/broken.csv && ln -s nowhere.csv fleet/gone.csv
"$headingd" replay fleet --jobs 2 >table3.txt 2>err; rc=$?
[ "$rc" -eq 66 ] && grep -q "^fleet/gone.csv .*No such file" table3.txt &&
  [ "$(grep -c '^fleet/vehicle' table3.txt)" -eq 5 ] || fail "dangling link: exit $rc: $(cat table3.txt err)"
rm fleet/gone.csv
echo "ok: a link to nothing is a row with its error, the five others done, exit 66"

mkdir other && cp fleet/vehicle1.csv other/
out=$("$headingd" replay fleet/vehicle1.csv other/vehicle1.csv --output-dir outs 2>&1); rc=$?
[ "$rc" -eq 64 ] && grep -q "would both write outs/vehicle1.estimates.csv" <<<"$out" || fail "collision: exit $rc: $out"
[ ! -e outs/vehicle1.estimates.csv ] || fail "something was written despite the collision"
out=$("$headingd" replay fleet missing.csv 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "missing.csv" <<<"$out" || fail "missing input: exit $rc: $out"
echo "ok: colliding outputs refused (64) before any work; a missing input 66"

# What `simulate` writes is a directory with one recording beside its truth: replayed as that
# recording (-o applies), the truth named as left out. A fleet directory that holds its own batch
# table and truth files: those are left out, a recording with a damaged header is not.
"$headingd" replay --no-dds s6 -o dir.csv 2>dir.log || fail "a simulation's directory: $(cat dir.log)"
grep -q "s6: left out, not recordings: truth.csv (a truth file)" dir.log || fail "truth not named: $(cat dir.log)"
"$headingd" replay --no-dds s6/imu.csv -o file.csv 2>/dev/null && cmp -s dir.csv file.csv ||
  fail "the directory's estimates differ from its recording's"
# Without -o or --plot the same directory is a batch of one: the table a fleet's script reads.
"$headingd" replay s6 >one.txt 2>/dev/null && head -1 one.txt | grep -q '^file ' && grep -q '^s6/imu.csv ' one.txt ||
  fail "a directory of one recording without -o is not a batch: $(cat one.txt)"
cp s1/truth.csv fleet/vehicle1-truth.csv && cp table.csv fleet/table.csv
printf 'tme_s,gx,gy,gz\n0,0,0,0\n' >fleet/garbled.csv
"$headingd" replay fleet --jobs 2 >table4.txt 2>err; rc=$?
grep -q "left out, not recordings: table.csv (a replay summary table), vehicle1-truth.csv (a truth file)" err ||
  fail "companions not named: $(cat err)"
[ "$rc" -eq 65 ] && grep -q "^fleet/garbled.csv .*missing column" table4.txt &&
  [ "$(grep -c '^fleet/' table4.txt)" -eq 6 ] || fail "companions or a damaged header: exit $rc: $(cat table4.txt err)"
"$headingd" replay --no-dds fleet/vehicle1-truth.csv -o t.csv 2>err; rc=$?
[ "$rc" -eq 65 ] && grep -q "missing column 'gx_dps'" err || fail "a truth file named on its own: exit $rc: $(cat err)"
echo "ok: a simulation's directory replays as its recording with -o, is a batch of one without; truth files and a batch table left out and named; a damaged header and a named truth file still fail"

# A fleet's archive, folders by vehicle and day, every recording named imu.csv: with -r all are
# found (a link back up the tree not followed), and under --output-dir each estimates file keeps
# its folders, so the same names do not collide.
for v in 1 2; do for d in 1 2; do
  i=$((v + d - 1)) && mkdir -p "archive/vehicle-$v/day-$d" && cp "fleet/vehicle$i.csv" "archive/vehicle-$v/day-$d/imu.csv" &&
    cp "s$i/truth.csv" "archive/vehicle-$v/day-$d/"
done; done
ln -s .. archive/vehicle-1/up
"$headingd" replay archive -r --jobs 2 --output-dir arch-out >table5.txt 2>err || fail "-r: $(cat table5.txt err)"
[ "$(grep -c '^archive/vehicle-[12]/day-[12]/imu.csv ' table5.txt)" -eq 4 ] && [ "$(grep -c '^archive' table5.txt)" -eq 4 ] ||
  fail "-r: expected the four recordings once each: $(cat table5.txt)"
grep -q "vehicle-2/day-1/truth.csv (a truth file)" err || fail "-r: nested truth files not named: $(cat err)"
"$headingd" replay --no-dds archive/vehicle-2/day-1/imu.csv -o single.csv 2>/dev/null &&
  cmp -s single.csv arch-out/vehicle-2/day-1/imu.estimates.csv || fail "-r: arch-out/vehicle-2/day-1 differs"
[ "$(find arch-out -name '*.estimates.csv' | wc -l)" -eq 4 ] || fail "-r: $(find arch-out)"
out=$("$headingd" replay archive --output-dir flat 2>&1); rc=$?
[ "$rc" -eq 66 ] && grep -q "no recordings .* in archive$" <<<"$out" || fail "without -r: exit $rc: $out"
echo "ok: -r finds a fleet archive's recordings at every depth, estimates under --output-dir keep their folders"
