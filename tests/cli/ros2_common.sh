# shellcheck shell=bash disable=SC2034  # the variables are for the sourcing script
# Sourced by the tests that run headingd beside the Cyclone DDS ROS 2 peer (tests/interop/ros_peer.c):
# arguments HEADINGD PEER ROOT, a scratch directory (kept with KEEP=1), background jobs (those in
# `pids` too) stopped on exit, fail(), and Cyclone's loopback configuration.
set -uo pipefail
headingd="$1"
peer="$2"
root="$3"
dir="$(mktemp -d)"
[ -z "${KEEP:-}" ] || echo "keeping $dir"
pids=()
# shellcheck disable=SC2046  # the job ids, one word each
trap 'kill "${pids[@]}" $(jobs -p) 2>/dev/null; [ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
export CYCLONEDDS_URI="file://$root/tests/interop/cyclone.xml"
