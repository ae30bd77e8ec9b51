#pragma once
// what every dynamics model reads from the design and the options, and the grid of
// time-integrated runs (rpm x control position) of the compliant and flexible models
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

struct DynamicsSetup {
  const DesignSpec& spec;      // the design as parsed
  const kin::Mechanism& mech;  // compiled from it
  Observer& observer;          // the job's notes and steps
  dynamics::Model model;       // its dynamics data
  std::vector<double> rpms;    // engine speeds [rpm]
  ControlPositions controls;   // the first control's positions, every control per position
  DriverRange range;           // cam angle range and step [cam deg]
};

// summary.json's keys of the rigid model's two modes: the design, its HLAs held rigid (a note
// naming `what` ran), the design file, the model, `mode` and the step
nlohmann::json rigid_summary_head(const DynamicsSetup& su, const std::string& design_file, const std::string& what,
                                  const std::string& mode);

// one time-integrated run per (rpm, control position) of the setup, in that nesting order
template <class Result>
struct GridRun {
  double rpm;
  std::size_t position;
  Result result;
};

// runs `integrate(rpm, controls, result)` over the grid, one observer step per run (a cancel
// stops it there, and a run that says it was interrupted); a failure stops with its control
// position named
template <class Result, class Integrate>
std::vector<GridRun<Result>> run_grid(const DynamicsSetup& su, Integrate&& integrate) {
  std::vector<GridRun<Result>> runs;
  su.observer.begin("dynamics", static_cast<long>(su.rpms.size() * su.controls.positions.size()));
  StepCounter steps(su.observer);
  for (double rpm : su.rpms)
    for (std::size_t p = 0; p < su.controls.positions.size(); ++p) {
      GridRun<Result> r{rpm, p, {}};
      const Status st = integrate(rpm, su.controls.positions[p], r.result);
      if (st.code == StatusCode::interrupted) throw Cancelled();
      if (!st.ok()) fail_at_position(su.mech, su.controls, st, p);
      runs.push_back(std::move(r));
      steps.step_done();
    }
  su.observer.end();
  return runs;
}

}  // namespace camopt::jobs
