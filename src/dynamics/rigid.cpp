// mode (a): inverse dynamics along the kinematic solution (see rigid.hpp)
#include "camopt/dynamics/rigid.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "camopt/kinematics/detail/geometry.hpp"

namespace camopt::dynamics {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// kg * mm/s^2 -> N; kg mm^2 / s^2 -> N mm
constexpr double kMilli = 1e-3;
// a balance whose reciprocal condition estimate falls below this is a toggle position
constexpr double kSingularRcond = 1e-13;
// a sliding speed below this times the mechanism size [mm per rad] is round-off
constexpr double kStillSliding = 1e-9;

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

double cam_speed_rad_per_s(double engine_rpm_value, double crank_per_cam) {
  return engine_rpm_value * 2.0 * kPi / 60.0 / crank_per_cam;
}
double engine_rpm(double cam_rad_per_s, double crank_per_cam) {
  return cam_rad_per_s * crank_per_cam * 60.0 / (2.0 * kPi);
}

RigidWorkspace::RigidWorkspace(const kin::Mechanism& mech, const Model& model) : kin(mech) {
  cases_ = 3 + static_cast<int>(model.springs.size());  // inertia, gas, springs, dampers
  const auto nc = static_cast<Eigen::Index>(mech.connections.size());
  const auto nv = static_cast<Eigen::Index>(mech.variables.size());
  const auto nn = static_cast<Eigen::Index>(mech.nodes.size());
  const auto rows = static_cast<Eigen::Index>(model.free_variables.size());
  force.setZero(nc, cases_);
  torque.setZero(cases_);
  reaction.setZero(2 * nn, cases_);
  spring_load.setZero(static_cast<Eigen::Index>(model.springs.size()));
  g.setZero(nv, nc);
  g_normal.setZero(nv, nc);
  g_tangent.setZero(nv, nc);
  seat.setZero(nc, cases_);
  mass.setZero(rows, rows);
  spring_stiffness.setZero(rows, rows);
  slide_sign.assign(nc, 0.0);
  loads.setZero(nv, cases_);
  system.setZero(rows, nc);
  rhs.setZero(rows, cases_);
  lu = Eigen::PartialPivLU<Eigen::MatrixXd>(rows);
  cg_acc.assign(nn, Eigen::Vector2d::Zero());
  cg_pos.assign(nn, Eigen::Vector2d::Zero());
  phi_acc.assign(nn, 0.0);
  on_b.assign(nc, Eigen::Vector2d::Zero());
}

int point_partials(const kin::Mechanism& mech, const kin::Workspace& kws, int node, const Eigen::Vector2d& p,
                   Eigen::Vector2d* out) {
  const kin::Node& n = mech.nodes[node];
  if (n.ground || n.first_variable < 0) return 0;
  switch (n.kind) {
    case NodeKind::rotational: {
      const Eigen::Vector2d r = p - kws.pivots[node];
      out[0] = {-r.y(), r.x()};
      return 1;
    }
    case NodeKind::translational:
      out[0] = n.direction;
      return 1;
    case NodeKind::floating: {
      const Eigen::Vector2d t(kws.vars[n.first_variable].value() + n.reference.x(),
                              kws.vars[n.first_variable + 1].value() + n.reference.y());
      const Eigen::Vector2d r = p - t;
      out[0] = {1.0, 0.0};
      out[1] = {0.0, 1.0};
      out[2] = {-r.y(), r.x()};
      return 3;
    }
  }
  return 0;
}

namespace {

// the angle variable of a node (-1: none)
int angle_variable(const kin::Node& n) {
  if (n.ground || n.first_variable < 0) return -1;
  if (n.kind == NodeKind::rotational) return n.first_variable;
  if (n.kind == NodeKind::floating) return n.first_variable + 2;
  return -1;
}

// add d . (dp/dq) * sign to column c of g for every variable of node
void add_gradient(const kin::Mechanism& mech, RigidWorkspace& ws, Eigen::MatrixXd& g, int node,
                  const Eigen::Vector2d& p, const Eigen::Vector2d& d, double sign, int c) {
  Eigen::Vector2d dp[3];
  const int k = point_partials(mech, ws.kin, node, p, dp);
  for (int i = 0; i < k; ++i) g(mech.nodes[node].first_variable + i, c) += sign * d.dot(dp[i]);
}

}  // namespace

Status solve_rigid(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double driver_rad) {
  Status st = kin::solve(mech, ws.kin, driver_rad, kin::Request{2, true});
  if (!st.ok()) return st;
  using kin::detail::node_pose;
  const auto& vars = ws.kin.vars;
  const int nn = static_cast<int>(mech.nodes.size());
  const int nc = static_cast<int>(mech.connections.size());
  ws.g.setZero();
  ws.loads.setZero();

  // inertia (case 0, per (rad/s)^2): m a_cg . dcg/dq + I alpha dphi/dq, a = d2/dtheta2
  for (int n = 1; n < nn; ++n) {
    const kin::Node& node = mech.nodes[n];
    const BodyInertia& b = model.bodies[n];
    const auto pose = node_pose(mech, n, vars.data(), ws.kin.pivots.data());
    const auto cg = pose.apply(b.cg.x(), b.cg.y());
    ws.cg_pos[n] = {cg.x.c[0], cg.y.c[0]};
    ws.cg_acc[n] = {2.0 * cg.x.c[2], 2.0 * cg.y.c[2]};
    const int av = angle_variable(node);
    ws.phi_acc[n] = av >= 0 ? 2.0 * vars[av].c[2] : 0.0;
    if (node.first_variable < 0) continue;
    Eigen::Vector2d dp[3];
    const int k = point_partials(mech, ws.kin, n, ws.cg_pos[n], dp);
    for (int i = 0; i < k; ++i) ws.loads(node.first_variable + i, 0) += kMilli * b.mass * ws.cg_acc[n].dot(dp[i]);
    if (av >= 0) ws.loads(av, 0) += kMilli * b.inertia * ws.phi_acc[n];
    // generalized mass of the free variables: one block per node
    for (int i = 0; i < k; ++i) {
      const int ri = model.row_of_variable[node.first_variable + i];
      if (ri < 0) continue;
      for (int j = 0; j < k; ++j) {
        const int rj = model.row_of_variable[node.first_variable + j];
        double mij = kMilli * b.mass * dp[i].dot(dp[j]);
        if (node.first_variable + i == av && node.first_variable + j == av) mij += kMilli * b.inertia;
        ws.mass(ri, rj) = mij;
      }
    }
  }
  // applied loads enter with a minus sign: gas (case 1) and springs (case 2 + s) oppose
  // the positive displacement of their node
  const double crank_deg = driver_rad / kDeg * model.crank_per_cam;
  ws.gas_force = 0.0;
  for (const GasForce& gf : model.gas_forces) {
    const double f = gf.at(crank_deg);
    ws.gas_force += f;
    ws.loads(mech.nodes[gf.node].first_variable, 1) += f;
  }
  ws.spring_stiffness.setZero();
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    const Spring& sp = model.springs[s];
    const int v = mech.nodes[sp.node].first_variable;
    if (!sp.on_point) {
      const double load = sp.load(vars[v].value());
      ws.spring_load(static_cast<Eigen::Index>(s)) = load;
      ws.loads(v, 2 + static_cast<int>(s)) += load;
      // the damper opposes the travel rate c x' omega: per rad/s c x'
      ws.loads(v, ws.damping_case()) += sp.damping * vars[v].c[1];
      const int r = model.row_of_variable[v];
      if (r >= 0) ws.spring_stiffness(r, r) += sp.stiffness(vars[v].value());
      continue;
    }
    // a spring pushing a point of a floating body along its line: travel x = d . (p - p_drawing),
    // generalized load x'(q) load, stiffness k x' x'^T (the load's geometric term, like the
    // contacts' in the flexible model, is left out: first order about the path)
    const auto pj = node_pose(mech, sp.node, vars.data(), ws.kin.pivots.data()).apply(sp.point.x(), sp.point.y());
    const Eigen::Vector2d p(pj.x.value(), pj.y.value());
    const double x = sp.direction.dot(p - sp.point), load = sp.load(x), k = sp.stiffness(x);
    ws.spring_load(static_cast<Eigen::Index>(s)) = load;
    Eigen::Vector2d dp[3];
    const int n = point_partials(mech, ws.kin, sp.node, p, dp);
    double g[3], rate = 0.0;  // the point's travel per rad
    for (int i = 0; i < n; ++i) {
      g[i] = sp.direction.dot(dp[i]);
      ws.loads(v + i, 2 + static_cast<int>(s)) += load * g[i];
      rate += g[i] * vars[v + i].c[1];
    }
    for (int i = 0; i < n; ++i) ws.loads(v + i, ws.damping_case()) += sp.damping * rate * g[i];
    for (int i = 0; i < n; ++i) {
      const int ri = model.row_of_variable[v + i];
      if (ri < 0) continue;
      for (int j = 0; j < n; ++j) {
        const int rj = model.row_of_variable[v + j];
        if (rj >= 0) ws.spring_stiffness(ri, rj) += k * g[i] * g[j];
      }
    }
  }

