// contacts that touch at rest, solved at compile (contact_assembly.hpp): side b's circle
// centre or line point moved along the contact normal until the shapes touch. The pair of
// shapes decides the closed form: two circles (their centres at the sum of the radii, or
// the difference inside a concave one), a circle on a flat face (the centre at its radius
// from the face), a circle on a cam curve (the centre on the curve's offset at the foot of
// the normal), a face on a circle or a curve (the face on the curve's support point).
#include "camopt/kinematics/contact_assembly.hpp"

#include <algorithm>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"

namespace camopt::kin {

namespace detail {

namespace {

using Eigen::Vector2d;

std::string mm(double v) { return format_value(v, 6) + " mm"; }
std::string point_text(const Vector2d& p) { return "[" + format_value(p.x(), 8) + ", " + format_value(p.y(), 8) + "]"; }

// the rigid map drawing -> drawing pose of every node: zero displacement, the controls at
// their defaults (a node set by a control at it, a pivot moved by one to it)
struct DrawingPose {
  std::vector<double> vars;
  std::vector<Vector2d> pivots;

  explicit DrawingPose(const Mechanism& m) : vars(m.variables.size(), 0.0), pivots(m.nodes.size()) {
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
      const Node& n = m.nodes[i];
      pivots[i] = n.pivot;
      if (n.pivot_control >= 0) {
        const double a = n.pivot_gain * m.controls[n.pivot_control].default_value;
        const Vector2d r = n.pivot - n.pivot_about;
        pivots[i] = n.pivot_about + Vector2d(std::cos(a) * r.x() - std::sin(a) * r.y(),
                                             std::sin(a) * r.x() + std::cos(a) * r.y());
      }
      if (n.control >= 0) {
        const Control& c = m.controls[n.control];
        vars[n.first_variable] = c.is_angle ? c.default_value * pi / 180.0 : c.default_value;
      }
    }
  }
  Pose<double> of(const Mechanism& m, int node) const { return node_pose(m, node, vars.data(), pivots.data()); }
};

Vector2d apply(const Pose<double>& p, const Vector2d& x) {
  const V2<double> v = p.apply(x.x(), x.y());
  return {v.x, v.y};
}
Vector2d rotate(const Pose<double>& p, const Vector2d& x) {
  const V2<double> v = p.rotate(x.x(), x.y());
  return {v.x, v.y};
}
// drawing -> pose inverted: x = r + R^T (p - t)
Vector2d unapply(const Pose<double>& p, const Vector2d& w) {
  const double dx = w.x() - p.tx, dy = w.y() - p.ty;
  return {p.rx + p.c * dx + p.s * dy, p.ry - p.s * dx + p.c * dy};
}

// a point of a curve surface in its body's drawing frame, and its first two derivatives
struct CurveFrame {
  const Mechanism& m;
  const Surface& s;
  Vector2d point(double u, Vector2d* d1 = nullptr, Vector2d* d2 = nullptr) const {
    const CurvePoint<double> c = m.profiles[s.profile].point(u, true);
    const auto rot = [&](double x, double y) {
      return Vector2d(s.cos_orient * x - s.sin_orient * y, s.sin_orient * x + s.cos_orient * y);
    };
    if (d1) *d1 = rot(c.dx, c.dy);
    if (d2) *d2 = rot(c.ddx, c.ddy);
    return s.origin + rot(c.x, c.y);
  }
};

// the parameter u minimising f(u) on a closed curve: a scan of 1440 points, then Newton on
// f'(u) = 0 (f' and f'' given by `derivs`)
template <class F, class D>
double minimise_on_curve(const F& f, const D& derivs) {
  constexpr int samples = 1440;
  double best_u = 0.0, best = f(0.0);
  for (int i = 1; i < samples; ++i) {
    const double u = 2.0 * pi * i / samples;
    if (const double v = f(u); v < best) best = v, best_u = u;
  }
  double u = best_u;
  const double h = 2.0 * pi / samples;
  for (int it = 0; it < 50; ++it) {
    double g = 0.0, gg = 0.0;
    derivs(u, g, gg);
    if (!(gg > 0.0)) break;
    const double step = std::clamp(-g / gg, -h, h);
    u += step;
    if (std::abs(step) < 1e-15) break;
  }
  return u;
}

// a contact drawn touching to within this is left as drawn [mm]: the solve's own round-off
// (a foot point on a spline) is ~1e-14 mm, and a design drawn touching keeps its bits
constexpr double kTouchingTolerance_mm = 1e-12;

struct Solved {
  Vector2d moved_to;   // side b's circle centre or line point (world, the drawing pose)
  double moved = 0.0;  // along the normal a -> b [mm]
};

[[noreturn]] void cannot_close(const Connection& c, const std::string& key, double gap, const std::string& why) {
  throw InputError(c.where, "connection '" + c.name + "': touch_at_rest: " + key + " cannot close on side a: " + why +
                                " (gap " + mm(gap) + ")");
}

// side b a circle (centre cb, signed radius rb) against side a
Solved circle_on(const Mechanism& m, const Connection& c, const Pose<double>& pa, const Vector2d& cb, double rb) {
  const Surface& a = c.surface_a;
  const std::string key = "b.center_mm";
  if (a.kind == SurfaceKind::point) {
    const Vector2d ca = apply(pa, a.origin);
    const double d = (cb - ca).norm(), ra = a.offset;
    const bool inside = ra < 0 || rb < 0;
    const double touching = std::abs(ra + rb);
    const double gap = inside ? touching - d : d - touching;
    if (!(d > 0.0)) cannot_close(c, key, gap, "the centres coincide (no contact normal)");
    if (!inside && d < ra) cannot_close(c, key, gap, "b's centre " + point_text(cb) + " is inside a's circle of radius " + mm(ra));
    if (inside && ra + rb >= 0.0 && ra < 0)
      cannot_close(c, key, gap, "a circle of radius " + mm(rb) + " does not fit inside a's concave radius " + mm(-ra));
    if (inside && ra + rb <= 0.0 && rb < 0)
      cannot_close(c, key, gap, "a's circle of radius " + mm(ra) + " does not fit inside b's concave radius " + mm(-rb));
    const Vector2d n = (cb - ca) / d;
    return {ca + n * touching, touching - d};
  }
  if (rb < 0) cannot_close(c, key, 0.0, "a concave circle touches only a circle");
  if (a.kind == SurfaceKind::line) {
    const Vector2d q = apply(pa, a.origin), n = rotate(pa, a.normal);
    const double d = (cb - q).dot(n);
    if (d < 0) cannot_close(c, key, d - rb, "b's centre " + point_text(cb) + " is behind a's face");
    return {cb + n * (rb - d), rb - d};
  }
  // a curve: the foot of the normal from the centre, in a's drawing frame
  const CurveFrame curve{m, a};
  const Vector2d local = unapply(pa, cb);
  const double u = minimise_on_curve([&](double t) { return (curve.point(t) - local).squaredNorm(); },
                                     [&](double t, double& g, double& gg) {
                                       Vector2d d1, d2;
                                       const Vector2d e = curve.point(t, &d1, &d2) - local;
                                       g = e.dot(d1);
                                       gg = d1.squaredNorm() + e.dot(d2);
                                     });
  Vector2d d1;
  const Vector2d foot = curve.point(u, &d1);
  const Vector2d n = Vector2d(d1.y(), -d1.x()).normalized();  // outward: right of the ccw tangent
  const double d = (local - foot).dot(n);
  if (d < 0) cannot_close(c, key, d - rb, "b's centre " + point_text(cb) + " is inside a's profile");
  return {apply(pa, foot + n * rb), rb - d};
}

// side b a flat face (point q, unit normal n towards a) against side a
Solved face_on(const Mechanism& m, const Connection& c, const Pose<double>& pa, const Vector2d& q, const Vector2d& n) {
  const Surface& a = c.surface_a;
  const std::string key = "b.point_mm";
  if (a.kind == SurfaceKind::point) {
    if (a.offset < 0) cannot_close(c, key, 0.0, "a flat face cannot touch a concave circle");
    const Vector2d ca = apply(pa, a.origin);
    const double h = (ca - q).dot(n);  // a's centre ahead of the face
    if (h < 0) cannot_close(c, key, h - a.offset, "a's centre " + point_text(ca) + " is behind b's face");
    return {q + n * (h - a.offset), a.offset - h};
  }
  // a curve: its support point against the face's normal, in a's drawing frame
  const CurveFrame curve{m, a};
  const Vector2d nl = Vector2d(pa.c * n.x() + pa.s * n.y(), -pa.s * n.x() + pa.c * n.y());
  const double u = minimise_on_curve([&](double t) { return curve.point(t).dot(nl); },
                                     [&](double t, double& g, double& gg) {
                                       Vector2d d1, d2;
                                       curve.point(t, &d1, &d2);
                                       g = d1.dot(nl);
                                       gg = d2.dot(nl);
                                     });
  const Vector2d support = apply(pa, curve.point(u));
  const double gap = (support - q).dot(n);
  return {q + n * gap, -gap};
}

}  // namespace

bool has_unsolved_contacts(const DesignSpec& spec) {
  return std::any_of(spec.connections.begin(), spec.connections.end(), [](const ConnectionSpec& c) {
    return c.kind == ConnectionKind::contact && c.touch_at_rest && !c.drawn_b_mm;
  });
}

void assemble_mechanism_contacts(const DesignSpec& spec, Mechanism& m) {
  const DrawingPose drawing(m);
  for (std::size_t ci = 0; ci < spec.connections.size(); ++ci) {
    const ConnectionSpec& cs = spec.connections[ci];
    if (cs.kind != ConnectionKind::contact || !cs.touch_at_rest) continue;
    Connection& c = m.connections[ci];
    Surface& b = c.surface_b;
    const std::string key = b.kind == SurfaceKind::line ? "b.point_mm" : "b.center_mm";
    if (cs.drawn_b_mm) {
      m.assembled.push_back({static_cast<int>(ci), key, *cs.drawn_b_mm, cs.surface_b.origin_mm, cs.moved_b_mm});
      continue;
    }
    if (b.kind == SurfaceKind::curve)
      throw InputError(c.where, "connection '" + c.name + "': touch_at_rest moves side b, a circle or a line; b is a "
                                "profile (give the profile as side a)");
    const Pose<double> pa = drawing.of(m, c.node_a), pb = drawing.of(m, c.node_b);
    const Solved s = b.kind == SurfaceKind::point ? circle_on(m, c, pa, apply(pb, b.origin), b.offset)
                                                  : face_on(m, c, pa, apply(pb, b.origin), rotate(pb, b.normal));
    const Vector2d drawn = b.origin;
    const bool touching = std::abs(s.moved) <= kTouchingTolerance_mm;
    if (!touching) b.origin = unapply(pb, s.moved_to);
    m.assembled.push_back(
        {static_cast<int>(ci), key, {drawn.x(), drawn.y()}, {b.origin.x(), b.origin.y()}, touching ? 0.0 : s.moved});
  }
}

}  // namespace detail

void assemble_contacts(DesignSpec& spec) {
  if (!detail::has_unsolved_contacts(spec)) return;
  const Mechanism m = detail::compile_as_drawn(spec);
  for (const AssembledContact& a : m.assembled) {
    ConnectionSpec& c = spec.connections[static_cast<std::size_t>(a.connection)];
    if (c.drawn_b_mm) continue;
    c.drawn_b_mm = c.surface_b.origin_mm;
    c.surface_b.origin_mm = a.solved_mm;
    c.moved_b_mm = a.moved_mm;
  }
}

}  // namespace camopt::kin
