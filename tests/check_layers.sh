#!/usr/bin/env bash
# Layers point one way: an #include may only reach the folders below its own (see
# docs/architecture.md). Fails naming every include that breaks a rule:
#  - each folder includes only from the folders listed for it below;
#  - core/ includes nothing but core/, Eigen and the C++ standard library;
#  - no file of the DDS layer includes an estimator header (it sees Estimate and Diagnostics);
#  - in app/, only the sensor factory (live_source) reaches the simulator.
# Usage: check_layers.sh [SOURCE_ROOT]
set -uo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$root" || exit 2

declare -A allowed=(
  [core]="core"
  [io]="core io"
  [hw]="core io hw"
  [sim]="core io hw sim"
  [dds]="core dds"
  [service]="core io hw dds service"
  [pipeline]="core io dds service pipeline"
  [tools]="core io sim dds service pipeline tools"
  [app]="core io hw sim dds service pipeline tools app"
)
estimator_headers="core/estimator.hpp core/auto_estimator.hpp core/paper_estimator.hpp core/bias_tracker.hpp"

problems=0
report() {
  echo "$1"
  problems=$((problems + 1))
}
checked=0
quoted_include='^[[:space:]]*#[[:space:]]*include[[:space:]]*"([^"]*)"'
system_include='^[[:space:]]*#[[:space:]]*include[[:space:]]*<([^>]*)>'
for folder in "${!allowed[@]}"; do
  [ -d "$folder" ] || { report "$folder/: missing (a layer was renamed? update tests/check_layers.sh)"; continue; }
  while IFS= read -r file; do
    checked=$((checked + 1))
    while IFS=: read -r line text; do
      # bash's own matching, not a sed per line: this runs over every include of the tree, eight
      # times in lint.layers.
      target="" system=""
      if [[ "$text" =~ $quoted_include ]]; then
        target="${BASH_REMATCH[1]}"
      elif [[ "$text" =~ $system_include ]]; then
        system="${BASH_REMATCH[1]}"
      fi
      if [ -n "$target" ]; then
        case "$target" in
          */*)
            layer="${target%%/*}"
            [[ " ${allowed[$folder]} " == *" $layer "* ]] ||
              report "$file:$line: includes $target: $folder/ may include only from ${allowed[$folder]}"
            if [ "$folder" = dds ] && [[ " $estimator_headers " == *" $target "* ]]; then
              report "$file:$line: includes $target: the DDS layer maps Estimate and Diagnostics, never the estimator"
            fi
            if [ "$folder" = app ] && [ "$layer" = sim ] && [[ "$file" != app/live_source.* ]]; then
              report "$file:$line: includes $target: the app reaches the simulator only through live_source"
            fi
            ;;
          *)  # generated DDS types (idl/), for the layers that speak DDS
            [[ " dds tools app " == *" $folder "* ]] || report "$file:$line: includes \"$target\" outside a layer"
            ;;
        esac
      elif [ -n "$system" ] && [ "$folder" = core ]; then
        [[ "$system" == Eigen/* || "$system" =~ ^[a-z_]+$ ]] ||
          report "$file:$line: includes <$system>: core/ is C++ and Eigen only"
      fi
    done < <(grep -n '^[[:space:]]*#[[:space:]]*include' "$file")
  done < <(find "$folder" -name '*.hpp' -o -name '*.cpp' | sort)
done
if [ "$problems" -gt 0 ]; then
  echo "FAIL: $problems include(s) break the layers"
  exit 1
fi
echo "ok: $checked files, every include points down"
