#pragma once
// templated geometry of the kinematics kernel, written once for double (values),
// Dual<M> (jacobian columns and r_1 in one sweep) and Jet<N> (the derivative sweeps).
#include <cmath>
#include <vector>

#include "camopt/core/jet.hpp"
#include "camopt/core/trig_cache.hpp"
#include "camopt/core/dual.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/pose.hpp"

namespace camopt::kin::detail {

// the pose types and functions are public (camopt/kinematics/pose.hpp); the kernel names
// them here as well
using kin::V2;
using kin::dot;
using kin::cross;
using kin::Pose;
using kin::offset_local;
using kin::node_pose;

// pose providers for the residuals: direct (recomputed) or cached per point
template <class T>
struct DirectPoses {
  const Mechanism& m;
  const T* vars;
  const Eigen::Vector2d* pivots;
  Pose<T> get(int n) const { return node_pose(m, n, vars, pivots); }
};

// poses of nodes whose variables are final at this point are computed once; the nodes
// being solved (stamp < 0 requested by the caller) are recomputed on every call
template <class T>
struct PoseCache {
  std::vector<Pose<T>> poses;
  std::vector<long> stamp;  // point id at which poses[n] was computed
  void resize(std::size_t nodes) {
    poses.resize(nodes);
    stamp.assign(nodes, -1);
  }
  void invalidate(int n) { stamp[n] = -1; }
};

template <class T>
struct CachedPoses {
  const Mechanism& m;
  const T* vars;
  const Eigen::Vector2d* pivots;
  PoseCache<T>& cache;
  long point;
  const std::vector<char>& solving;  // per node: its variables are unknowns of this block
  // optional: a cache of third-order poses of the same variables; a pose it holds for this
  // point gives this one by truncation (a jet's order-k coefficient depends only on the
  // orders <= k of its arguments, so the coefficients are the same numbers)
  const PoseCache<Jet<3>>* higher = nullptr;
  const Pose<T>& get(int n) const {
    if (solving[n] || cache.stamp[n] != point) {
      if constexpr (is_jet_v<T>) {
        if (higher != nullptr && !solving[n] && higher->stamp[n] == point) {
          cache.poses[n] = truncate_pose(higher->poses[n]);
          cache.stamp[n] = point;
          return cache.poses[n];
        }
      }
      cache.poses[n] = node_pose(m, n, vars, pivots);
      cache.stamp[n] = solving[n] ? -1 : point;
    }
    return cache.poses[n];
  }

