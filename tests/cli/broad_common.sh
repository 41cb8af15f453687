# shellcheck shell=bash
# Shared by broad_trials.sh and broad_moving_start.sh (sourced, with their three arguments):
# a scratch directory, and one replay scored against the BROAD truth as a ratio to a reference.
# Arguments of the sourcing script: HEADINGD BROAD_HEADING_ERROR DATA_ROOT
source "$(dirname "$0")/cli_common.sh"
score="$2"
data="$3"
[ -d "$data/broad-05" ] || { echo "SKIP: no $data/broad-05"; exit 77; }

# check_ratio LABEL IMU TRUTH REFERENCE_LINE MAX [MIN_WITHIN]: replays IMU with auto, scores it,
# checks that `headingd score` reads the same figures off the same estimates (with MIN_WITHIN),
# and fails if auto's heading RMSE over the reference (the figure on the scorer's line matching
# REFERENCE_LINE) is above MAX, or, given MIN_WITHIN, if fewer than that percentage of the moving
# samples lie within auto's own 2 sigma.
check_ratio() {
  local label="$1" imu="$2" truth="$3" reference_line="$4" max="$5" min_within="${6:-}" out reference auto ratio within
  "$headingd" replay --no-dds --quiet "$imu" --output-rate 0 -o "$dir/est.csv" 2>/dev/null ||
    fail "$label: replay failed"
  out=$("$score" "$truth" "$imu" "auto=$dir/est.csv") || fail "$label: $out"
  reference=$(sed -n "s/.*${reference_line} *\([0-9.]*\).*/\1/p" <<<"$out")
  auto=$(sed -n 's/.*headingd auto *\([0-9.]*\).*/\1/p' <<<"$out")
  [ -n "$reference" ] && [ -n "$auto" ] || fail "$label: no figures in: $out"
  ratio=$(awk -v a="$auto" -v r="$reference" 'BEGIN { printf "%.3f", a / r }')
  echo "$label: auto $auto deg, $reference_line $reference deg, ratio $ratio (at most $max)"
  awk -v x="$ratio" -v m="$max" 'BEGIN { exit !(x <= m) }' || fail "$label: auto/reference $ratio above $max"
  [ -n "$min_within" ] || return 0
  within=$(sed -n 's/.*headingd auto .*2 sigma on \([0-9.]*\) %.*/\1/p' <<<"$out")
  [ -n "$within" ] || fail "$label: no share within 2 sigma in: $out"
  # `headingd score` against the same orientation truth gives the same moving RMSE and share.
  local scored scored_rms scored_within
  scored=$("$headingd" score "$dir/est.csv" "$truth" --label est 2>&1) || fail "$label: headingd score: $scored"
  scored_rms=$(awk '$1 == "est" && $2 == "moving" { print $5 }' <<<"$scored")
  scored_within=$(sed -n 's/.*, \([0-9.]*\) % of the [0-9]* moving$/\1/p' <<<"$scored")
  [ "$scored_rms $scored_within" = "$auto $within" ] ||
    fail "$label: headingd score says RMSE '$scored_rms', within '$scored_within'; the scorer $auto, $within: $scored"
  echo "$label: $within % of the moving samples within 2 sigma (at least $min_within)"
  awk -v x="$within" -v m="$min_within" 'BEGIN { exit !(x >= m) }' ||
    fail "$label: only $within % within 2 sigma, below $min_within"
}
