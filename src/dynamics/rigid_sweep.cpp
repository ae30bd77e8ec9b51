// mode (a) over a sweep: every quantity split by load case at each driver angle, and what
// follows from the split: the separation speed of a contact and the spring margin (rigid.hpp)
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

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

namespace {

// the parts of a contact force: at rest A (springs, gas), per rad/s C (dampers), per (rad/s)^2
// B (inertia): F = A + C w + B w^2
struct ForceSplit {
  double at_rest = 0.0, viscous = 0.0, inertial = 0.0;
};
ForceSplit split_of(const double* f, int cases) {
  ForceSplit s{0.0, f[cases - 1], f[0]};
  for (int j = 1; j + 1 < cases; ++j) s.at_rest += f[j];
  return s;
}
ForceSplit split_at(const RigidSweep& sweep, std::size_t point, int connection) {
  return split_of(&sweep.force[(point * sweep.connections + connection) * sweep.cases], sweep.cases);
}

// round-off scale: a part below 1e-9 of its largest over the sweep carries no load at any speed
ForceSplit split_tolerances(const RigidSweep& sweep, int connection) {
  ForceSplit scale;
  for (std::size_t i = 0; i < sweep.points(); ++i) {
    const ForceSplit f = split_at(sweep, i, connection);
    scale.at_rest = std::max(scale.at_rest, std::abs(f.at_rest));
    scale.viscous = std::max(scale.viscous, std::abs(f.viscous));
    scale.inertial = std::max(scale.inertial, std::abs(f.inertial));
  }
  return {1e-9 * scale.at_rest, 1e-9 * scale.viscous, 1e-9 * scale.inertial};
}

// the smallest cam speed [rad/s] at which F = A + C w + B w^2 reaches zero at one point: 0
// when it is already <= 0 at rest (or unloaded at rest and pulled apart), +inf when never
double zero_force_speed(ForceSplit f, const ForceSplit& tol) {
  const double a = f.at_rest;
  const double c = std::abs(f.viscous) <= tol.viscous ? 0.0 : f.viscous;
  const double b = std::abs(f.inertial) <= tol.inertial ? 0.0 : f.inertial;
  double w = std::numeric_limits<double>::infinity();
  if (std::abs(a) <= tol.at_rest) {
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
  return w;
}

// Brent's minimisation of f on [a, b] to the abscissa tolerance `tol` (golden sections with
// parabolic steps; Brent, Algorithms for Minimization without Derivatives, 1973, ch. 5,
// procedure localmin): the abscissa of the least value found and the value there
template <class F>
std::pair<double, double> brent_minimum(F&& f, double a, double b, double tol) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0)), eps = std::sqrt(std::numeric_limits<double>::epsilon());
  double x = a + golden * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx, d = 0.0, e = 0.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double m = 0.5 * (a + b), tol1 = eps * std::abs(x) + tol, tol2 = 2.0 * tol1;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) break;
    double p = 0.0, q = 0.0, r = 0.0;
    if (std::abs(e) > tol1) {  // a parabola through x, w, v
      r = (x - w) * (fx - fv);
      q = (x - v) * (fx - fw);
      p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      else q = -q;
      r = e;
      e = d;
    }
    if (std::abs(p) < std::abs(0.5 * q * r) && p > q * (a - x) && p < q * (b - x)) {
      d = p / q;
      if ((x + d) - a < tol2 || b - (x + d) < tol2) d = x < m ? tol1 : -tol1;
    } else {  // a golden section
      e = (x < m ? b : a) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol1 ? d : (d > 0.0 ? tol1 : -tol1));
    const double fu = f(u);
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) v = w, fv = fw, w = u, fw = fu;
      else if (fu <= fv || v == x || v == w) v = u, fv = fu;
    }
  }
  return {x, fx};
}

}  // namespace

Separation separation_speed(const RigidSweep& sweep, const Model& model, int connection) {
  Separation sep;
  CAMOPT_THROW_UNLESS(connection >= 0 && connection < static_cast<int>(model.contacts.size()) &&
                          model.contacts[connection].is_contact,
                      "separation_speed: connection = " + std::to_string(connection) + " must be a contact");
  if (model.contacts[connection].two_sided) return sep;  // guided both ways: it never separates
  const ForceSplit tol = split_tolerances(sweep, connection);
  for (std::size_t i = 0; i < sweep.points(); ++i) {
    if (sweep.contact[i * sweep.connections + connection].open) continue;
    const double w = zero_force_speed(split_at(sweep, i, connection), tol);
    const double rpm = std::isfinite(w) ? engine_rpm(w, model.crank_per_cam) : w;
    if (rpm < sep.engine_rpm) sep = {rpm, sweep.cam_deg[i]};
  }
  return sep;
}

Status refined_separation_speed(const kin::Mechanism& mech, const Model& model, const RigidSweep& sweep,
                                int connection, Separation& out) {
  // the grid's least and its point; nothing to refine at 0 or +inf
  out = separation_speed(sweep, model, connection);
  if (!(out.engine_rpm > 0.0) || !std::isfinite(out.engine_rpm) || sweep.points() < 2) return Status::success();
  const auto at = std::find(sweep.cam_deg.begin(), sweep.cam_deg.end(), out.cam_deg);
  const auto i = static_cast<std::size_t>(at - sweep.cam_deg.begin());
  const std::size_t lo = i > 0 ? i - 1 : i, hi = std::min(i + 1, sweep.points() - 1);
  // beside an open lash gap the force jumps: the grid's
  for (std::size_t k = lo; k <= hi; ++k)
    if (sweep.contact[k * sweep.connections + connection].open) return Status::success();
  // w(theta) [rad/s] by a mode (a) solve at each trial angle, continued from the bracket's start
  RigidWorkspace ws(mech, model);
  ws.kin.set_controls(sweep.controls);
  Status failed = solve_rigid(mech, model, ws, sweep.cam_deg[lo] * rad_per_deg);
  if (!failed.ok()) return failed;
  const ForceSplit tol = split_tolerances(sweep, connection);
  const double start = sweep.cam_deg[lo];
  auto speed_at = [&](double offset_deg) {
    const double inf = std::numeric_limits<double>::infinity();
    if (!failed.ok()) return inf;
    failed = solve_rigid(mech, model, ws, (start + offset_deg) * rad_per_deg);
    if (!failed.ok() || ws.kin.contacts[connection].open) return inf;
    const ForceSplit f{ws.force.row(connection).segment(1, ws.cases() - 2).sum(), ws.force(connection, ws.cases() - 1),
                       ws.force(connection, 0)};
    return zero_force_speed(f, tol);
  };
  // the least on both intervals beside the point [deg from the bracket's start]
  const auto [offset, w] = brent_minimum(speed_at, 0.0, sweep.cam_deg[hi] - start, 1e-10);
  if (!failed.ok()) return failed;
  const double rpm = engine_rpm(w, model.crank_per_cam);
  if (rpm < out.engine_rpm) out = {rpm, start + offset};
  return Status::success();
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
