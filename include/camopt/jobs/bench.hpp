#pragma once
// the bench job (camopt bench): a user's own design timed stage by stage (the kinematic sweep
// with the lift only and with every output, the synthesis of its cam from its own lift, a
// rigid and a flexible dynamics cycle), each stage run at its default setting and at a tighter
// one, with the default run's error against the tight run: a work-precision table.
#include <limits>
#include <string>
#include <vector>

#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// every option of `camopt bench` but its files
struct BenchOptions {
  std::string design_file;  // the design's file, as the messages name it
  std::string control;      // --control: one position of the design's first control ("": its default)
  double rpm = 6000.0;      // --rpm: engine speed of the dynamics runs [rpm, crankshaft]
  int repeat = 3;           // --repeat: a default run's time is the best of this many runs
};

// one run of a stage (a number that does not apply is NaN: an empty cell)
struct BenchRow {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string stage;    // "kinematics lift", "kinematics all", "synthesis", "rigid", "flexible"
  std::string run;      // "default" or "tight"
  std::string setting;  // what the two runs differ in: "step 1 deg", "points 1440", "rtol 1e-06 atol 1e-07"
  double points = kNone;        // output points: cam angles (synthesis: profile table points)
  double time_ms = kNone;       // best wall time of the run [ms]; flexible: per cam revolution
  double ns_per_point = kNone;  // time_ms / points [ns]
  // kinematics: lift between the grid points (linear interpolation) against the tight run's
  // finer grid; synthesis: the round trip (forward lift of the made cam against the target);
  // flexible: the valve lift against the tight run, max over the cycle [mm]
  double lift_error_mm = kNone;
  // rigid, flexible: the peak contact force against the tight run's, the largest over the
  // contacts, relative to the tight run's peak
  double force_error_rel = kNone;
  // rigid: the separation speed against the tight run's, the largest over the contacts [rpm]
  double separation_error_rpm = kNone;
  std::string note;  // a skipped stage: why
};

struct BenchResult {
  std::vector<BenchRow> rows;  // per stage: the default run, then the tight run
};

// InputError naming the option for a value out of its range (rpm in (0, 1e6], repeat in
// [1, 1000])
void validate(const BenchOptions& options);

// every stage of the design: a stage the design cannot run (no cam to re-synthesize, no
// dynamics data) is a row with its reason. InputError for bad options or a bad control;
// NumericalError where a solve fails
BenchResult run_bench(const LoadedDesign& design, const BenchOptions& options, Observer& observer);

// the table as CSV (units in the headers, numbers shortest round-trip) and as aligned text
std::string bench_csv(const BenchResult& result);
std::string bench_text(const BenchResult& result);

}  // namespace camopt::jobs
