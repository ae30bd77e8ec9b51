#pragma once
// the outputs of `camopt dynamics --model rigid --contacts compliant` (mode (b)): dynamics.csv
// with the rigid mode (a) force beside each integrated one, and summary.json with every run's
// force extremes, contact stiffness and events
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/csv.hpp"
#include "dynamics_setup.hpp"

namespace camopt::jobs {

using CompliantRun = GridRun<dynamics::CompliantResult>;

// dynamics.csv's columns: long format, one row per (rpm, control position, cam angle); rigid: the mode
// (a) sweep of every control position
io::Columns compliant_columns(const DynamicsSetup& su, const std::vector<CompliantRun>& runs,
                              const std::vector<dynamics::RigidSweep>& rigid);

// summary.json: the run and, per (rpm, control position), the integrator's counts, every
// connection's force extremes and stiffness, and the contact events
nlohmann::json compliant_summary(const DynamicsSetup& su, const std::string& design_file,
                                 const std::vector<CompliantRun>& runs, double seconds);

}  // namespace camopt::jobs
