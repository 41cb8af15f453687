#!/usr/bin/env bash
# The README's second command: installs what is missing, builds, and runs the whole test
# suite with ctest — optimised first, then again under AddressSanitizer + UBSan — and then each
# libFuzzer target for HEADINGD_FUZZ_SECONDS (default 60). Exits non-zero on any failure.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
ensure_packages "${HEADINGD_PACKAGES[@]}"

jobs="$(nproc)"
for preset in default asan; do
  echo "== build and test: $preset"
  build_preset "$preset"
  # The 200 ms stop limit of tests/cli/exit_paths.sh is the optimised build's; under the
  # sanitizers everything runs two to three times slower (one run took 214 ms there).
  limit=200
  [ "$preset" = asan ] && limit=600
  HEADINGD_STOP_LIMIT_MS="${HEADINGD_STOP_LIMIT_MS:-$limit}" ctest --preset "$preset" -j "$jobs"
done

echo "== fuzz: each target ${HEADINGD_FUZZ_SECONDS:-60} s"
cd "$HEADINGD_ROOT"
cmake --preset fuzz -DHEADINGD_FUZZ_SECONDS="${HEADINGD_FUZZ_SECONDS:-60}" >/dev/null
cmake --build --preset fuzz
ctest --preset fuzz -j "$jobs"
