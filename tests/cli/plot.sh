#!/usr/bin/env bash
# `plot` draws a PNG (or SVG) of a replay with its truth and recording: the file is a real PNG of
# the promised size; a name built to break out of a gnuplot script is only a name; `replay
# --plot` does the same in one command; bad inputs are errors that name them.
source "$(dirname "$0")/cli_common.sh"
cd "$dir" || exit 1

"$headingd" simulate --scenario thermal --seed 2 --hours 0.1 --output-dir sim >/dev/null 2>&1 || fail "simulate"
"$headingd" replay --no-dds sim/imu.csv -o est.csv --quiet || fail "replay"
"$headingd" plot est.csv --truth sim/truth.csv --recording sim/imu.csv -o out.png 2>err || fail "plot: $(cat err)"
# PNG: the signature, then IHDR with width and height (big-endian) at bytes 16..23.
[ "$(head -c 8 out.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "not a PNG"
width=$(od -An -tu4 --endian=big -j16 -N4 out.png | tr -d ' ')
height=$(od -An -tu4 --endian=big -j20 -N4 out.png | tr -d ' ')
size=$(stat -c %s out.png)
[ "$width" -eq 1200 ] && [ "$height" -eq 900 ] && [ "$size" -gt 20000 ] || fail "PNG ${width}x${height}, $size bytes"
echo "ok: plot with truth and recording: PNG ${width}x${height}, $size bytes"

"$headingd" plot est.csv -o out.svg 2>err || fail "svg: $(cat err)"
grep -q '<svg' out.svg && grep -q 'width="1200"' out.svg || fail "not a 1200-wide SVG"
echo "ok: SVG without truth (two panels)"

# Against an orientation truth (motion capture's layout, written here from the estimates' own
# attitude turned 3 degrees about the vertical from 60 s on): three panels, the error one among them.
awk -F, 'NR > 1 { if ($1 >= 60) { c = cos(3 * 3.14159265358979 / 360); s = sin(3 * 3.14159265358979 / 360)
    printf "%s,%.12f,%.12f,%.12f,%.12f,1\n", $1, c*$3 - s*$6, c*$4 - s*$5, c*$5 + s*$4, c*$6 + s*$3 }
  else printf "%s,%s,%s,%s,%s,0\n", $1, $3, $4, $5, $6 }
  NR == 1 { print "time_s,qw,qx,qy,qz,moving" }' est.csv >mocap.csv
"$headingd" plot est.csv --truth mocap.csv -o mocap.svg 2>err || fail "plot against an orientation truth: $(cat err)"
grep -q 'Heading error (truth' mocap.svg && grep -q 'height="900"' mocap.svg || fail "no error panel against mocap.csv"
"$headingd" score est.csv mocap.csv --label m >score.txt 2>err || fail "score mocap: $(cat err)"
read -r _ max _ <<<"$(grep '^m ' score.txt)"
[ "$max" = 3.00 ] || fail "a truth turned 3 deg scores a max of $max: $(cat score.txt)"
echo "ok: plot and score against an orientation truth (the estimates' attitude turned 3 deg: max 3.00)"

# A name made to close a gnuplot string and run a command: written as a name, nothing runs.
evil="x';system 'touch pwned';print '\$(touch pwned2).png"
"$headingd" plot est.csv -o "$evil" 2>err || fail "hostile name: $(cat err)"
[ -s "$evil" ] && [ ! -e pwned ] && [ ! -e pwned2 ] || fail "the hostile name was not just a name: $(ls)"
ln -s "$dir/victim" link.png
"$headingd" plot est.csv -o link.png 2>err || fail "plot over a link: $(cat err)"
[ ! -e victim ] && [ ! -L link.png ] || fail "the picture was written through a planted link"
echo "ok: a hostile output name is only a name; a planted link is replaced, not followed"

"$headingd" replay --no-dds sim/imu.csv -o est2.csv --quiet --plot replay.png || fail "replay --plot"
[ "$(head -c 4 replay.png | od -An -tx1 | tr -d ' \n')" = 89504e47 ] || fail "replay --plot drew no PNG"
echo "ok: replay --plot"

# Joined, the temperature is drawn from all the parts (the recording cut in two by awk).
awk '/^#/ { next } !h { h = 1; print > "part1.csv"; print > "part2.csv"; next }
  { print > (++n <= 20000 ? "part1.csv" : "part2.csv") }' sim/imu.csv
"$headingd" replay --no-dds --join part1.csv part2.csv -o joined.csv --quiet --plot joined.svg 2>err ||
  fail "replay --join --plot: $(cat err)"
grep -q 'sensor temperature' joined.svg || fail "replay --join --plot drew no temperature"
echo "ok: replay --join --plot draws the temperature of the joined recordings"

out=$("$headingd" plot est.csv -o out.jpg 2>&1); rc=$?
[ "$rc" -eq 64 ] && grep -q "must end in .png or .svg" <<<"$out" || fail "bad extension: exit $rc: $out"
out=$("$headingd" plot sim/truth.csv -o x.png 2>&1); rc=$?
[ "$rc" -eq 65 ] && grep -q "truth.csv:.*header lacks 'heading_sigma_deg'" <<<"$out" || fail "wrong input: exit $rc: $out"
out=$("$headingd" replay --no-dds sim/imu.csv --plot x.png 2>&1); rc=$?
[ "$rc" -eq 64 ] && grep -q "needs the estimates in a file" <<<"$out" || fail "replay --plot without -o: exit $rc: $out"
echo "ok: errors: bad extension 64, not an estimates file 65 (naming it), replay --plot without -o 64"
