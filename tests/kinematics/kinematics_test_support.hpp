#pragma once
// shared pieces of the kinematics accuracy tests: small DesignSpec builders (mechanisms
// inline in code, like the smoke test) and a rigid placement of a textbook frame into the
// drawing; the named tolerances and the per-sweep compare against an oracle come from
// tests/support/compare.hpp.
#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/core/design_spec.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "oracles/oracles.hpp"
#include "support/compare.hpp"

namespace camopt::kin_test {

using Eigen::Vector2d;
using oracles::Motion;

using camopt::pi;
inline constexpr double deg = camopt::rad_per_deg;

// the named tolerances and the compare helpers (tests/support/compare.hpp)
using namespace camopt::test::tol;
using camopt::test::ScalarCompare;
using camopt::test::SweepCompare;

// the accuracy sweep: a full revolution at 0.5 deg
inline constexpr double kSweepStepDeg = 0.5;
inline constexpr int kSweepPoints = 721;  // 0 .. 360 deg, both ends

// a rigid placement of an oracle's textbook frame into the drawing [rad, mm]
struct Placement {
  double angle = 0.0;
  Vector2d shift{0, 0};

  Vector2d point(const Vector2d& p) const { return shift + direction(p); }
  Vector2d direction(const Vector2d& d) const {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * d.x() - s * d.y(), s * d.x() + c * d.y()};
  }
  Vec2 pt(const Vector2d& p) const {
    const Vector2d q = point(p);
    return {q.x(), q.y()};
  }
  Vec2 dir(const Vector2d& d) const {
    const Vector2d q = direction(d);
    return {q.x(), q.y()};
  }
  double degrees(double local_angle_rad) const { return (local_angle_rad + angle) / deg; }
};

inline NodeSpec rotational(const std::string& name, const Vec2& pivot) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::rotational;
  n.pivot_mm = pivot;
  return n;
}

inline NodeSpec translational(const std::string& name, const Vec2& origin, const Vec2& direction) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::translational;
  n.origin_mm = origin;
  n.direction = direction;
  return n;
}

inline NodeSpec floating(const std::string& name) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::floating;
  return n;
}

inline ConnectionSpec link(const std::string& name, const std::string& node_a, const Vec2& pin_a,
                           const std::string& node_b, const Vec2& pin_b) {
  ConnectionSpec c;
  c.name = name;
  c.kind = ConnectionKind::link;
  c.pin_a = {node_a, pin_a, {}};
  c.pin_b = {node_b, pin_b, {}};
  return c;
}

inline SurfaceSpec profile_surface(const std::string& node, const std::string& profile, const Vec2& origin,
                                   double orientation_deg) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::profile;
  s.profile = profile;
  s.origin_mm = origin;
  s.orientation_deg = orientation_deg;
  return s;
}

inline SurfaceSpec circle_surface(const std::string& node, const Vec2& centre, double radius, bool roller) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::circle;
  s.origin_mm = centre;
  s.radius_mm = radius;
  s.roller = roller;
  return s;
}

inline SurfaceSpec line_surface(const std::string& node, const Vec2& point, const Vec2& normal) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::line;
  s.origin_mm = point;
  s.normal = normal;
  return s;
}

inline ConnectionSpec contact(const std::string& name, const SurfaceSpec& a, const SurfaceSpec& b) {
  ConnectionSpec c;
  c.name = name;
  c.kind = ConnectionKind::contact;
  c.surface_a = a;
  c.surface_b = b;
  return c;
}

inline ProfileSpec eccentric_profile(const std::string& name, double R, double e) {
  ProfileSpec p;
  p.name = name;
  p.form = ProfileForm::eccentric;
  p.disc_radius_mm = R;
  p.eccentricity_mm = e;
  return p;
}

// the polar table cam of the accuracy tests: r = 18 + 3 (1 - cos phi)^2 / 4 [mm] sampled at 1 deg
inline double lobe_radius(double phi) {
  const double k = 1.0 - std::cos(phi);
  return 18.0 + 0.75 * k * k;
}
inline ProfileSpec lobe_table(const std::string& name) {
  ProfileSpec p;
  p.name = name;
  p.form = ProfileForm::polar;
  for (int i = 0; i < 360; ++i) {
    p.angle_deg.push_back(i);
    p.radius_mm.push_back(lobe_radius(i * deg));
  }
  return p;
}

// the periodic quintic spline the kernel builds from that table (same sites, same values):
// the reference geometry of the table cam
inline PeriodicSpline lobe_spline() {
  std::vector<double> u, r;
  const ProfileSpec p = lobe_table("lobe");
  for (std::size_t i = 0; i < p.angle_deg.size(); ++i) {
    u.push_back(p.angle_deg[i] * (std::numbers::pi / 180.0));
    r.push_back(p.radius_mm[i]);
  }
  return PeriodicSpline::interpolate(u, r, 2.0 * std::numbers::pi);
}

inline DesignSpec design(const std::string& name, const std::string& driver, const std::string& output) {
  DesignSpec d;
  d.name = name;
  d.driver.node = driver;
  d.output_node = output;
  return d;
}

// displacement jet of a node
inline const Jet<3>& node_jet(const kin::Mechanism& m, const kin::Workspace& ws, const std::string& node) {
  const int n = m.node_index(node);
  REQUIRE(n > 0);
  return ws.vars[static_cast<std::size_t>(m.nodes[static_cast<std::size_t>(n)].first_variable)];
}

inline Motion motion_of(const Jet<3>& j) { return {j.derivative(0), j.derivative(1), j.derivative(2), j.derivative(3)}; }

}  // namespace camopt::kin_test