 private:
  template <int N>
  static Pose<T> truncate_pose(const Pose<Jet<N>>& p) {
    constexpr int order = T::order;
    Pose<T> out;
    out.tx = truncate<order>(p.tx);
    out.ty = truncate<order>(p.ty);
    out.c = truncate<order>(p.c);
    out.s = truncate<order>(p.s);
    out.rx = p.rx;
    out.ry = p.ry;
    return out;
  }
};

// a surface point in global coordinates with d/du and d2/du2 (curve and line surfaces)
template <class T>
struct SurfacePoint {
  V2<T> p, d1, d2;
};

// second = false skips d2 (the residuals need only the point and its tangent); memo: a
// profile's values through the per-thread spline memo (CamProfile::point)
template <class T>
SurfacePoint<T> surface_point(const Mechanism& m, const Surface& s, const Pose<T>& pose, const T* vars,
                              bool second = true, bool memo = false) {
  SurfacePoint<T> out;
  switch (s.kind) {
    case SurfaceKind::point:
      out.p = pose.apply(s.origin.x(), s.origin.y());
      out.d1 = {T(0.0), T(0.0)};
      out.d2 = out.d1;
      break;
    case SurfaceKind::line: {
      const T& u = vars[s.variable];
      const double tx = -s.normal.y(), ty = s.normal.x();  // tangent: outward normal on its right
      out.p = pose.apply(s.origin.x() + u * tx, s.origin.y() + u * ty);
      out.d1 = pose.rotate(tx, ty);
      out.d2 = {T(0.0), T(0.0)};
      break;
    }
    case SurfaceKind::curve: {
      const CurvePoint<T> c = m.profiles[s.profile].point(vars[s.variable], second, memo);
      const double co = s.cos_orient, so = s.sin_orient;
      out.p = pose.apply(s.origin.x() + co * c.x - so * c.y, s.origin.y() + so * c.x + co * c.y);
      out.d1 = pose.rotate(co * c.dx - so * c.dy, so * c.dx + co * c.dy);
      if (second) out.d2 = pose.rotate(co * c.ddx - so * c.ddy, so * c.ddx + co * c.ddy);
      break;
    }
  }
  return out;
}

// F(q) = integral_0^q ratio for a variable gear
inline double gear_integral(const Connection& c, double q) { return c.ratio_table.integral(0.0, q); }
template <int N>
Jet<N> gear_integral(const Connection& c, const Jet<N>& q) {
  const double x0 = c.ratio_table.knots()[0];
  return c.ratio_table.antiderivative(q) - c.ratio_table.integral(x0, 0.0);
}
template <int M>
Dual<M> gear_integral(const Connection& c, const Dual<M>& q) {
  const Jet<1> f = gear_integral(c, Jet<1>::variable(q.value()));  // F(q0), F'(q0)
  return chain(q, f.c[0], f.c[1]);
}

// residuals of connection c into out[0 .. equation_count); the last one of a contact is
// its closure (signed gap + lash) [mm], the others tangency conditions [mm]
template <class T, class Poses>
void connection_residual(const Mechanism& m, const Connection& c, const T* vars, const Poses& poses, T* out) {
  using std::sqrt;
  switch (c.kind) {
    case ConnectionKind::link:
    case ConnectionKind::crank_slider: {
      const auto pa = poses.get(c.node_a).apply(c.pin_a.x(), c.pin_a.y());
      const auto pb = poses.get(c.node_b).apply(c.pin_b.x(), c.pin_b.y());
      const V2<T> d{pb.x - pa.x, pb.y - pa.y};
      out[0] = sqrt(dot(d, d)) - c.length;
      return;
    }
    case ConnectionKind::gear:
      out[0] = (vars[m.nodes[c.node_b].first_variable] - c.ratio * vars[m.nodes[c.node_a].first_variable]) *
               m.length_scale;
      return;
    case ConnectionKind::variable_gear:
      out[0] = (vars[m.nodes[c.node_b].first_variable] - gear_integral(c, vars[m.nodes[c.node_a].first_variable])) *
               m.length_scale;
      return;
    case ConnectionKind::rack_pinion:
      out[0] = vars[m.nodes[c.node_b].first_variable] - c.pitch_radius * vars[m.nodes[c.node_a].first_variable];
      return;
    case ConnectionKind::contact:
      break;
  }
  const auto& pose_a = poses.get(c.node_a);
  const auto& pose_b = poses.get(c.node_b);
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  const auto a = surface_point(m, sa, pose_a, vars, false);
  const auto b = surface_point(m, sb, pose_b, vars, false);
  if (sa.kind == SurfaceKind::point && sb.kind == SurfaceKind::point) {
    const V2<T> d{b.p.x - a.p.x, b.p.y - a.p.y};
    const T dist = sqrt(dot(d, d));
    const bool inside = sa.offset < 0 || sb.offset < 0;
    const T gap = inside ? -(sa.offset + sb.offset) - dist : dist - (sa.offset + sb.offset);
    out[0] = gap + c.lash;
    return;
  }
  if (sa.kind == SurfaceKind::point || sb.kind == SurfaceKind::point) {
    // curve/line x against the circle centre: (centre - p) . t = 0, (centre - p) . n - r = gap
    const bool a_is_curve = sb.kind == SurfaceKind::point;
    const auto& cu = a_is_curve ? a : b;
    const auto& pt = a_is_curve ? b : a;
    const double radius = a_is_curve ? sb.offset : sa.offset;
    const V2<T> d{pt.p.x - cu.p.x, pt.p.y - cu.p.y};
    const T len = sqrt(dot(cu.d1, cu.d1));
    const V2<T> n{cu.d1.y / len, -cu.d1.x / len};  // outward: right of the ccw tangent
    out[0] = dot(d, cu.d1) / len;
    out[1] = dot(d, n) - radius + c.lash;
    return;
  }
  // two curves: antiparallel tangents, zero tangential offset, closure along a's normal
  const T la = sqrt(dot(a.d1, a.d1)), lb = sqrt(dot(b.d1, b.d1));
  const V2<T> d{b.p.x - a.p.x, b.p.y - a.p.y};
  const V2<T> n{a.d1.y / la, -a.d1.x / la};
  out[0] = cross(a.d1, b.d1) / (la * lb) * m.length_scale;
  out[1] = dot(d, a.d1) / la;
  out[2] = dot(d, n) + c.lash;
}

}  // namespace camopt::kin::detail
