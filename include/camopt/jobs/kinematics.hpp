#pragma once
// the kinematics job (camopt kinematics): a design's kinematic sweep over the cam cycle and
// control range, as the columns of kinematics.csv (long format) and summary.json.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// every option of `camopt kinematics` but its files (--out, the report)
struct KinematicsOptions {
  std::string design_file;  // the design's file, as summary.json and the messages name it
  // --control: positions of the design's first control [deg or mm]: a value, a list a,b,c or
  // START:STOP:COUNT ("": the control's default)
  std::string control;
  // --outputs: a comma list of lift, velocity, acceleration, jerk, nodes, contacts, all,
  // node:NAME (that node's columns), contact:NAME (that contact's columns)
  std::string outputs = "lift,velocity,acceleration,jerk";
  double step_deg = 0.0;    // --step: driver step [cam deg, or mm for a translating driver]; 0: the design's
  double rpm = 0.0;         // --rpm: engine speed [rpm, crankshaft]; 0: no SI columns
  std::string duration_at;  // --duration-at: heights [mm, in or deg] ("": 1 and 0.1 in the output's unit)
  int threads = 1;          // worker threads, at most one per control position
};

// what `camopt kinematics` writes, in memory
struct KinematicsResult {
  io::Columns columns;     // kinematics.csv: one row per (control position, driver point)
  nlohmann::json summary;  // summary.json
  std::size_t positions = 0, points = 0;  // control positions, driver points per position
  double seconds = 0.0;                   // the sweep's wall time [s]
};

// InputError naming the option for a value out of its range (step_deg, rpm < 0, rpm > 1e6,
// threads < 1), or an --outputs item that is not one of the list (run_kinematics also checks
// the names of node:NAME and contact:NAME against the design); the CLI checks the numbers
// as it parses them
void validate(const KinematicsOptions& options);

// the sweep and its summaries: notes per control position ("kinematics: ..."), one progress
// step per position. InputError for bad options or a design without the control asked for;
// NumericalError naming the angle, the residual and the control value where a solve fails;
// Cancelled when the observer asks
KinematicsResult run_kinematics(const LoadedDesign& design, const KinematicsOptions& options, Observer& observer);

}  // namespace camopt::jobs
