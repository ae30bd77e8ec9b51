// mode (a) over a sweep: every quantity split by load case at each driver angle, and what
// follows from the split: the separation speed of a contact and the spring margin (rigid.hpp)
#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/rigid.hpp"

namespace camopt::dynamics {

Status rigid_sweep(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                   double start_deg, double stop_deg, double step_deg, RigidSweep& out) {
  CAMOPT_THROW_UNLESS(step_deg > 0, "rigid_sweep: step_deg = " + format_value(step_deg) + " must be > 0");
  CAMOPT_THROW_UNLESS(stop_deg >= start_deg, "rigid_sweep: stop_deg = " + format_value(stop_deg) +
                                                 " must be >= start_deg = " + format_value(start_deg));
  RigidWorkspace ws(mech, model);
  ws.kin.set_controls(controls);
  const auto points = static_cast<std::size_t>(std::floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1;
  out = RigidSweep{};
  out.controls = controls;
  out.cases = ws.cases();
  out.variables = static_cast<int>(mech.variables.size());
  out.connections = static_cast<int>(mech.connections.size());
  out.nodes = static_cast<int>(mech.nodes.size());
  out.springs = static_cast<int>(model.springs.size());
  out.cam_deg.resize(points);
  out.force.resize(points * out.connections * out.cases);
  out.torque.resize(points * out.cases);
  out.reaction.resize(points * out.nodes * 2 * out.cases);
  out.contact.resize(points * out.connections);
  out.spring_load.resize(points * out.springs);
  out.gas_force.resize(points);
  out.output.resize(points);
  out.loads.resize(points * out.variables * out.cases);
  const kin::Node& on = mech.nodes[mech.output_node];
  const bool out_angle = on.kind != NodeKind::translational;
  for (std::size_t i = 0; i < points; ++i) {
    const double deg = start_deg + step_deg * static_cast<double>(i);
    out.cam_deg[i] = deg;
    const Status st = solve_rigid(mech, model, ws, deg * rad_per_deg);
    if (!st.ok()) return st;
    for (int c = 0; c < out.connections; ++c)
      for (int j = 0; j < out.cases; ++j) out.force[(i * out.connections + c) * out.cases + j] = ws.force(c, j);
    for (int j = 0; j < out.cases; ++j) out.torque[i * out.cases + j] = ws.torque(j);
    for (int r = 0; r < 2 * out.nodes; ++r)
      for (int j = 0; j < out.cases; ++j) out.reaction[(i * out.nodes * 2 + r) * out.cases + j] = ws.reaction(r, j);
    std::copy(ws.kin.contacts.begin(), ws.kin.contacts.end(), out.contact.begin() + static_cast<long>(i * out.connections));
    for (int s = 0; s < out.springs; ++s) out.spring_load[i * out.springs + s] = ws.spring_load(s);
    out.gas_force[i] = ws.gas_force;
    for (int v = 0; v < out.variables; ++v)
      for (int j = 0; j < out.cases; ++j) out.loads[(i * out.variables + v) * out.cases + j] = ws.loads(v, j);
    const double q = ws.kin.vars[on.first_variable].value() - on.rest;
    out.output[i] = out_angle ? q / rad_per_deg : q;
  }
  return Status::success();
}

Separation separation_speed(const RigidSweep& sweep, const Model& model, int connection) {
  Separation sep;
  CAMOPT_THROW_UNLESS(connection >= 0 && connection < static_cast<int>(model.contacts.size()) &&
                          model.contacts[connection].is_contact,
                      "separation_speed: connection = " + std::to_string(connection) + " must be a contact");
  if (model.contacts[connection].two_sided) return sep;  // guided both ways: it never separates
  // split of the force at point i: at rest A (springs, gas), per rad/s C (dampers), per
  // (rad/s)^2 B (inertia): F = A + C w + B w^2
  auto split = [&](std::size_t i, double& at_rest, double& viscous, double& inertial) {
    const double* f = &sweep.force[(i * sweep.connections + connection) * sweep.cases];
    inertial = f[0];
    viscous = f[sweep.cases - 1];
    at_rest = 0.0;
    for (int j = 1; j + 1 < sweep.cases; ++j) at_rest += f[j];
  };
  // round-off scale: a point where every part is below it carries no load at any speed
  double scale_rest = 0.0, scale_viscous = 0.0, scale_inertial = 0.0;
  for (std::size_t i = 0; i < sweep.points(); ++i) {
    double a = 0, c = 0, b = 0;
    split(i, a, c, b);
    scale_rest = std::max(scale_rest, std::abs(a));
    scale_viscous = std::max(scale_viscous, std::abs(c));
    scale_inertial = std::max(scale_inertial, std::abs(b));
  }
  const double tol_rest = 1e-9 * scale_rest, tol_viscous = 1e-9 * scale_viscous, tol_inertial = 1e-9 * scale_inertial;
  for (std::size_t i = 0; i < sweep.points(); ++i) {
    if (sweep.contact[i * sweep.connections + connection].open) continue;
    double a = 0, c = 0, b = 0;
    split(i, a, c, b);
    if (std::abs(c) <= tol_viscous) c = 0.0;
    if (std::abs(b) <= tol_inertial) b = 0.0;
    double w = std::numeric_limits<double>::infinity();  // the smallest speed with F = 0 [rad/s]
    if (std::abs(a) <= tol_rest) {
      if (c < 0.0 || (c == 0.0 && b < 0.0)) w = 0.0;  // unloaded at rest, pulled apart at any speed
    } else if (a < 0.0) {
      w = 0.0;
    } else if (b == 0.0) {
      if (c < 0.0) w = -a / c;
    } else {
      // B w^2 + C w + A = 0 with A > 0: the smallest positive root (q: no cancellation)
      const double disc = c * c - 4.0 * a * b;
      if (disc >= 0.0) {
        const double q = -0.5 * (c + std::copysign(std::sqrt(disc), c));
        for (double root : {q / b, q != 0.0 ? a / q : std::numeric_limits<double>::infinity()})
          if (root > 0.0) w = std::min(w, root);
      }
    }
    const double rpm = std::isfinite(w) ? engine_rpm(w, model.crank_per_cam) : w;
    if (rpm < sep.engine_rpm) sep = {rpm, sweep.cam_deg[i]};
  }
  return sep;
}

double spring_margin(const RigidSweep& sweep, const Model& model, std::size_t point, int spring, double omega) {
  const double load = sweep.spring_load[point * sweep.springs + spring];
  double ratio = 1.0;
  bool any = false;
  for (int c = 0; c < sweep.connections; ++c) {
    if (!model.contacts[c].is_contact || sweep.contact[point * sweep.connections + c].open) continue;
    const double part = sweep.force[(point * sweep.connections + c) * sweep.cases + 2 + spring];
    if (!(part > 1e-12 * std::abs(load))) continue;
    const double r = sweep.force_at(point, c, omega) / part;
    ratio = any ? std::min(ratio, r) : r;
    any = true;
  }
  return load * ratio;
}

}  // namespace camopt::dynamics
