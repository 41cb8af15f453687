# shellcheck shell=bash
# Sourced by the command-line tests (their first argument is headingd; the sourcing script reads
# its others itself): strict mode, a scratch directory `dir` removed on exit (kept, and named, with
# KEEP=1, to look at after a failure), and fail().
set -uo pipefail
# shellcheck disable=SC2034  # used by the sourcing script
headingd="$1"
dir="$(mktemp -d)"
[ -z "${KEEP:-}" ] || echo "keeping $dir"
trap '[ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
