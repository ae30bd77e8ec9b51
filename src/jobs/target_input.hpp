#pragma once
// a target valve lift from a csv (cam_deg or crank_deg, lift_mm), fitted by
// synthesis::fit_target_lift; shared by `synthesize` and `optimize`
#include <string>

#include "camopt/core/design_spec.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"
#include "camopt/synthesis/target_lift.hpp"

namespace camopt::jobs {

struct ValveTarget {
  synthesis::TargetLift fit;
  io::AngleBasis basis = io::AngleBasis::cam;
  std::size_t rows = 0;
};

ValveTarget read_valve_target(const io::CsvTable& table, const std::string& path, const DesignSpec& spec,
                              const synthesis::TargetLiftOptions& options, Observer& observer);

}  // namespace camopt::jobs
