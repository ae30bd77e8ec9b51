#pragma once
// the summary of one flexible-dynamics run (its reported revolution), shared by
// `dynamics --model flexible` and `optimize --verify`
#include <nlohmann/json.hpp>

#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::jobs {

// lift against kinematic lift (max loss), cam torque, friction power; per connection the
// force extremes and open intervals; seating velocity, bounce count and height (designs
// with a seat); per spring chain the surge amplitude and coil clash; deformation per
// compliant node; the events and the integrator's figures. Keys carry their units.
nlohmann::json flexible_run_summary(const kin::Mechanism& mech, const dynamics::Model& model,
                                    const dynamics::FlexibleResult& r);

}  // namespace camopt::jobs
