#!/usr/bin/env bash
# Regenerates the expected outputs of the recorded regressions under tests/data/.
# This is a reviewed step: run it only when a change of the estimates is intended, then read
# `git diff --stat tests/data` and explain the change in the commit message.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
build_preset default quiet
headingd="$HEADINGD_ROOT/build/default/app/headingd"
data="$HEADINGD_ROOT/tests/data"
for method in a b c auto; do
  "$headingd" replay --no-dds "$data/agv-1min/imu.csv" --method "$method" --output "$data/agv-1min/expected-$method.csv" --quiet
done
for method in c auto; do
  "$headingd" replay --no-dds "$data/broad-05-excerpt/imu.csv" --method "$method" --output "$data/broad-05-excerpt/expected-$method.csv" --quiet
done
git -C "$HEADINGD_ROOT" diff --stat -- tests/data || true
