#pragma once
// the lift job (camopt lift): a target valve lift from the lift-law library, one cam revolution
// as the columns of the CLI's table, and its figures (docs/cli.md, "lift"). An option not given
// is empty (std::nullopt): the CLI's defaults then apply, and the rules that concern which
// options were given (--duration or --open with --close) read it.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// every option of `camopt lift` but its files; angles [cam deg], lengths [mm]
struct LiftOptions {
  std::string law;                         // --law: the opening flank's law (and the closing one's)
  std::optional<std::string> close_law;    // --close-law (default: --law)
  double lift_mm = 10.0;                   // --lift: maximum lift [mm]
  std::optional<double> duration_deg;      // --duration: the whole event [cam deg] (default 130)
  std::optional<double> open_deg;          // --open: opening flank [cam deg] (with --close)
  std::optional<double> close_deg;         // --close: closing flank [cam deg] (with --open)
  double dwell_deg = 0.0;                  // --dwell [cam deg]
  double ramp_height_mm = 0.0;             // --ramp-height [mm]
  double ramp_length_deg = 0.0;            // --ramp-length [cam deg]
  std::optional<double> close_ramp_height_mm;   // --close-ramp-height (default --ramp-height)
  std::optional<double> close_ramp_length_deg;  // --close-ramp-length (default --ramp-length)
  double ramp_blend = 0.5;                 // --ramp-blend [fraction of each ramp]
  double peak_deg = 180.0;                 // --peak-at [cam deg]
  std::optional<std::vector<double>> acc_controls;  // --acc-bspline (law bspline)
  std::optional<int> bspline_degree;       // --bspline-degree (law bspline; default 3)
  std::optional<double> polydyne_rpm;      // --polydyne-rpm [rpm, crankshaft] (law polydyne)
  std::optional<double> polydyne_hz;       // --polydyne-fn [Hz] (law polydyne)
  double step_deg = 0.25;                  // --step: table step [cam deg], divides 360
  std::string basis = "cam";               // --basis: cam (cam_deg) or crank (crank_deg)
};

// what `camopt lift` writes and prints, in memory
struct LiftResult {
  io::Columns table;       // cam_deg (or crank_deg), lift_mm, vel_mm_per_deg, acc_mm_per_deg2, jerk_mm_per_deg3
  nlohmann::json summary;  // the event's figures [mm, cam deg, per cam deg]: what the notes print
};

// the table of one cycle, 0 <= cam angle < 360, and its summary; the summary's lines as notes
// ("lift: opening ...", "lift: max lift ...", "lift: velocity ..."). InputError naming the
// option (--law, --step, ...) for a bad value or a rule of the lift laws
LiftResult run_lift(const LiftOptions& options, Observer& observer);

}  // namespace camopt::jobs
