#!/usr/bin/env bash
# Build the benchmarks (build-bench/, Release) and run them; each prints its work-precision
# table and writes it to bench/results/<name>.csv. Usage: scripts/bench.sh [NAME...] with
# NAME in kinematics synthesis optimize dynamics (default: all). Extra arguments for one
# benchmark: BENCH_ARGS_<NAME>, e.g. BENCH_ARGS_kinematics="--repeat 7 --threads 2".
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="$REPO/build-bench"
names=("$@")
((${#names[@]} > 0)) || names=(kinematics synthesis optimize dynamics)
for name in "${names[@]}"; do
  case "$name" in
    kinematics | synthesis | optimize | dynamics) ;;
    *) echo "bench.sh: unknown benchmark '$name' (kinematics, synthesis, optimize, dynamics)" >&2; exit 2 ;;
  esac
done

if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  cmake -S "$REPO" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCAMOPT_BUILD_BENCH=ON -DCAMOPT_BUILD_TESTS=OFF
fi
cmake --build "$build_dir" --parallel "$(nproc)" --target "${names[@]/#/bench_}"

mkdir -p "$REPO/bench/results"
cd "$REPO"
for name in "${names[@]}"; do
  extra_var="BENCH_ARGS_$name"
  read -r -a extra <<<"${!extra_var:-}"
  echo "== bench_$name ${extra[*]} --csv bench/results/$name.csv"
  "$build_dir/bench/bench_$name" "${extra[@]}" --csv "bench/results/$name.csv"
done
