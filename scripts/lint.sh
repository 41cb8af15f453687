#!/usr/bin/env bash
# clang-format (must be clean) over our C++ sources and the C test peers, clang-tidy (checks in
# .clang-tidy) over the C++ ones; our shell scripts through shellcheck (warnings and errors,
# following what a script sources).
# Usage: bash scripts/lint.sh [--format-only | --shell-only]. clang-tidy needs a configured
# build/default (compile_commands.json).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "not a git checkout: nothing to list the sources with" >&2
  exit 77
fi
# Each from its own folder, as `source "$(dirname "$0")/…"` finds its file there.
lint_shell() {
  local scripts bad=0 f
  mapfile -t scripts < <(git ls-files '*.sh' .ci/run packaging/postinst packaging/prerm packaging/postrm packaging/iio-permissions)
  for f in "${scripts[@]}"; do
    (cd "$(dirname "$f")" && shellcheck -S warning -x "$(basename "$f")") || bad=1
  done
  [ "$bad" -eq 0 ] || return 1
  echo "shellcheck: ${#scripts[@]} scripts clean"
}
if [ "${1:-}" = "--shell-only" ]; then
  lint_shell
  exit
fi
mapfile -t sources < <(git ls-files '*.cpp' '*.hpp' '*.c' | grep -v '^idl/')
clang-format --dry-run --Werror "${sources[@]}"
echo "clang-format: ${#sources[@]} files clean"
[ "${1:-}" = "--format-only" ] && exit 0
lint_shell
[ -f build/default/compile_commands.json ] || { echo "configure first: cmake --preset default" >&2; exit 1; }
mapfile -t units < <(printf '%s\n' "${sources[@]}" | grep '\.cpp$' | grep -v '^fuzz/')
report="$(mktemp)"
trap 'rm -f "$report"' EXIT
printf '%s\n' "${units[@]}" | xargs -P"$(nproc)" -n1 clang-tidy -p build/default --quiet 2>/dev/null |
  grep -E 'warning:|error:' | sort -u >"$report" || true
cat "$report"
echo "clang-tidy: ${#units[@]} files, $(wc -l <"$report") findings"
