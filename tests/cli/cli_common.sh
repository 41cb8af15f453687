# shellcheck shell=bash disable=SC2034  # the variables are for the sourcing script
# Sourced by the command-line tests (their first argument is headingd; the sourcing script reads
# its others itself): strict mode, a scratch directory `dir` removed on exit (kept, and named, with
# KEEP=1, to look at after a failure), and fail().
set -uo pipefail
headingd="$1"
dir="$(mktemp -d)"
[ -z "${KEEP:-}" ] || echo "keeping $dir"
trap '[ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
