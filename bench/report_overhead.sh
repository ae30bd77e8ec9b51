#!/usr/bin/env bash
# the report's cost: wall time of the bundled jobs with and without --no-report, best of N
# (default 5), the runs of a job alternated so that a load from outside hits both alike.
# Usage: bench/report_overhead.sh [CAMOPT_BINARY] [REPEATS]   (from the repository root;
# default binary build/camopt). Prints a Markdown table: job, best with, best without, overhead,
# and the best time of `camopt report` rebuilding the job's report alone (process start included):
# an upper bound of the report's share that the machine's noise does not blur as much.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="$(realpath "${1:-$REPO/build/camopt}")"
REPEATS="${2:-5}"
cd "$REPO"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# name | arguments (each run gets --out <folder>)
jobs=(
  "synthesize default|synthesize designs/targets/rff_intake_lift.csv --design designs/roller_finger_follower.toml"
  "kinematics CVVL 17 positions, --outputs all|kinematics designs/cvvl_swing_cam.toml --outputs all --control 0:16:17 --step 0.5"
  "optimize RFF passenger car|optimize designs/roller_finger_follower.toml --constraints constraints/passenger_car_intake.toml --points 720"
  "dynamics rigid CVVL, 4 speeds|dynamics designs/cvvl_swing_cam.toml --model rigid --rpm 1000:7000:4"
  "dynamics flexible RFF|dynamics designs/roller_finger_follower.toml --model flexible --rpm 6000"
)

# wall time of one run [s]
wall() {
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>&1 || { echo "report_overhead.sh: failed: $*" >&2; exit 1; }
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f\n", b - a }' 
}
min() { printf '%s\n' "$@" | sort -g | head -n 1; }

echo "| job | with report [s] | --no-report [s] | overhead | camopt report alone [s] |"
echo "|---|---|---|---|---|"
for job in "${jobs[@]}"; do
  name="${job%%|*}"
  read -r -a args <<<"${job#*|}"
  with=() without=() alone=()
  for ((i = 0; i < REPEATS; ++i)); do
    with+=("$(wall "$BIN" -q --threads 2 "${args[@]}" --out "$work/with")")
    without+=("$(wall "$BIN" -q --threads 2 "${args[@]}" --out "$work/without" --no-report)")
    alone+=("$(wall "$BIN" report "$work/with")")
  done
  a=$(min "${with[@]}")
  b=$(min "${without[@]}")
  c=$(min "${alone[@]}")
  awk -v n="$name" -v a="$a" -v b="$b" -v c="$c" \
    'BEGIN { printf "| %s | %.3f | %.3f | %+.1f %% | %.3f (%.0f %%) |\n", n, a, b, (a / b - 1) * 100, c, c / b * 100 }' 
done
