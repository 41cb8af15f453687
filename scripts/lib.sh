# shellcheck shell=bash disable=SC2034  # HEADINGD_PACKAGES is for the sourcing script
# Shared by the README's commands: install what is missing, configure and build.
# Sourced, not run. Works as root on a fresh Debian 12; uses sudo otherwise.

HEADINGD_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

# Debian packages the build, the tests and the benchmarks need.
HEADINGD_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev libcli11-dev libtomlplusplus-dev libgpiod-dev libsystemd-dev libzstd-dev zlib1g-dev
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools cyclonedds-dev cyclonedds-tools
  libgtest-dev libgmock-dev gdb libiio-dev
  gnuplot-nox zstd
  clang libclang-rt-14-dev clang-format clang-tidy shellcheck
  openssl systemd systemd-container lintian
)

# Installs the named Debian packages that are not installed yet; does nothing when all are.
ensure_packages() {
  local missing=()
  local pkg
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "headingd: installing ${missing[*]}" >&2
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Configures and builds a CMake preset (default: "default"). With "quiet" as second
# argument the compiler output goes to build/PRESET.log and is shown only on failure.
build_preset() {
  local preset="${1:-default}"
  cd "$HEADINGD_ROOT" || return 1
  if [ "${2:-}" = quiet ]; then
    mkdir -p build
    local log="build/$preset.log"
    if ! { cmake --preset "$preset" && cmake --build --preset "$preset"; } >"$log" 2>&1; then
      tail -n 40 "$log" >&2
      echo "headingd: build failed; full log in $log" >&2
      return 1
    fi
  else
    cmake --preset "$preset" >/dev/null
    cmake --build --preset "$preset"
  fi
}

# The daemon as built at revision SHA (a full commit id of this clone), built once from the
# revision's tree into build/baseline-SHA12 (no checkout of this clone moves); prints its path.
baseline_daemon() {
  local sha="$1" dir="$HEADINGD_ROOT/build/baseline-${1:0:12}"
  local daemon="$dir/src/build/default/app/headingd"
  if [ ! -x "$daemon" ]; then
    echo "building headingd at ${sha:0:12} in $dir (once; log in $dir/build.log)" >&2
    rm -rf "$dir"
    mkdir -p "$dir/src"
    git -C "$HEADINGD_ROOT" archive "$sha" | tar -x -C "$dir/src"
    if ! (cd "$dir/src" && cmake --preset default && cmake --build --preset default --target headingd) \
      >"$dir/build.log" 2>&1; then
      tail -n 30 "$dir/build.log" >&2
      echo "headingd: the baseline at ${sha:0:12} did not build" >&2
      return 1
    fi
  fi
  echo "$daemon"
}

# The arguments of bench/broad_gaps.sh and bench/sim_gaps.sh: NAME, the default gaps (one string),
# then the script's own [BASELINE_REV|-] [GAP_S...]. Sets `gaps` and `binaries` (name=daemon: the
# daemon built here as "after", after the baseline's as "before" when a revision is named).
gap_bench_args() {
  local name="$1" defaults="$2" rev="${3:--}" g sha
  shift 3 || shift $#
  gaps=("$@")
  [ ${#gaps[@]} -eq 0 ] && read -r -a gaps <<<"$defaults"
  for g in "${gaps[@]}"; do
    [[ "$g" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "$name: GAP_S must be a number of seconds, not '$g'" >&2; exit 64; }
  done
  binaries=("after=$HEADINGD_ROOT/build/default/app/headingd")
  [ "$rev" = "-" ] && return 0
  [[ "$rev" =~ ^[0-9A-Za-z_][0-9A-Za-z._/-]*$ ]] || { echo "$name: BASELINE_REV must be a commit, not '$rev'" >&2; exit 64; }
  sha="$(git -C "$HEADINGD_ROOT" rev-parse --verify --quiet "$rev^{commit}")" ||
    { echo "$name: no commit '$rev' in this clone" >&2; exit 64; }
  binaries=("before=$(baseline_daemon "$sha")" "${binaries[@]}")
}