  // connection gradients g_c and the force direction on body b
  for (int c = 0; c < nc; ++c) {
    const kin::Connection& conn = mech.connections[c];
    ws.on_b[c].setZero();
    switch (conn.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider: {
        const auto pa_j = node_pose(mech, conn.node_a, vars.data(), ws.kin.pivots.data()).apply(conn.pin_a.x(), conn.pin_a.y());
        const auto pb_j = node_pose(mech, conn.node_b, vars.data(), ws.kin.pivots.data()).apply(conn.pin_b.x(), conn.pin_b.y());
        const Eigen::Vector2d pa(pa_j.x.value(), pa_j.y.value()), pb(pb_j.x.value(), pb_j.y.value());
        const Eigen::Vector2d u = (pb - pa).normalized();
        add_gradient(mech, ws, ws.g, conn.node_b, pb, u, 1.0, c);
        add_gradient(mech, ws, ws.g, conn.node_a, pa, u, -1.0, c);
        ws.on_b[c] = u;
        break;
      }
      case ConnectionKind::gear:
      case ConnectionKind::variable_gear:
      case ConnectionKind::rack_pinion: {
        const int va = mech.nodes[conn.node_a].first_variable, vb = mech.nodes[conn.node_b].first_variable;
        double ratio = conn.ratio;
        if (conn.kind == ConnectionKind::variable_gear) ratio = conn.ratio_table(vars[va].value());
        if (conn.kind == ConnectionKind::rack_pinion) ratio = conn.pitch_radius;
        if (vb >= 0) ws.g(vb, c) += 1.0;
        if (va >= 0) ws.g(va, c) -= ratio;
        break;
      }
      case ConnectionKind::contact: {
        const kin::ContactState& cs = ws.kin.contacts[c];
        const ContactData& cd = model.contacts[c];
        const Eigen::Vector2d n(cs.normal_x, cs.normal_y), t(-cs.normal_y, cs.normal_x);
        const Eigen::Vector2d p(cs.x, cs.y);
        ws.g_normal.col(c).setZero();
        ws.g_tangent.col(c).setZero();
        add_gradient(mech, ws, ws.g_normal, conn.node_b, p, n, 1.0, c);
        add_gradient(mech, ws, ws.g_normal, conn.node_a, p, n, -1.0, c);
        add_gradient(mech, ws, ws.g_tangent, conn.node_b, p, t, 1.0, c);
        add_gradient(mech, ws, ws.g_tangent, conn.node_a, p, t, -1.0, c);
        // Coulomb friction on b opposes b's sliding relative to a: (v_b - v_a).t = -sliding
        // below round-off (a stationary follower on the base circle) the contact sticks: no
        // friction direction
        const double still = kStillSliding * mech.length_scale;
        ws.slide_sign[c] = cs.sliding > still ? 1.0 : cs.sliding < -still ? -1.0 : 0.0;
        if (cs.open) break;  // column replaced below
        const double mu = cd.rolling ? 0.0 : cd.friction;
        ws.g.col(c) = ws.g_normal.col(c) + (mu * ws.slide_sign[c]) * ws.g_tangent.col(c);
        ws.on_b[c] = n + (mu * ws.slide_sign[c]) * t;
        break;
      }
    }
  }

