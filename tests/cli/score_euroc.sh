#!/usr/bin/env bash
# A recording and its ground truth in the EuRoC/ASL layout, written here by hand (awk), not by our
# simulator: imu0/data.csv (ns time stamps, rad/s, accelerometer columns) with a known gyro bias,
# still, a 90 degree turn at 30 dps, still; state_groundtruth_estimate0/data.csv at 200 Hz on time
# stamps of its own (2.5 ms after the IMU's), with position, velocity and bias columns around the
# orientation. `replay` then `score` against the ground truth: the heading error stays small, every
# estimate inside the truth's span is scored; the same estimates against a truth turned 5 degrees
# more after the turn show 5 degrees; our bias against the truth's bias columns.
source "$(dirname "$0")/cli_common.sh"
cd "$dir" || exit 1
# Time stamps printed as seconds then nanoseconds: awk's numbers would round 19 digits.

awk 'BEGIN {
  pi = 3.14159265358979; rate = 30 * pi / 180
  print "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]"
  for (i = 0; i < 8000; i++) {
    t = i / 200; z = (t > 15 && t <= 18) ? rate : 0
    printf "%d%09d,%.9f,%.9f,%.9f,0.0,0.0,9.81\n", 1403636579 + int(i / 200), (i % 200) * 5000000, -0.002 + 1e-4 * sin(i * 1.7), 0.003 + 1e-4 * sin(i * 2.3), z + 0.008 + 1e-4 * sin(i * 0.9)
  }
}' >imu.csv
truth() {  # truth EXTRA_DEG [BIAS_Z]: the yaw after the turn EXTRA_DEG more than the gyro says
  awk -v extra="$1" -v bz="${2:-0.008}" 'BEGIN {
    pi = 3.14159265358979
    print "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]"
    for (i = 0; i < 7990; i++) {
      t = i / 200 + 0.0025; yaw = 30 + 30 * (t < 15 ? 0 : (t > 18 ? 3 : t - 15)) + (t > 18 ? extra : 0)
      h = yaw * pi / 360
      printf "%d%09d,4.6,-1.8,0.8,%.12f,0,0,%.12f,0,0,0,-0.002,0.003,%s,0,0,0\n", 1403636579 + int(i / 200),
        (i % 200) * 5000000 + 2500000, cos(h), sin(h), bz
    }
  }'
}
truth 0 >truth.csv && truth 5 >truth5.csv && truth 0 0.0081 >truth_bias.csv

"$headingd" replay --no-dds imu.csv --output-rate 0 -o est.csv 2>replay.log || fail "replay: $(cat replay.log)"
grep -q "EuRoC/ASL" replay.log || fail "not read as EuRoC: $(head -2 replay.log)"
out=$("$headingd" score est.csv truth.csv --label est 2>&1) || fail "score: $out"
read -r _ max final rms _ <<<"$(grep '^est ' <<<"$out")"
rows=$(sed -n 's/.* on [0-9.]* % of \([0-9]*\) rows.*/\1/p' <<<"$out")
echo "EuRoC ground truth: max $max, final $final, RMS $rms deg over $rows rows"
awk -v m="$max" 'BEGIN { exit !(m < 0.5) }' || fail "heading error $max deg against the ground truth: $out"
# Estimates every 5 ms from 0 to 39.995 s; the truth from 0.0025 to 39.9475 s: 7989 rows between.
[ "$rows" = 7989 ] || fail "scored $rows rows, expected 7989: $out"
out5=$("$headingd" score est.csv truth5.csv --label est 2>&1) || fail "score 5: $out5"
read -r _ _ final5 _ <<<"$(grep '^est ' <<<"$out5")"
awk -v f="$final5" -v f0="$final" 'BEGIN { exit !(f - f0 > 4.99 && f - f0 < 5.01) }' ||
  fail "a truth turned 5 deg more shows final $final5 against $final: $out5"
echo "ok: EuRoC imu0 and ground truth written by hand: replayed and scored, error under 0.5 deg; 5 deg more in the truth shows as 5 deg"

# The ground truth's gyro bias (b_w_RS_S_*, rad/s) against ours: the recording's own bias at the
# end (every axis within 0.5 mdps), and a truth whose z bias is 1e-4 rad/s (5.73 mdps) more shows it.
bias_end() { sed -n 's/.*bias minus the truth.s (mdps) .* at the end x \([-+0-9.]*\) y \([-+0-9.]*\) z \([-+0-9.]*\) .*/\1 \2 \3/p'; }
read -r bx by bz <<<"$(bias_end <<<"$out")"
[ -n "$bz" ] || fail "no bias line: $out"
awk -v x="$bx" -v y="$by" -v z="$bz" 'BEGIN { exit !(x * x < 0.25 && y * y < 0.25 && z * z < 0.25) }' ||
  fail "bias at the end x $bx y $by z $bz mdps from the truth's: $out"
out_bias=$("$headingd" score est.csv truth_bias.csv --label est 2>&1) || fail "score bias: $out_bias"
read -r _ _ bz2 <<<"$(bias_end <<<"$out_bias")"
awk -v z="$bz2" -v z0="$bz" 'BEGIN { d = z0 - z; exit !(d > 5.70 && d < 5.76) }' ||
  fail "a truth bias 5.73 mdps more in z shows z $bz2 against $bz: $out_bias"
echo "ok: the ground truth's gyro bias: ours at the end within 0.5 mdps on every axis ($bx $by $bz); 5.73 mdps more in the truth shows"

# The dataset's folders, replayed as a whole: only imu0 is a recording; the ground truth and a
# camera's list share its layout and are left out, named.
mkdir -p mav0/imu0 mav0/state_groundtruth_estimate0 mav0/cam0
cp imu.csv mav0/imu0/data.csv && cp truth.csv mav0/state_groundtruth_estimate0/data.csv
printf '#timestamp [ns],filename\n1403636579758555392,1403636579758555392.png\n' >mav0/cam0/data.csv
"$headingd" replay -r mav0 --output-dir out >table.txt 2>err || fail "replay -r mav0: $(cat table.txt err)"
[ "$(grep -c '^mav0/' table.txt)" -eq 1 ] && grep -q '^mav0/imu0/data.csv ' table.txt || fail "rows: $(cat table.txt)"
grep -q "cam0/data.csv (another EuRoC/ASL sensor's data, no w_RS_S_x)" err &&
  grep -q "state_groundtruth_estimate0/data.csv (an EuRoC/ASL ground truth)" err || fail "left out unnamed: $(cat err)"
"$headingd" score out/imu0/data.estimates.csv mav0/state_groundtruth_estimate0/data.csv --label dir >dir.txt 2>&1 ||
  fail "score of the dataset's replay: $(cat dir.txt)"
echo "ok: replay -r of an EuRoC dataset's folders takes imu0 only (ground truth and camera left out, named); scored: $(grep '^dir ' dir.txt)"
