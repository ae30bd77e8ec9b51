// the one-equation form of a curve-circle contact (WorkspaceState::Block::OffsetContact): a
// profile curve on a known body against a circle on the block's one unknown body, which
// rotates or translates. The circle centre lies on the curve's offset; the block's two
// unknowns (the body's displacement and the curve parameter u) reduce to one equation g(u)
// = 0 [mm]: the centre at its arm's distance from the pivot (rotational) or on the line of
// travel (translational).
#include <cmath>

#include "camopt/core/trig_cache.hpp"
#include "kernel.hpp"

namespace camopt::kin::detail {

namespace {

using OffsetContact = WorkspaceState::Block::OffsetContact;

// the one equation [mm]: the centre at its distance from the unknown body's pivot
// (rotational) or on the unknown body's line of travel (translational)
double offset_residual(const OffsetContact& oc, const Node& node, const Eigen::Vector2d& pivot,
                       const V2<double>& centre) {
  if (node.kind == NodeKind::rotational) {
    const double dx = centre.x - pivot.x(), dy = centre.y - pivot.y();  // [mm]: no overflow
    return std::sqrt(dx * dx + dy * dy) - oc.arm;
  }
  return node.direction.x() * (centre.y - oc.centre.y()) - node.direction.y() * (centre.x - oc.centre.x());
}

// d g / d centre: a unit vector along the rotational arm, the travel's normal otherwise
V2<double> offset_gradient(const Node& node, const Eigen::Vector2d& pivot, const V2<double>& centre) {
  if (node.kind != NodeKind::rotational) return V2<double>{-node.direction.y(), node.direction.x()};
  const double dx = centre.x - pivot.x(), dy = centre.y - pivot.y(), dist = std::sqrt(dx * dx + dy * dy);
  return V2<double>{dx / dist, dy / dist};
}

// the root of g(u) = 0 and the centre there
template <int M>
struct OffsetRoot {
  double u = 0.0;             // the curve parameter [rad or 2 pi chord fraction]
  double evaluated_at = 0.0;  // where the curve was last evaluated (the series was shifted from there to u)
  V2<Jet<M>> q;               // the centre in the curve body's frame, series in u [mm]
  V2<double> centre, centre_u;  // the centre and dC/du, global [mm, mm per u]
};

// newton on g(u) from root.u (the prediction). One evaluation gives the centre as a taylor
// series of order M in u; while a newton step du is below `shift_limit` the series is
// shifted to the new u instead of evaluating the curve again (the truncation, ~ q^(M+1)
// du^(M+1-k) in the k-th coefficient, is below round-off). false: no root (non-finite, a
// flat g, or no convergence)
template <int M>
bool offset_newton(const Mechanism& m, const OffsetContact& oc, const Surface& curve, const Node& node,
                   const Eigen::Vector2d& pivot, const Pose<double>& pose0, double tol, SolveStats& stats,
                   OffsetRoot<M>& root) {
  // [rad or 2 pi chord fraction]: the first neglected term q_(M+1) du^(M+1) of the value
  // stays below round-off (order 1: ~1e-16 q_2)
  constexpr double shift_limit = M == 1 ? 1e-8 : 1e-7;
  constexpr int max_evaluations = 6, max_shifts = 3;
  double& u = root.u;
  V2<Jet<M>>& q = root.q;
  double g = 0.0, gu = 0.0;
  bool converged = false;
  root.evaluated_at = u;
  for (int ev = 0; ev < max_evaluations && !converged; ++ev) {
    root.evaluated_at = u;
    q = offset_local<M>(m, curve, oc.centre_offset, u);
    bool reevaluate = false;
    for (int shifts = 0; shifts <= max_shifts && !reevaluate; ++shifts) {
      root.centre = pose0.apply(q.x.c[0], q.y.c[0]);
      root.centre_u = pose0.rotate(q.x.c[1], q.y.c[1]);
      g = offset_residual(oc, node, pivot, root.centre);
      gu = dot(offset_gradient(node, pivot, root.centre), root.centre_u);
      if (!std::isfinite(g) || !std::isfinite(gu) || gu == 0.0) return false;
      if (std::abs(g) <= tol) {
        converged = true;
        break;
      }
      if (shifts == max_shifts) break;
      ++stats.newton_iterations;
      const double du = -g / gu;
      u += du;
      reevaluate = std::abs(du) > shift_limit;
      if (!reevaluate) {
        taylor_shift(q.x, du);
        taylor_shift(q.y, du);
      }
    }
  }
  return converged;
}

// the block's 2 x 2 jacobian of (tangency, closure) in (displacement, u): its condition
// into ws.max_condition, the toggle margin (the cosine of the pressure angle) and the
// determinant's sign into the block; singular when the condition reaches 1e13
Status offset_condition(const Mechanism& m, Workspace& ws, WorkspaceState::Block& b, const Connection& c, const Node& node,
                        const Eigen::Vector2d& pivot, const V2<double>& centre, const V2<double>& centre_u,
                        double driver) {
  const bool rotational = node.kind == NodeKind::rotational;
  // the curve's unit tangent: along dC/du (the offset curve is parallel to the curve; a
  // reversed sign leaves the condition number below unchanged)
  const double centre_u_norm = std::sqrt(centre_u.x * centre_u.x + centre_u.y * centre_u.y);
  const V2<double> tangent{centre_u.x / centre_u_norm, centre_u.y / centre_u_norm};
  // d/dq = (X_q . t, X_q . n), d/du = (-C_u . t, 0) with n = (t_y, -t_x)
  const V2<double> xq = rotational ? V2<double>{-(centre.y - pivot.y()), centre.x - pivot.x()}
                                   : V2<double>{node.direction.x(), node.direction.y()};
  const V2<double> n{tangent.y, -tangent.x};
  const double a = dot(xq, tangent), bb = -dot(centre_u, tangent);
  const double cc = dot(xq, n);
  const double det = -bb * cc;
  // |J|_1 |J^-1|_1, J^-1 = [[0, -b], [-c, a]] / det
  const double cond = std::max(std::abs(a) + std::abs(cc), std::abs(bb)) *
                      std::max(std::abs(cc), std::abs(bb) + std::abs(a)) / std::abs(det);
  ws.max_condition = std::max(ws.max_condition, cond);
  // the cosine of the pressure angle: the normal against the centre's direction of motion
  b.margin = std::abs(cc) / std::sqrt(dot(xq, xq));
  b.sign = det > 0 ? 2 : det < 0 ? -2 : 0;
  ws.toggle_margin = std::min(ws.toggle_margin, b.margin);
  if (!(cond < 1e13))
    return {StatusCode::singular,
            "connection(s) '" + c.name + "' are singular (condition number " + fmt(cond) +
                "): a pressure angle reached 90 deg or a linkage is at toggle",
            driver_text(m, driver)};
  return Status::success();
}

// taylor coefficients in the driver, order by order, each linear in its u_k: the centre
// C(t) = T(t) + R(t) (Q(u(t)) - r) (T, R the known body's pose, Q the centre in its frame,
// Faa di Bruno for Q(u(t)) up to order 3), g_k = 0 for u_k. Gives u (uj) and the centre
// (cx, cy) as series in the driver.
template <int M>
void offset_taylor(const OffsetRoot<M>& root, const Pose<Jet3>& pose3, const Pose<double>& pose0, const Node& node,
                   const Eigen::Vector2d& pivot, SolveStats& stats, Jet3& uj, Jet3& cx, Jet3& cy) {
  const bool rotational = node.kind == NodeKind::rotational;
  const V2<Jet<M>>& q = root.q;
  const V2<double>& centre = root.centre;
  const V2<double>& centre_u = root.centre_u;
  constexpr int order = continuation_order;
  uj = Jet3(root.u);
  cx = Jet3(centre.x);
  cy = Jet3(centre.y);
  // the body-frame lever L = Q - r, order by order
  V2<double> lever[4] = {{q.x.c[0] - pose3.rx, q.y.c[0] - pose3.ry}, {0, 0}, {0, 0}, {0, 0}};
  const V2<double> q1{q.x.c[1], q.y.c[1]};
  const V2<double> d0{centre.x - pivot.x(), centre.y - pivot.y()};  // rotational: centre - pivot
  const V2<double> travel_normal{-node.direction.y(), node.direction.x()};
  for (int k = 1; k <= order; ++k) {
    // Q_k without its u_k term
    const double u1 = uj.c[1], u2 = uj.c[2];
    V2<double> known{0.0, 0.0};
    if constexpr (M >= 2) {
      if (k == 2) known = {q.x.c[2] * u1 * u1, q.y.c[2] * u1 * u1};
    }
    if constexpr (M >= 3) {
      if (k == 3) {
        const double a2 = 2.0 * u1 * u2, a3 = u1 * u1 * u1;
        known = {q.x.c[2] * a2 + q.x.c[3] * a3, q.y.c[2] * a2 + q.y.c[3] * a3};
      }
    }
    // C_k without its u_k term: T_k + sum_{i=1..k} R_i L_{k-i} + R_0 known
    V2<double> ck{pose3.tx.c[k], pose3.ty.c[k]};
    for (int i = 1; i <= k; ++i) {
      const double ci = pose3.c.c[i], si = pose3.s.c[i];
      const V2<double>& l = lever[k - i];
      ck.x += ci * l.x - si * l.y;
      ck.y += si * l.x + ci * l.y;
    }
    ck.x += pose0.c * known.x - pose0.s * known.y;
    ck.y += pose0.s * known.x + pose0.c * known.y;
    // g_k = 0, linear in u_k through C_u u_k
    double uk;
    if (rotational) {
      // |C - P|^2 = arm^2: 2 D_0 . D_k + sum_{0<i<k} D_i . D_{k-i} = 0
      double rest = 2.0 * dot(d0, ck);
      const V2<double> d1{cx.c[1], cy.c[1]}, d2{cx.c[2], cy.c[2]};
      if (k == 2) rest += dot(d1, d1);
      if (k == 3) rest += 2.0 * dot(d1, d2);
      uk = -rest / (2.0 * dot(d0, centre_u));
    } else {
      uk = -dot(travel_normal, ck) / dot(travel_normal, centre_u);
    }
    uj.c[k] = uk;
    ++stats.taylor_orders;
    lever[k] = {known.x + q1.x * uk, known.y + q1.y * uk};
    cx.c[k] = ck.x + centre_u.x * uk;
    cy.c[k] = ck.y + centre_u.y * uk;
  }
}

// the unknown body's displacement [rad or mm] from its circle centre (cx, cy); a rotation
// takes the branch nearest `predicted` [rad] and leaves its sine and cosine in the trig memo
Jet3 offset_displacement(const OffsetContact& oc, const Node& node, const Eigen::Vector2d& pivot,
                         const V2<double>& centre, const Jet3& cx, const Jet3& cy, double predicted) {
  Jet3 qn;
  if (node.kind == NodeKind::rotational) {
    qn = atan2(cy - pivot.y(), cx - pivot.x()) - oc.arm_angle;
    // the branch nearest the prediction (the general solver tracks it continuously)
    const double turns = std::round((predicted - qn.value()) / (2 * pi));
    qn.c[0] += turns * 2 * pi;
    // sin and cos of the body's angle from the arm's direction d0 / |d0| turned back by the
    // arm angle: the body's pose then needs no libm call
    const V2<double> d0{centre.x - pivot.x(), centre.y - pivot.y()};
    const double dist = std::sqrt(d0.x * d0.x + d0.y * d0.y);
    const double ca = d0.x / dist, sa = d0.y / dist;
    memo_sin_cos_insert(qn.value(), sa * oc.cos_arm - ca * oc.sin_arm, ca * oc.cos_arm + sa * oc.sin_arm);
  } else {
    qn = node.direction.x() * (cx - oc.centre.x()) + node.direction.y() * (cy - oc.centre.y());
  }
  return qn;
}

}  // namespace

// solves the block through its one equation by newton from the predicted u, then its
// taylor coefficients in the driver and the body's displacement in closed form from the
// centre. solved = false (values untouched) leaves the block to the general solver.
template <int M>
Status Kernel::solve_offset_contact(WorkspaceState::Block& b, double driver, bool& solved) {
  const auto& oc = b.offset;
  const Connection& c = m_.connections[oc.connection];
  const Surface& curve = oc.curve_on_a ? c.surface_a : c.surface_b;
  const Node& node = m_.nodes[oc.unknown_node];
  const Eigen::Vector2d pivot = st_.pivots[oc.unknown_node];
  solved = false;
  const auto& pose3 =
      CachedPoses<Jet3>{m_, ws_.vars.data(), st_.pivots.data(), st_.poses3, st_.point_id, b.solving}.get(
          oc.known_node);
  const auto pose0 = pose_values(pose3);
  // the root of the one equation in u
  OffsetRoot<M> root;
  root.u = st_.values[oc.curve_variable];
  if (!offset_newton<M>(m_, oc, curve, node, pivot, pose0, tolerance(), ws_.stats, root)) return Status::success();
  // the contact outputs evaluate the curve at the shifted u
  if (root.u != root.evaluated_at) m_.profiles[curve.profile].shift_memo(root.evaluated_at, root.u - root.evaluated_at);
  // condition and toggle margin of the block
  if (Status st = offset_condition(m_, ws_, b, c, node, pivot, root.centre, root.centre_u, driver); !st.ok())
    return st;
  // taylor coefficients of u and of the circle centre in the driver
  Jet3 uj, cx, cy;
  offset_taylor<M>(root, pose3, pose0, node, pivot, ws_.stats, uj, cx, cy);
  // the body's displacement from its circle centre
  const Jet3 qn = offset_displacement(oc, node, pivot, root.centre, cx, cy, st_.values[oc.node_variable]);
  st_.values[oc.curve_variable] = root.u;
  st_.values[oc.node_variable] = qn.value();
  ws_.vars[oc.curve_variable] = uj;
  ws_.vars[oc.node_variable] = qn;
  solved = true;
  return Status::success();
}

// the derivatives need the centre's series to order 4 in u (solve_point.cpp)
template Status Kernel::solve_offset_contact<4>(WorkspaceState::Block& b, double driver, bool& solved);

}  // namespace camopt::kin::detail