  // the balance over the free variables: system * force = rhs
  const int rows = static_cast<int>(model.free_variables.size());
  for (int r = 0; r < rows; ++r) {
    const int v = model.free_variables[r];
    ws.system.row(r) = ws.g.row(v);
    ws.rhs.row(r) = ws.loads.row(v);
  }
  for (int c = 0; c < nc; ++c)
    if (mech.connections[c].kind == ConnectionKind::contact && ws.kin.contacts[c].open) {
      // open lash gap: no contact force; the held node's seat reaction takes its place
      ws.system.col(c).setZero();
      const int held = model.contacts[c].held_node;
      CAMOPT_ASSERT(held > 0);
      ws.system(model.row_of_variable[mech.nodes[held].first_variable], c) = 1.0;
    }
  ws.lu.compute(ws.system);
  const double rcond = ws.lu.rcond();
  if (!(rcond > kSingularRcond))
    return {StatusCode::singular,
            "the force balance is singular (reciprocal condition " + fmt(rcond) + "): a toggle position",
            "driver " + fmt(driver_rad / kDeg) + " deg"};
  ws.force.noalias() = ws.lu.solve(ws.rhs);
  ws.seat.setZero();
  for (int c = 0; c < nc; ++c)
    if (mech.connections[c].kind == ConnectionKind::contact && ws.kin.contacts[c].open) {
      ws.seat.row(c) = ws.force.row(c);
      ws.force.row(c).setZero();
    }

