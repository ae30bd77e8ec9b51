#!/usr/bin/env bash
# Fuzz the input readers with libFuzzer (clang, ASan + UBSan): build tests/fuzz/fuzz_* in
# build-fuzz, then run each target for a time budget from the seeds of tests/fuzz/seeds.txt
# plus every earlier crash (tests/fuzz/regressions/<target>/). A crash leaves its input in
# build-fuzz/crashes/<target>/ and fails the run: copy it to tests/fuzz/regressions/<target>/
# (the normal test suite replays it), then fix the reader.
set -euo pipefail

usage() {
  cat <<EOF2
usage: scripts/fuzz.sh [--seconds N] [--build-dir DIR] [TARGET...]

  --seconds N     time budget per target (default 60)
  --build-dir DIR clang build directory (default: build-fuzz); the sanitizer build of
                  scripts/setup.sh --sanitize has the harnesses too
  TARGET          target_lift_csv, design_toml, constraint_toml (default: all)
EOF2
}
die() {
  echo "fuzz.sh: error: $*" >&2
  exit 1
}

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds=60
build_dir="build-fuzz"
targets=()
while (($# > 0)); do
  case "$1" in
    --seconds)
      (($# >= 2)) || die "--seconds needs a number"
      seconds="$2"
      shift 2
      ;;
    --build-dir)
      (($# >= 2)) || die "--build-dir needs a directory"
      build_dir="$2"
      shift 2
      ;;
    -h | --help) usage; exit 0 ;;
    -*) usage >&2; die "unknown option '$1'" ;;
    *) targets+=("$1"); shift ;;
  esac
done
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || die "--seconds must be a positive integer, got '$seconds'"
[[ "$build_dir" = /* ]] || build_dir="$REPO/$build_dir"
((${#targets[@]} > 0)) || targets=(target_lift_csv design_toml constraint_toml)

# shellcheck source=scripts/packages.sh
source "$REPO/scripts/packages.sh"
ensure_packages "${PACKAGES[@]}" "${CLANG_PACKAGES[@]}"
# the configure inlines the report page's uPlot from node_modules
ensure_node_modules "$REPO"

# configure without a finished configure (no build.ninja: none yet, or an earlier one failed)
if [[ ! -f "$build_dir/CMakeCache.txt" || ! -f "$build_dir/build.ninja" ]]; then
  # -O1 with line tables only: the instrumented build compiles in about 70 % of the time of
  # RelWithDebInfo (-O2 -g), and a crash's stack trace still names file and line
  CC=clang CXX=clang++ cmake -S "$REPO" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
    -DCAMOPT_BUILD_FUZZ=ON -DCAMOPT_BUILD_TESTS=OFF
elif ! grep -q '^CAMOPT_BUILD_FUZZ:BOOL=ON' "$build_dir/CMakeCache.txt"; then
  die "$build_dir has no fuzz harnesses (CAMOPT_BUILD_FUZZ is off): use a build of scripts/setup.sh --sanitize, or another --build-dir"
fi
cmake --build "$build_dir" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

status=0
for target in "${targets[@]}"; do
  corpus="$build_dir/corpus/$target"
  crashes="$build_dir/crashes/$target"
  mkdir -p "$corpus" "$crashes"
  # seeds: the listed directories, then the crash regressions
  while read -r name dir extension; do
    [[ -z "$name" || "$name" == \#* || "$name" != "$target" ]] && continue
    cp -f "$REPO/$dir"/*"$extension" "$corpus"/
  done <"$REPO/tests/fuzz/seeds.txt"
  if compgen -G "$REPO/tests/fuzz/regressions/$target/*" >/dev/null; then
    cp -f "$REPO/tests/fuzz/regressions/$target"/* "$corpus"/
  fi
  echo "== fuzzing $target for $seconds s (corpus $(find "$corpus" -type f | wc -l) files)"
  # libFuzzer resolves relative profile paths of designs against the source tree (fuzz_entry.cpp)
  log="$build_dir/fuzz_$target.log"
  if ! (cd "$REPO" && "$build_dir/tests/fuzz/fuzz_$target" "$corpus" -max_total_time="$seconds" -max_len=16384 \
    -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$crashes/" >"$log" 2>&1); then
    grep -E "fuzz target|ERROR|runtime error" "$log" | head -n 5 || true
    tail -n 25 "$log"
    echo "== $target: FAILED (log $log); crash inputs in $crashes/ (copy them to tests/fuzz/regressions/$target/)"
    status=1
  else
    grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)" "$log" || true
  fi
done
exit "$status"
