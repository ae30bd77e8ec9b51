#pragma once
// the outputs of `camopt dynamics --model rigid` (docs/dynamics.md, "dynamics.csv" and
// "summary.json"), from one rigid sweep per control position
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/csv.hpp"
#include "dynamics_setup.hpp"

namespace camopt::jobs {

// dynamics.csv's columns: long format, one row per (rpm, control position, cam angle)
io::Columns rigid_columns(const DynamicsSetup& su, const std::vector<dynamics::RigidSweep>& sweeps);

// summary.json: the run, per control position the separation speeds, per (rpm, control
// position) the torque, connection, spring and pivot extremes, and with [oil] the films
nlohmann::json rigid_summary(const DynamicsSetup& su, const std::string& design_file,
                             const std::vector<dynamics::RigidSweep>& sweeps, double seconds);

}  // namespace camopt::jobs