  // drive torque: inertia minus applied minus connection loads on the driver variable
  const int dv = mech.driver_variable();
  ws.torque = ws.loads.row(dv);
  ws.torque.noalias() -= ws.g.row(dv) * ws.force;

  // pivot / guide reactions: R = m a_cg - sum connection forces - applied forces
  ws.reaction.setZero();
  for (int n = 1; n < nn; ++n) {
    ws.reaction(2 * n, 0) = kMilli * model.bodies[n].mass * ws.cg_acc[n].x();
    ws.reaction(2 * n + 1, 0) = kMilli * model.bodies[n].mass * ws.cg_acc[n].y();
  }
  for (int c = 0; c < nc; ++c) {
    const kin::Connection& conn = mech.connections[c];
    for (int j = 0; j < ws.cases(); ++j) {
      const Eigen::Vector2d fb = ws.on_b[c] * ws.force(c, j);
      ws.reaction(2 * conn.node_b, j) -= fb.x();
      ws.reaction(2 * conn.node_b + 1, j) -= fb.y();
      ws.reaction(2 * conn.node_a, j) += fb.x();
      ws.reaction(2 * conn.node_a + 1, j) += fb.y();
    }
  }
  for (const GasForce& gf : model.gas_forces) {
    const Eigen::Vector2d f = -gf.at(crank_deg) * mech.nodes[gf.node].direction;
    ws.reaction(2 * gf.node, 1) -= f.x();
    ws.reaction(2 * gf.node + 1, 1) -= f.y();
  }
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    const Spring& sp = model.springs[s];
    if (sp.kind != SpringKind::compression || sp.on_point) continue;
    const Eigen::Vector2d f = -ws.spring_load(static_cast<Eigen::Index>(s)) * mech.nodes[sp.node].direction;
    ws.reaction(2 * sp.node, 2 + static_cast<int>(s)) -= f.x();
    ws.reaction(2 * sp.node + 1, 2 + static_cast<int>(s)) -= f.y();
    const int v = mech.nodes[sp.node].first_variable;
    const Eigen::Vector2d fd = -sp.damping * ws.kin.vars[v].c[1] * mech.nodes[sp.node].direction;
    ws.reaction(2 * sp.node, ws.damping_case()) -= fd.x();
    ws.reaction(2 * sp.node + 1, ws.damping_case()) -= fd.y();
  }
  ws.reaction.topRows(2).setZero();  // ground
  return Status::success();
}

Status rigid_sweep(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                   double start_deg, double stop_deg, double step_deg, RigidSweep& out) {
  CAMOPT_ASSERT(step_deg > 0 && stop_deg >= start_deg);
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
    const Status st = solve_rigid(mech, model, ws, deg * kDeg);
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
    out.output[i] = out_angle ? q / kDeg : q;
  }
  return Status::success();
}

Separation separation_speed(const RigidSweep& sweep, const Model& model, int connection) {
  Separation sep;
  CAMOPT_ASSERT(model.contacts[connection].is_contact);
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
