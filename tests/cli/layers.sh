#!/usr/bin/env bash
# The layer rules hold on the tree, and the checker does catch a new violation of each rule.
set -uo pipefail
root="$1"
check="$root/tests/check_layers.sh"
fail() { echo "FAIL: $*"; exit 1; }
bash "$check" "$root" || fail "the tree breaks the layers"

dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
for folder in core io hw sim dds service pipeline tools app; do cp -r "$root/$folder" "$dir/"; done
bash "$check" "$dir" >/dev/null || fail "a copy of the tree does not pass"
expect() {  # FILE LINE PATTERN: adding LINE to FILE must be reported with PATTERN
  cp "$dir/$1" "$dir/$1.orig"
  echo "$2" >>"$dir/$1"
  out="$(bash "$check" "$dir")" && fail "not caught: $2 in $1"
  grep -qF -- "$3" <<<"$out" || fail "$2 in $1: reported as: $out"
  mv "$dir/$1.orig" "$dir/$1"
  echo "ok: caught $2 in $1"
}
expect core/units.hpp '#include "io/csv_out.hpp"' "core/ may include only from core"
expect core/units.hpp '#include <fastdds/dds/core/Entity.hpp>' "core/ is C++ and Eigen only"
expect dds/dds_node.hpp '#include "core/estimator.hpp"' "never the estimator"
expect io/csv_out.hpp '#include "pipeline/pipeline.hpp"' "io/ may include only from core io"
expect pipeline/pacer.hpp '#include "sim/scenarios.hpp"' "pipeline/ may include only from"
expect app/job.cpp '#include "sim/scenarios.hpp"' "only through live_source"
