#pragma once
// the outputs of `camopt dynamics --model flexible`: dynamics.csv (valve motion, connection,
// seat and spring forces, cam torque, deformations) and summary.json (the model parameters,
// every run's summary and the speed map)
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/dynamics/flexible.hpp"
#include "camopt/io/csv.hpp"
#include "dynamics_setup.hpp"

namespace camopt::jobs {

using FlexibleRun = GridRun<dynamics::FlexibleResult>;

// dynamics.csv's columns: long format, one row per (rpm, control position, cam angle)
io::Columns flexible_columns(const DynamicsSetup& su, const std::vector<FlexibleRun>& runs, bool coil_displacements);

// summary.json; a run far off its linearised gap or without a periodic steady state is
// also a warning on stderr
nlohmann::json flexible_summary(const DynamicsSetup& su, const std::string& design_file,
                                const dynamics::FlexibleOptions& options, const std::vector<FlexibleRun>& runs,
                                double seconds);

}  // namespace camopt::jobs
