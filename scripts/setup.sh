#!/usr/bin/env bash
# camopt set-up: install the Debian 12 packages, configure, build, and optionally test and
# run the default design. Safe to run again: it installs, configures and builds only what is
# missing or changed.
set -euo pipefail

# the main job run by --run-default (paths relative to the repo root): synthesize the cam of
# the bundled roller finger follower for a bundled target lift, then run the kinematics of
# the synthesized design with every output at 6000 rpm
DEFAULT_DESIGN="designs/roller_finger_follower.toml"
DEFAULT_TARGET="designs/targets/rff_intake_lift.csv"
DEFAULT_OUT="out/synthesis"
DEFAULT_CHECK_ARGS=(--step 0.5 --outputs all --rpm 6000)


usage() {
  cat <<EOF
usage: scripts/setup.sh [--build-dir DIR] [--type Release|Debug] [--sanitize] [--test] [--run-default]

  --build-dir DIR  build directory (default: build; a relative path is taken from the repo root)
  --type TYPE      CMAKE_BUILD_TYPE: Release (default) or Debug
  --sanitize       build with clang, AddressSanitizer + UndefinedBehaviorSanitizer, and the
                   libFuzzer harnesses (scripts/fuzz.sh --build-dir DIR runs them)
  --test           run the test suite (ctest) and exit with its status
  --run-default    synthesize the cam of $DEFAULT_DESIGN for $DEFAULT_TARGET, results in $DEFAULT_OUT/
EOF
}

die() {
  echo "setup.sh: error: $*" >&2
  exit 1
}

usage_error() {
  echo "setup.sh: $*" >&2
  usage >&2
  exit 2
}

# repo root from the script location, so any cwd works
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

build_dir="build"
build_type="Release"
sanitize="OFF"
run_tests=0
run_default=0
while (($# > 0)); do
  case "$1" in
    --build-dir)
      (($# >= 2)) || usage_error "--build-dir needs a directory"
      build_dir="$2"
      shift 2
      ;;
    --build-dir=*) build_dir="${1#*=}"; shift ;;
    --type)
      (($# >= 2)) || usage_error "--type needs Release or Debug"
      build_type="$2"
      shift 2
      ;;
    --type=*) build_type="${1#*=}"; shift ;;
    --sanitize) sanitize="ON"; shift ;;
    --test) run_tests=1; shift ;;
    --run-default) run_default=1; shift ;;
    -h | --help) usage; exit 0 ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
done
case "$build_type" in
  Release | Debug) ;;
  *) usage_error "--type must be Release or Debug, got '$build_type'" ;;
