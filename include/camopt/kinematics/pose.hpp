#pragma once
// the pose of a body of a compiled mechanism, written once for double, Dual<M> and Jet<N>:
// V2 (a point or vector), Pose (the rigid map drawing -> current), node_pose (a node's pose
// from the variables) and offset_local (the centre of a circle rolling on a profile). The
// kinematics kernel, synthesis, optimisation and dynamics all place bodies with these.
#include <Eigen/Core>
#include <cmath>

#include "camopt/core/dual.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/core/trig_cache.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::kin {

template <class T>
struct V2 {
  T x, y;
};

template <class T>
[[gnu::always_inline]] inline T dot(const V2<T>& a, const V2<T>& b) {
  return a.x * b.x + a.y * b.y;
}
template <class T>
[[gnu::always_inline]] inline T cross(const V2<T>& a, const V2<T>& b) {
  return a.x * b.y - a.y * b.x;
}

// rigid map drawing -> current: p = t + R (p_drawing - ref)
template <class T>
struct Pose {
  T tx, ty, c, s;
  double rx = 0.0, ry = 0.0;

  template <class P>
  V2<T> apply(const P& px, const P& py) const {
    const auto dx = px - rx, dy = py - ry;
    return {tx + c * dx - s * dy, ty + s * dx + c * dy};
  }
  template <class P>
  V2<T> rotate(const P& vx, const P& vy) const {
    return {c * vx - s * vy, s * vx + c * vy};
  }
};

// the circle centre that touches the curve at parameter u, in the curve body's drawing
// frame [mm]: C = p(u) + offset n(u), n the curve's outward unit normal (right of its
// counter-clockwise tangent), as its taylor series of order M in u
template <int M>
inline V2<Jet<M>> offset_local(const Mechanism& m, const Surface& s, double offset, double u) {
  using std::sqrt;
  using T = Jet<M>;
  const CurvePoint<T> c = m.profiles[s.profile].point_series<M>(u);
  const T len = sqrt(square(c.dx) + square(c.dy));
  const T k = offset / len;
  const T qx = c.x + k * c.dy, qy = c.y - k * c.dx;
  const double co = s.cos_orient, so = s.sin_orient;
  return {s.origin.x() + co * qx - so * qy, s.origin.y() + so * qx + co * qy};
}

// pose of node n given all variables (vars) and the current pivots (controls applied)
template <class T>
Pose<T> node_pose(const Mechanism& m, int n, const T* vars, const Eigen::Vector2d* pivots) {
  const Node& node = m.nodes[n];
  Pose<T> p;
  if (node.ground) {
    p.tx = T(0.0);
    p.ty = T(0.0);
    p.c = T(1.0);
    p.s = T(0.0);
    return p;
  }
  switch (node.kind) {
    case NodeKind::rotational: {
      sin_cos(vars[node.first_variable], p.s, p.c);
      p.tx = T(pivots[n].x());
      p.ty = T(pivots[n].y());
      p.rx = node.pivot.x();
      p.ry = node.pivot.y();
      break;
    }
    case NodeKind::translational: {
      const T& q = vars[node.first_variable];
      p.c = T(1.0);
      p.s = T(0.0);
      p.tx = q * node.direction.x();
      p.ty = q * node.direction.y();
      break;
    }
    case NodeKind::floating: {
      const T* q = vars + node.first_variable;
      sin_cos(q[2], p.s, p.c);
      p.tx = q[0] + node.reference.x();
      p.ty = q[1] + node.reference.y();
      p.rx = node.reference.x();
      p.ry = node.reference.y();
      break;
    }
  }
  return p;
}

}  // namespace camopt::kin
