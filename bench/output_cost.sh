#!/usr/bin/env bash
# what writing the outputs costs against the solve, in instructions (callgrind), for every
# bundled job run the way a user runs it (one thread, --no-report).
# Usage: bench/output_cost.sh [CAMOPT_BINARY] [FORMAT] [JOB_FILTER]   (from the repository root;
# default binary build/camopt, format long (the default), every job; FORMAT wide|npz adds
# --format). Prints a Markdown table: job, total instructions, the solve's, the writing's
# (io::format_csv, io::wide_table or io::format_npz, the summary's JSON text, the staged files) and the
# writing's share.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="$(realpath "${1:-$REPO/build/camopt}")"
FORMAT="${2:-long}"
FILTER="${3:-}"
cd "$REPO"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# name | solve function (a callgrind_annotate name prefix) | arguments (each run gets --out)
jobs=()
for d in eccentric_flat_follower eccentric_offset_roller eccentric_oscillating_roller four_bar offset_slider_crank \
         bucket_tappet roller_finger_follower rocker_arm cvvl_swing_cam vvld valvetronic; do
  jobs+=("kinematics $d --outputs all|camopt::kin::sweep(|kinematics designs/$d.toml --outputs all --step 0.5")
done
jobs+=(
  "kinematics CVVL 17 positions --outputs all|camopt::kin::sweep(|kinematics designs/cvvl_swing_cam.toml --outputs all --control 0:16:17 --step 0.5"
  "synthesize RFF|camopt::synthesis::synthesize(|synthesize designs/targets/rff_intake_lift.csv --design designs/roller_finger_follower.toml"
  "dynamics rigid CVVL 4 speeds x 17 positions|camopt::dynamics::rigid_sweep(|dynamics designs/cvvl_swing_cam.toml --model rigid --rpm 1000:7000:4 --control 0:16:17"
  "dynamics flexible RFF 6000 rpm|camopt::dynamics::run_flexible(|dynamics designs/roller_finger_follower.toml --model flexible --rpm 6000"
)

# the inclusive count of the function whose name starts with $2 in annotation $1 (the largest
# line: an outer overload includes the inner ones)
inclusive() {
  { grep -F ":$2" "$1" || true; } | awk '{ gsub(",", "", $1); if ($1 + 0 > m) m = $1 + 0 } END { print m + 0 }'
}

echo "| job | total | solve | summaries (kinematics) | writing | writing / solve |"
echo "|---|---|---|---|---|---|"
for job in "${jobs[@]}"; do
  name="${job%%|*}"
  rest="${job#*|}"
  solve_fn="${rest%%|*}"
  read -r -a args <<<"${rest#*|}"
  [[ -n "$FILTER" && "$name" != *"$FILTER"* ]] && continue
  extra=()
  if [[ "$FORMAT" != long && "${args[0]}" != synthesize ]]; then
    [[ "$FORMAT" == wide && "$name" == *flexible* ]] || extra=(--format "$FORMAT")
  fi
  out="$work/cg.out"
  valgrind --tool=callgrind --callgrind-out-file="$out" "$BIN" -q --threads 1 "${args[@]}" "${extra[@]}" \
    --out "$work/run" --no-report >/dev/null 2>&1 || { echo "output_cost.sh: failed: ${args[*]}" >&2; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$out" >"$work/ann.txt" 2>/dev/null
  total=$(grep -m1 "PROGRAM TOTALS" "$work/ann.txt" | awk '{ gsub(",", "", $1); print $1 }')
  solve=$(inclusive "$work/ann.txt" "$solve_fn")
  fmt=$(inclusive "$work/ann.txt" "camopt::io::format_csv(")
  npz=$(inclusive "$work/ann.txt" "camopt::io::format_npz(")
  wide=$(inclusive "$work/ann.txt" "camopt::io::wide_table(")
  stage=$(inclusive "$work/ann.txt" "camopt::io::OutputTransaction::stage(")
  dump=$(inclusive "$work/ann.txt" "nlohmann::json_abi_v3_11_2::detail::serializer<")
  summaries=$(inclusive "$work/ann.txt" "camopt::kin::summarize(")
  writing=$((fmt + npz + wide + stage + dump))
  awk -v n="$name" -v t="$total" -v s="$solve" -v m="$summaries" -v w="$writing" \
    'BEGIN { printf "| %s | %.1f M | %.1f M | %.1f M | %.1f M | %.2f |\n", n, t / 1e6, s / 1e6, m / 1e6, w / 1e6, (s > 0 ? w / s : 0) }'
done
