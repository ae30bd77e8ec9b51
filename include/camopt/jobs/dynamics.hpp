#pragma once
// the dynamics job (camopt dynamics --model rigid | flexible): a design's valvetrain dynamics
// over engine speeds and control positions, as the columns of dynamics.csv and summary.json
// (docs/dynamics.md). The modal analysis (--model modes) is its own job (jobs/modes.hpp).
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "camopt/dynamics/flexible.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// every option of `camopt dynamics` for the rigid and flexible models but its files
struct DynamicsOptions {
  std::string design_file;       // the design's file, as summary.json and the messages name it
  std::string model = "rigid";   // --model: rigid or flexible
  std::string contacts = "rigid";  // --contacts (rigid model): rigid (mode a) or compliant (mode b)
  // --rpm: engine speeds [rpm, crankshaft]: a value, a list a,b,c or START:STOP:COUNT, each in (0, 1e6]
  std::string rpm;
  std::string control;    // --control: the first control's positions [deg or mm] ("": its default)
  double step_deg = 0.0;  // --step: cam angle step [cam deg]; 0: the design's driver.step_deg
  // the flexible model: --revolutions, --start rest (start_at_rest), --coil-displacements,
  // --rtol, --atol
  dynamics::FlexibleOptions flexible;
};

// what `camopt dynamics` writes, in memory
struct DynamicsResult {
  io::Columns columns;     // dynamics.csv: one row per (rpm, control position, cam angle)
  nlohmann::json summary;  // summary.json
  std::size_t positions = 0, points = 0, speeds = 0;  // control positions, cam angles per run, engine speeds
  std::size_t runs = 0;  // time-integrated runs (compliant contacts, flexible): speeds x positions
  double seconds = 0.0;  // the solves' wall time [s]
};

// InputError naming the option for a value out of its range or not one of its list (model,
// contacts, step_deg, an empty rpm, the flexible model's revolutions and tolerances); the
// CLI checks them as it parses them
void validate(const DynamicsOptions& options);

// the rigid model (mode a, or mode b with compliant contacts) or the flexible model: one
// progress step per control position (mode a) or per (rpm, control position) run, notes for
// the held HLAs and the flexible runs' warnings. InputError for bad options or dynamics data;
// NumericalError naming the cam angle, the residual and the control value where a solve
// fails; Cancelled when the observer asks
DynamicsResult run_dynamics(const LoadedDesign& design, const DynamicsOptions& options, Observer& observer);

}  // namespace camopt::jobs
