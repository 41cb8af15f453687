#!/usr/bin/env bash
# Real data: the five BROAD trials in ../shared/data (slow and fast rotation, tapping, a vibrating
# phone), heading RMSE during movement for auto and the paper's C beside the gyro-only reference
# with the first rest's bias (bench/broad05.sh on each; see ../shared/data/README.md).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
data="$here/../../shared/data"
for trial in broad-01 broad-05 broad-08 broad-24 broad-26; do
  bash "$here/broad05.sh" "$data/$trial" | sed "s/BROAD trial 05/$trial/"
done
