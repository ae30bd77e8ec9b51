#pragma once
// what every `camopt dynamics` model reads from the design and the options
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::cli {

struct DynamicsSetup {
  DesignSpec spec;
  kin::Mechanism mech;
  dynamics::Model model;
  std::vector<double> rpms, control_values;    // engine speeds [rpm]; the first control's positions
  std::vector<std::vector<double>> positions;  // every control, per control position
  double start = 0, stop = 0, step = 0;        // cam angle range and step [cam deg]
  std::string control_unit;                    // "deg" or "mm"
};

}  // namespace camopt::cli