esac
[[ -n "$build_dir" ]] || usage_error "--build-dir must not be empty"
[[ "$build_dir" = /* ]] || build_dir="$REPO/$build_dir"

jobs="$(nproc)"

# --- packages: apt only when something is missing ---------------------------------------
# shellcheck source=scripts/packages.sh
source "$REPO/scripts/packages.sh"
wanted=("${PACKAGES[@]}")
((run_tests)) && wanted+=("${TEST_PACKAGES[@]}")
[[ "$sanitize" == ON ]] && wanted+=("${CLANG_PACKAGES[@]}")
ensure_packages "${wanted[@]}"
# the npm packages of package-lock.json (uPlot, inlined into every report.html at build time)
ensure_node_modules "$REPO"

# --- configure: only without a cache or when an option changed --------------------------
cache="$build_dir/CMakeCache.txt"
cache_get() { sed -n "s/^$1:[A-Za-z]*=//p" "$cache" | head -n 1; }
as_bool() {
  case "${1^^}" in
    ON | TRUE | YES | Y | 1) echo ON ;;
    *) echo OFF ;;
  esac
}
reason=""
if [[ ! -f "$cache" ]]; then
  reason="new build directory"
elif [[ ! -f "$build_dir/build.ninja" ]]; then
  reason="an earlier configure did not finish"
else
  cached_source="$(cache_get CMAKE_HOME_DIRECTORY)"
  [[ "$cached_source" -ef "$REPO" ]] ||
    die "$build_dir was configured for the sources in '$cached_source'; use another --build-dir"
  cached_generator="$(cache_get CMAKE_GENERATOR)"
  [[ "$cached_generator" == "Ninja" ]] ||
    die "$build_dir was configured with the '$cached_generator' generator, not Ninja; delete it or use another --build-dir"
  if [[ "$(cache_get CMAKE_BUILD_TYPE)" != "$build_type" ]]; then
    reason="build type changed to $build_type"
  elif [[ "$(as_bool "$(cache_get CAMOPT_WERROR)")" != ON ]]; then
    reason="CAMOPT_WERROR changed to ON"
  elif [[ "$(as_bool "$(cache_get CAMOPT_SANITIZE)")" != "$sanitize" ]]; then
    reason="CAMOPT_SANITIZE changed to $sanitize"
  fi
  # the sanitizer build is clang's; CMake cannot change a build directory's compiler
  cached_compiler="$(cache_get CMAKE_CXX_COMPILER)"
  if [[ "$sanitize" == ON && "$cached_compiler" != *clang* ]] || [[ "$sanitize" == OFF && "$(as_bool "$(cache_get CAMOPT_SANITIZE)")" == ON ]]; then
    die "$build_dir was configured with the compiler '$cached_compiler' (sanitize $(as_bool "$(cache_get CAMOPT_SANITIZE)")); the --sanitize build uses clang, the others the default compiler: delete it or use another --build-dir"
  fi
fi
if [[ -n "$reason" ]]; then
  echo "== configuring $build_dir ($build_type, sanitize $sanitize; $reason)"
  cmake_args=(-S "$REPO" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" -DCAMOPT_WERROR=ON)
  if [[ "$sanitize" == ON ]]; then
    # clang: the same instrumented libraries serve the unit tests and the libFuzzer harnesses
    cmake_args+=(-DCAMOPT_SANITIZE=ON -DCAMOPT_BUILD_FUZZ=ON)
    CC=clang CXX=clang++ cmake "${cmake_args[@]}"
  else
    cmake_args+=(-DCAMOPT_SANITIZE=OFF)
    cmake "${cmake_args[@]}"
  fi
else
  echo "== configuring: $build_dir is up to date ($build_type, sanitize $sanitize)"
fi

# --- build: ninja rebuilds only what changed; the main job alone needs only camopt (and the
# Python module, build/python/camopt, when it is built) --------------------------------------
if ((run_default && !run_tests)); then
  targets=(camopt)
  [[ "$(as_bool "$(cache_get CAMOPT_BUILD_PYTHON)")" == ON ]] && targets+=(camopt_python)
  echo "== building ${targets[*]} in $build_dir ($jobs jobs)"
  cmake --build "$build_dir" --parallel "$jobs" --target "${targets[@]}"
else
  echo "== building $build_dir ($jobs jobs)"
  cmake --build "$build_dir" --parallel "$jobs"
fi

# --- test ---------------------------------------------------------------------------------
if ((run_tests)); then
  echo "== testing"
  # the sanitizer build: the font caches fontconfig keeps for the process's life (loaded by
  # cairo when a figure draws text) are not leaks of ours
  # (print_suppressions=0: nothing added to the stderr the CLI tests read)
  [[ "$sanitize" == ON ]] && export LSAN_OPTIONS="suppressions=$REPO/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
  # the sanitizer build leaves out the tests labelled release_only: long sweeps and external
  # processes (Chromium, a consumer project's build) whose C++ paths the rest of the suite runs
  # (tests/release_only.cmake, docs/testing.md "CI")
  ctest_args=()
  if [[ "$sanitize" == ON ]]; then
    ctest_args=(--label-exclude release_only)
    echo "== the sanitizer build skips the tests labelled release_only (they run in the Release suite)"
  fi
  test_status=0
  ctest --test-dir "$build_dir" --output-on-failure --parallel "$jobs" "${ctest_args[@]}" || test_status=$?
  if ((test_status != 0 || !run_default)); then
    exit "$test_status"
  fi
fi

# --- run the default design -----------------------------------------------------------------
if ((run_default)); then
  cd "$REPO"
  [[ -f "$DEFAULT_DESIGN" ]] || die "default design $REPO/$DEFAULT_DESIGN not found"
  [[ -f "$DEFAULT_TARGET" ]] || die "default target $REPO/$DEFAULT_TARGET not found"
  echo "== running: camopt synthesize $DEFAULT_TARGET --design $DEFAULT_DESIGN --out $DEFAULT_OUT"
  "$build_dir/camopt" synthesize "$DEFAULT_TARGET" --design "$DEFAULT_DESIGN" --out "$DEFAULT_OUT"
  echo "== running: camopt kinematics $DEFAULT_OUT/design.toml ${DEFAULT_CHECK_ARGS[*]} --out $DEFAULT_OUT/kinematics"
  "$build_dir/camopt" kinematics "$DEFAULT_OUT/design.toml" "${DEFAULT_CHECK_ARGS[@]}" --out "$DEFAULT_OUT/kinematics"
  echo "== results in $REPO/$DEFAULT_OUT/:"
  ls -l "$DEFAULT_OUT"
  echo "== open the report in a browser: $REPO/$DEFAULT_OUT/kinematics/report.html"
  if [[ -f "$build_dir/python/camopt/__init__.py" ]]; then
    echo "== the Python module: PYTHONPATH=$build_dir/python python3 -c \"import camopt\" (docs/python.md)"
  fi
fi
