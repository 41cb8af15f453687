#!/usr/bin/env bash
# The README's second command: installs what is missing, builds, and runs the whole test
# suite with ctest — optimised first, then again under AddressSanitizer + UBSan.
# Exits non-zero on any failure.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"

jobs="$(nproc)"
for preset in default asan; do
  echo "== build and test: $preset"
  build_preset "$preset"
  ctest --preset "$preset" -j "$jobs"
done
