// mode (a): inverse dynamics along the kinematic solution at one driver angle (rigid.hpp):
// the loads of every case, the connection gradients, the force balance, the drive torque and
// the pivot reactions; the sweep and its separation speeds are in rigid_sweep.cpp
#include "camopt/dynamics/rigid.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"

namespace camopt::dynamics {

namespace {
// kg * mm/s^2 -> N; kg mm^2 / s^2 -> N mm
constexpr double kMilli = 1e-3;
// a balance whose reciprocal condition estimate falls below this is a toggle position
constexpr double kSingularRcond = 1e-13;
// a sliding speed below this times the mechanism size [mm per rad] is round-off
constexpr double kStillSliding = 1e-9;
// the most free variables a balance has (RigidWorkspace checks)
constexpr int kMaxBalanceRows = 64;

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

double cam_speed_rad_per_s(double engine_rpm_value, double crank_per_cam) {
  return engine_rpm_value * 2.0 * pi / 60.0 / crank_per_cam;
}
double engine_rpm(double cam_rad_per_s, double crank_per_cam) {
  return cam_rad_per_s * crank_per_cam * 60.0 / (2.0 * pi);
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
  CAMOPT_THROW_UNLESS(rows <= kMaxBalanceRows, "rigid model: " + std::to_string(rows) + " free variables, at most " +
                                                   std::to_string(kMaxBalanceRows));
  lu = Eigen::PartialPivLU<Eigen::MatrixXd>(rows);
  inverse.setZero(rows, rows);
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
      const Eigen::Vector2d r = p - kws.pivots()[node];
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


// inertia (case 0, per (rad/s)^2): m a_cg . dcg/dq + I alpha dphi/dq, a = d2/dtheta2, and
// the generalized mass of the free variables, one block per node
void add_inertia(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws) {
  using kin::node_pose;
  const auto& vars = ws.kin.vars;
  const int nn = static_cast<int>(mech.nodes.size());
  for (int n = 1; n < nn; ++n) {
    const kin::Node& node = mech.nodes[n];
    const BodyInertia& b = model.bodies[n];
    const auto pose = node_pose(mech, n, vars.data(), ws.kin.pivots().data());
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
}

// a spring pushing a point of a floating body along its line: travel x = d . (p - p_drawing),
// generalized load x'(q) load, stiffness k x' x'^T (the load's geometric term, like the
// contacts' in the flexible model, is left out: first order about the path)
void add_point_spring(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, std::size_t s) {
  using kin::node_pose;
  const auto& vars = ws.kin.vars;
  const Spring& sp = model.springs[s];
  const int v = mech.nodes[sp.node].first_variable;
  const auto pj = node_pose(mech, sp.node, vars.data(), ws.kin.pivots().data()).apply(sp.point.x(), sp.point.y());
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

// applied loads enter with a minus sign: gas (case 1), springs (case 2 + s) and their
// dampers oppose the positive displacement of their node; crank angle [crank deg]
void add_applied_loads(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double crank_deg) {
  const auto& vars = ws.kin.vars;
  ws.gas_force = 0.0;
  for (const GasForce& gf : model.gas_forces) {
    const double f = gf.at(crank_deg);
    ws.gas_force += f;
    ws.loads(mech.nodes[gf.node].first_variable, 1) += f;
  }
  ws.spring_stiffness.setZero();
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    const Spring& sp = model.springs[s];
    if (sp.on_point) {
      add_point_spring(mech, model, ws, s);
      continue;
    }
    const int v = mech.nodes[sp.node].first_variable;
    const double load = sp.load(vars[v].value());
    ws.spring_load(static_cast<Eigen::Index>(s)) = load;
    ws.loads(v, 2 + static_cast<int>(s)) += load;
    // the damper opposes the travel rate c x' omega: per rad/s c x'
    ws.loads(v, ws.damping_case()) += sp.damping * vars[v].c[1];
    const int r = model.row_of_variable[v];
    if (r >= 0) ws.spring_stiffness(r, r) += sp.stiffness(vars[v].value());
  }
}

// connection gradients g_c and the force direction on body b: a link's length, a gear's
// phi_b - ratio phi_a, a contact's gap with Coulomb friction along the tangent
void add_connection_gradients(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws) {
  using kin::node_pose;
  const auto& vars = ws.kin.vars;
  const int nc = static_cast<int>(mech.connections.size());
  for (int c = 0; c < nc; ++c) {
    const kin::Connection& conn = mech.connections[c];
    ws.on_b[c].setZero();
    switch (conn.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider: {
        const auto pa_j = node_pose(mech, conn.node_a, vars.data(), ws.kin.pivots().data()).apply(conn.pin_a.x(), conn.pin_a.y());
        const auto pb_j = node_pose(mech, conn.node_b, vars.data(), ws.kin.pivots().data()).apply(conn.pin_b.x(), conn.pin_b.y());
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
        if (cs.open) break;  // column replaced in the balance
        const double mu = cd.rolling ? 0.0 : cd.friction;
        ws.g.col(c) = ws.g_normal.col(c) + (mu * ws.slide_sign[c]) * ws.g_tangent.col(c);
        ws.on_b[c] = n + (mu * ws.slide_sign[c]) * t;
        break;
      }
    }
  }
}

// A X = B for the few rows of a balance, X in place of B: the row permutation and the two
// triangular substitutions written out (Eigen's solve takes its blocked level-3 path, made
// for large matrices, which here cost more than the rest of the balance)
void lu_solve_in_place(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu, Eigen::MatrixXd& x) {
  const Eigen::MatrixXd& f = lu.matrixLU();
  const auto& perm = lu.permutationP().indices();
  const Eigen::Index n = f.rows();
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    // P b: row i of b goes to row perm(i); the rows are few, a fixed buffer holds the column
    double y[kMaxBalanceRows];
    for (Eigen::Index i = 0; i < n; ++i) y[perm(i)] = x(i, j);
    for (Eigen::Index i = 0; i < n; ++i)  // L y = P b, unit diagonal
      for (Eigen::Index k = 0; k < i; ++k) y[i] -= f(i, k) * y[k];
    for (Eigen::Index i = n - 1; i >= 0; --i) {  // U x = y
      for (Eigen::Index k = i + 1; k < n; ++k) y[i] -= f(i, k) * y[k];
      y[i] /= f(i, i);
    }
    for (Eigen::Index i = 0; i < n; ++i) x(i, j) = y[i];
  }
}

// the balance over the free variables, system * force = rhs; an open lash gap carries no
// contact force, the held node's seat reaction takes its place. Singular: a toggle position.
Status solve_balance(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double driver_rad) {
  const int nc = static_cast<int>(mech.connections.size());
  const int rows = static_cast<int>(model.free_variables.size());
  for (int r = 0; r < rows; ++r) {
    const int v = model.free_variables[r];
    ws.system.row(r) = ws.g.row(v);
    ws.rhs.row(r) = ws.loads.row(v);
  }
  for (int c = 0; c < nc; ++c)
    if (mech.connections[c].kind == ConnectionKind::contact && ws.kin.contacts[c].open) {
      ws.system.col(c).setZero();
      const int held = model.contacts[c].held_node;
      CAMOPT_ASSERT(held > 0);
      ws.system(model.row_of_variable[mech.nodes[held].first_variable], c) = 1.0;
    }
  ws.lu.compute(ws.system);
  // reciprocal 1-norm condition 1 / (|A|_1 |A^-1|_1), exact and into the workspace (the LU's
  // own estimate allocates its vectors at every point)
  ws.inverse.setIdentity();
  lu_solve_in_place(ws.lu, ws.inverse);
  double rcond = 1.0 / (ws.system.cwiseAbs().colwise().sum().maxCoeff() *
                        ws.inverse.cwiseAbs().colwise().sum().maxCoeff());
  if (!(rcond >= 0.0)) rcond = 0.0;  // a zero pivot: inf / NaN in the inverse
  if (!(rcond > kSingularRcond))
    return {StatusCode::singular,
            "the force balance is singular (reciprocal condition " + fmt(rcond) + "): a toggle position",
            "driver " + fmt(driver_rad / rad_per_deg) + " deg"};
  ws.force = ws.rhs;
  lu_solve_in_place(ws.lu, ws.force);
  ws.seat.setZero();
  for (int c = 0; c < nc; ++c)
    if (mech.connections[c].kind == ConnectionKind::contact && ws.kin.contacts[c].open) {
      ws.seat.row(c) = ws.force.row(c);
      ws.force.row(c).setZero();
    }
  return Status::success();
}

// pivot / guide reactions: R = m a_cg - sum connection forces - applied forces
void compute_reactions(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double crank_deg) {
  const int nn = static_cast<int>(mech.nodes.size());
  const int nc = static_cast<int>(mech.connections.size());
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
}

}  // namespace

Status solve_rigid(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double driver_rad) {
  // kinematics to order 2 with the contacts
  Status st = kin::solve(mech, ws.kin, driver_rad, kin::Request{2, true});
  if (!st.ok()) return st;
  ws.g.setZero();
  ws.loads.setZero();
  // the load cases: inertia, gas, springs and dampers
  add_inertia(mech, model, ws);
  const double crank_deg = driver_rad / rad_per_deg * model.crank_per_cam;
  add_applied_loads(mech, model, ws, crank_deg);
  // the connections' gradients and force directions
  add_connection_gradients(mech, model, ws);
  // the connection forces from the balance of the free variables
  st = solve_balance(mech, model, ws, driver_rad);
  if (!st.ok()) return st;
  // drive torque: inertia minus applied minus connection loads on the driver variable
  const int dv = mech.driver_variable();
  ws.torque = ws.loads.row(dv);
  ws.torque.noalias() -= ws.g.row(dv) * ws.force;
  // pivot and guide reactions
  compute_reactions(mech, model, ws, crank_deg);
  return Status::success();
}

}  // namespace camopt::dynamics
