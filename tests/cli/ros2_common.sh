# shellcheck shell=bash disable=SC2034  # the variables are for the sourcing script
# Sourced by the tests that run headingd beside the Cyclone DDS ROS 2 peer (tests/interop/ros_peer.c):
# arguments HEADINGD PEER ROOT; what cli_common.sh gives (the scratch directory, fail()), and
# background jobs (those in `pids` too) stopped on exit, and Cyclone's loopback configuration.
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"
peer="$2"
root="$3"
pids=()
# shellcheck disable=SC2046  # the job ids, one word each
trap 'kill "${pids[@]}" $(jobs -p) 2>/dev/null; [ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
export CYCLONEDDS_URI="file://$root/tests/interop/cyclone.xml"
