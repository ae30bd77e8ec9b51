// the round trip of a synthesized design (envelope.hpp): its forward kinematics against the
// target motion, with the largest pressure angle at the designed contact.
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::synthesis {

Status round_trip(const DesignSpec& spec, const PeriodicSpline& lift, const std::vector<double>& controls,
                  const std::string& connection, RoundTrip& out, const std::string& target_node) {
  const kin::Mechanism mech = kin::compile(spec);
  kin::SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0;
  s.step = 0.25;
  s.request = {1, true};
  const std::vector<double> pos = controls.empty() ? mech.default_controls() : controls;
  s.control_positions = {pos};
  const kin::SweepResult r = kin::sweep(mech, s);
  const auto& p = r.positions[0];
  if (!p.status.ok()) return p.status;
  const int target_index = target_node.empty() ? mech.output_node : mech.node_index(target_node);
  CAMOPT_THROW_UNLESS(target_index >= 0, "round_trip: target_node = '" + target_node + "' must be a node of design '" +
                                             spec.name + "'");
  const int out_var = mech.nodes[target_index].first_variable;
  // internal units (rad or mm) against the target; valve lift from its rest position
  const double rest = target_node.empty() ? mech.nodes[target_index].rest : 0.0;
  const double to_internal = mech.variables[out_var].is_angle ? rad_per_deg : 1.0;
  int ci = -1;
  for (int i = 0; i < static_cast<int>(mech.connections.size()); ++i)
    if (mech.connections[i].name == connection) ci = i;
  out = {};
  double sum = 0.0;
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    const double target = lift(r.driver[i] * pi / 180);
    const double got = p.value(i, out_var, 0) * to_internal - rest;
    const double e = std::abs(got - target);
    sum += e * e;
    if (e > out.max_error_mm) out.max_error_mm = e, out.max_error_at_deg = r.driver[i];
    if (ci >= 0) {
      const double pa = p.contacts[i * mech.connections.size() + ci].pressure_angle * 180 / pi;
      if (pa > out.max_pressure_angle_deg) out.max_pressure_angle_deg = pa, out.max_pressure_angle_at_deg = r.driver[i];
    }
  }
  out.rms_error_mm = std::sqrt(sum / static_cast<double>(r.driver.size()));
  return Status::success();
}

}  // namespace camopt::synthesis
