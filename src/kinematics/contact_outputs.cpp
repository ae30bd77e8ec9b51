// per-contact quantities of an accepted point (ContactState): the contact point and normal,
// where it lies on each body, the surfaces' curvatures, the rolling and sliding speeds and
// the pressure angle. They need values and first-order rates only (curvature is taken from
// the values of d1 and d2), so they run on first-order jets.
#include <cmath>

#include "camopt/core/angle.hpp"
#include "kernel.hpp"

namespace camopt::kin::detail {

namespace {

using J1 = Jet<1>;
using SurfacePointD = SurfacePoint<double>;

// velocity [per driver] of the material point at drawing position `local` of a body with this pose
V2<double> material_velocity(const Pose<J1>& pose, const Eigen::Vector2d& local) {
  const auto p = pose.apply(local.x(), local.y());
  return {p.x.c[1], p.y.c[1]};
}

// drawing coordinates of a global point on a body with this pose (inverse at the values)
Eigen::Vector2d to_local(const Pose<J1>& pose, double gx, double gy) {
  const double c = pose.c.value(), s = pose.s.value();
  const double dx = gx - pose.tx.value(), dy = gy - pose.ty.value();
  return {pose.rx + c * dx + s * dy, pose.ry - s * dx + c * dy};
}

// curvature of a surface point [1/mm], + convex
double curvature(const SurfacePointD& s) {
  const double q = dot(s.d1, s.d1);
  return cross(s.d1, s.d2) / (q * std::sqrt(q));
}

// the unit normal n from a into b and the contact point p (into out), and the contact
// point's velocity vc [mm per driver unit], returned. On a curve or line surface p = X(t)
// (S(u(t))): vc = the material velocity of X at p + S_u u'. Between two circles p = C_a +
// |r_a| e, e = d / |d|, d = C_b - C_a: vc = C_a' + |r_a| (d' - e (e . d')) / |d|
V2<double> contact_point(const Connection& c, const SurfacePointD& A, const SurfacePointD& B, const Pose<J1>& pa,
                         const Pose<J1>& pb, const J1* vars, ContactState& out) {
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  V2<double> n, p, vc;
  auto on_surface = [&](const SurfacePointD& sp, const Surface& s, const Pose<J1>& pose) {
    p = sp.p;
    const V2<double> vm = material_velocity(pose, to_local(pose, p.x, p.y));
    const double du = vars[s.variable].c[1];
    vc = {vm.x + sp.d1.x * du, vm.y + sp.d1.y * du};
  };
  if (sa.kind != SurfaceKind::point) {
    const double len = std::sqrt(dot(A.d1, A.d1));
    n = {A.d1.y / len, -A.d1.x / len};
    on_surface(A, sa, pa);
  } else if (sb.kind != SurfaceKind::point) {
    const double len = std::sqrt(dot(B.d1, B.d1));
    n = {-B.d1.y / len, B.d1.x / len};  // b's outward normal points into a
    on_surface(B, sb, pb);
  } else {
    const V2<double> d{B.p.x - A.p.x, B.p.y - A.p.y};
    const double len = std::sqrt(dot(d, d));
    const V2<double> e{d.x / len, d.y / len};
    const double sign = (sa.offset < 0 || sb.offset < 0) ? (sa.offset < 0 ? -1.0 : 1.0) : 1.0;
    n = {sign * e.x, sign * e.y};
    p = {A.p.x + e.x * std::abs(sa.offset), A.p.y + e.y * std::abs(sa.offset)};
    const V2<double> va_centre = material_velocity(pa, sa.origin), vb_centre = material_velocity(pb, sb.origin);
    const V2<double> dd{vb_centre.x - va_centre.x, vb_centre.y - va_centre.y};
    const double along = dot(e, dd), k = std::abs(sa.offset) / len;
    vc = {va_centre.x + k * (dd.x - e.x * along), va_centre.y + k * (dd.y - e.y * along)};
  }
  out.x = p.x;
  out.y = p.y;
  out.normal_x = n.x;
  out.normal_y = n.y;
  return vc;
}

// where the contact point lies on each body (drawing frame), the cam parameter there and
// both surfaces' curvatures
void contact_geometry(const Connection& c, const SurfacePointD& A, const SurfacePointD& B, const Pose<J1>& pa,
                      const Pose<J1>& pb, const double* values, ContactState& out) {
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  const Eigen::Vector2d la = to_local(pa, out.x, out.y);
  const Eigen::Vector2d lb = to_local(pb, out.x, out.y);
  out.local_a_x = la.x();
  out.local_a_y = la.y();
  out.local_b_x = lb.x();
  out.local_b_y = lb.y();
  out.polar_angle_a = sa.variable >= 0 ? values[sa.variable] : 0.0;
  out.curvature_a = sa.kind == SurfaceKind::curve ? curvature(A) : sa.kind == SurfaceKind::point ? 1.0 / sa.offset : 0.0;
  out.curvature_b = sb.kind == SurfaceKind::curve ? curvature(B) : sb.kind == SurfaceKind::point ? 1.0 / sb.offset : 0.0;
}

// a body's angular velocity [rad per driver unit] (0 for the ground and a translating body)
double angular_velocity(const Mechanism& m, const Workspace& ws, int node) {
  double omega = 0.0;
  const Node& cn = m.nodes[node];
  if (!cn.ground && cn.kind == NodeKind::rotational) omega = ws.vars[cn.first_variable].c[1];
  if (!cn.ground && cn.kind == NodeKind::floating) omega = ws.vars[cn.first_variable + 2].c[1];
  return omega;
}

// the surfaces' speeds along the tangent relative to the contact point (vc): sliding,
// entrainment, and a roller's spin for perfect rolling [per driver unit]
void surface_speeds(const Mechanism& m, const Workspace& ws, const Connection& c, const Pose<J1>& pa,
                    const Pose<J1>& pb, const V2<double>& vc, ContactState& out) {
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  // material velocities at the contact point [mm per driver unit]
  const V2<double> va = material_velocity(pa, Eigen::Vector2d(out.local_a_x, out.local_a_y));
  const V2<double> vb = material_velocity(pb, Eigen::Vector2d(out.local_b_x, out.local_b_y));
  const V2<double> t{-out.normal_y, out.normal_x};
  double ua = (va.x - vc.x) * t.x + (va.y - vc.y) * t.y;
  double ub = (vb.x - vc.x) * t.x + (vb.y - vc.y) * t.y;
  out.roller_speed = 0.0;
  const bool roller_a = sa.kind == SurfaceKind::point && sa.roller;
  const bool roller_b = sb.kind == SurfaceKind::point && sb.roller;
  if (roller_a || roller_b) {
    // perfect rolling: the roller's surface moves with the other body's surface
    const Surface& sr = roller_a ? sa : sb;
    const int carrier = roller_a ? c.node_a : c.node_b;
    const V2<double> v_other = roller_a ? vb : va;
    const auto& cpose = roller_a ? pa : pb;
    const V2<double> v_centre = material_velocity(cpose, sr.origin);
    const auto centre = cpose.apply(sr.origin.x(), sr.origin.y());
    const double ex = (out.x - centre.x.value()) / sr.offset, ey = (out.y - centre.y.value()) / sr.offset;
    // omega_abs * r * (z x e) = (v_other - v_centre) tangential
    const double omega_abs = ((v_other.x - v_centre.x) * (-ey) + (v_other.y - v_centre.y) * ex) / sr.offset;
    // carrier angular velocity: d(phi)/d(driver)
    out.roller_speed = omega_abs - angular_velocity(m, ws, carrier);
    if (roller_a) ua = ub; else ub = ua;
  }
  out.sliding = ua - ub;
  out.entrainment = 0.5 * (ua + ub);
}

// pressure angle [rad]: the normal against the direction of motion of the follower's trace
// point - a roller's or pad's centre (the normal passes through it), else the contact point
// on the follower's surface (Norton, Cam Design and Manufacturing Handbook, ch. 7)
double pressure_angle(const Mechanism& m, const Workspace& ws, const SolveStep& step, const Connection& c,
                      const Pose<J1>& pa, const Pose<J1>& pb, const ContactState& out) {
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  const bool follower_is_a = step.output_node == c.node_a;
  const int follower = follower_is_a || step.output_node == c.node_b ? step.output_node : c.node_b;
  const Surface& fs = follower == c.node_a ? sa : sb;
  const Node& fn = m.nodes[follower];
  double trace_x = out.x, trace_y = out.y;
  if (fs.kind == SurfaceKind::point) {
    const auto centre = (follower == c.node_a ? pa : pb).apply(fs.origin.x(), fs.origin.y());
    trace_x = centre.x.value();
    trace_y = centre.y.value();
  }
  V2<double> dir{0, 0};
  if (fn.kind == NodeKind::translational) {
    dir = {fn.direction.x(), fn.direction.y()};
  } else if (fn.kind == NodeKind::rotational) {
    const Eigen::Vector2d o = state(ws).pivots[follower];
    dir = {-(trace_y - o.y()), trace_x - o.x()};
  } else {
    // a floating follower has no fixed path: use the trace point's velocity; while the
    // body is at rest the angle is undefined and reported as 0
    const auto& fpose = follower == c.node_a ? pa : pb;
    dir = material_velocity(fpose, to_local(fpose, trace_x, trace_y));
    if (std::hypot(dir.x, dir.y) < 1e-9 * m.length_scale) dir = {0.0, 0.0};
  }
  const double dn = std::sqrt(dir.x * dir.x + dir.y * dir.y);  // [mm] scale: no overflow
  // atan2 keeps full precision near 0 and 90 deg (acos of a dot product does not)
  const double along = std::abs(dir.x * out.normal_x + dir.y * out.normal_y);
  const double across = std::abs(dir.x * out.normal_y - dir.y * out.normal_x);
  return dn > 0 ? atan2_by_atan(across, along) : 0.0;
}

}  // namespace

void Kernel::contact_outputs(int step_index) {
  const SolveStep& step = m_.plan[step_index];
  for (int ci : step.connections) {
    const Connection& c = m_.connections[ci];
    if (c.kind != ConnectionKind::contact) continue;
    ContactState& out = ws_.contacts[ci];
    ++ws_.stats.contact_outputs;
    out.open = st_.open[step_index];
    if (!out.open) out.gap = 0.0;
    const J1* vars = st_.vars1.data();
    // a body's pose serves every contact it carries (every variable is final here)
    const CachedPoses<J1> poses{m_, vars, st_.pivots.data(), st_.poses1, st_.point_id, st_.no_node_solving, &st_.poses3};
    const auto& pa = poses.get(c.node_a);
    const auto& pb = poses.get(c.node_b);
    // the surfaces at the values: points, tangents d/du and d2/du2 (global) [mm]
    const auto A = surface_point(m_, c.surface_a, pose_values(pa), st_.values.data(), true, true);
    const auto B = surface_point(m_, c.surface_b, pose_values(pb), st_.values.data(), true, true);
    // the contact point, its normal and its velocity
    const V2<double> vc = contact_point(c, A, B, pa, pb, vars, out);
    // where it lies on each body, and the curvatures there
    contact_geometry(c, A, B, pa, pb, st_.values.data(), out);
    // rolling, sliding and entrainment speeds
    surface_speeds(m_, ws_, c, pa, pb, vc, out);
    // the pressure angle at the follower
    out.pressure_angle = pressure_angle(m_, ws_, step, c, pa, pb, out);
  }
}

}  // namespace camopt::kin::detail
