#pragma once
// building a DesignSpec in code, the counterpart of a design file's tables ([[node]],
// [[connection]], [[profile]], [[spring]]): each builder fills the fields its table would
// and leaves the rest at their defaults. Lengths mm, angles deg, forces N, masses kg.
//
//   DesignSpec d = build::design("cam and flat tappet", "cam", "tappet");
//   d.nodes = {build::rotational("cam", {0, 0}), build::translational("tappet", {0, 0}, {0, 1})};
//   d.profiles = {build::eccentric_profile("disc", 20, 4)};
//   d.connections = {build::contact("cam_tappet", build::profile_surface("cam", "disc", {0, 0}, 0),
//                                   build::line_surface("tappet", {0, 0}, {0, -1}))};
//   const kin::Mechanism m = kin::compile(d);
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/design_spec.hpp"

namespace camopt::build {

// [design]: its name, the node the driver turns and the node reported as valve lift
inline DesignSpec design(const std::string& name, const std::string& driver, const std::string& output) {
  DesignSpec d;
  d.name = name;
  d.driver.node = driver;
  d.output_node = output;
  return d;
}

// a body turning about a fixed pivot [mm]
inline NodeSpec rotational(const std::string& name, const Vec2& pivot_mm) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::rotational;
  n.pivot_mm = pivot_mm;
  return n;
}

// a body sliding along a line through origin_mm [mm] in direction (any length; positive sense)
inline NodeSpec translational(const std::string& name, const Vec2& origin_mm, const Vec2& direction) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::translational;
  n.origin_mm = origin_mm;
  n.direction = direction;
  return n;
}

// a body free in the plane (coupler, floating lever): placed by its connections
inline NodeSpec floating(const std::string& name) {
  NodeSpec n;
  n.name = name;
  n.kind = NodeKind::floating;
  return n;
}

// a rigid link of fixed length between pin_a on node_a and pin_b on node_b (drawing, mm)
inline ConnectionSpec link(const std::string& name, const std::string& node_a, const Vec2& pin_a_mm,
                           const std::string& node_b, const Vec2& pin_b_mm) {
  ConnectionSpec c;
  c.name = name;
  c.kind = ConnectionKind::link;
  c.pin_a = {node_a, pin_a_mm, {}};
  c.pin_b = {node_b, pin_b_mm, {}};
  return c;
}

// a [[profile]] surface on node, its table's origin at origin_mm, turned by orientation_deg
inline SurfaceSpec profile_surface(const std::string& node, const std::string& profile, const Vec2& origin_mm,
                                   double orientation_deg) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::profile;
  s.profile = profile;
  s.origin_mm = origin_mm;
  s.orientation_deg = orientation_deg;
  return s;
}

// a circle of radius_mm centred at centre_mm on node; roller = it spins freely on its pin
inline SurfaceSpec circle_surface(const std::string& node, const Vec2& centre_mm, double radius_mm, bool roller) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::circle;
  s.origin_mm = centre_mm;
  s.radius_mm = radius_mm;
  s.roller = roller;
  return s;
}

// a flat face on node through point_mm with outward normal (any length)
inline SurfaceSpec line_surface(const std::string& node, const Vec2& point_mm, const Vec2& normal) {
  SurfaceSpec s;
  s.node = node;
  s.shape = SurfaceShape::line;
  s.origin_mm = point_mm;
  s.normal = normal;
  return s;
}

// a contact between two surfaces (the first on the driving side)
inline ConnectionSpec contact(const std::string& name, const SurfaceSpec& a, const SurfaceSpec& b) {
  ConnectionSpec c;
  c.name = name;
  c.kind = ConnectionKind::contact;
  c.surface_a = a;
  c.surface_b = b;
  return c;
}

// an eccentric disc: radius_mm, its centre eccentricity_mm from the turning axis
inline ProfileSpec eccentric_profile(const std::string& name, double radius_mm, double eccentricity_mm) {
  ProfileSpec p;
  p.name = name;
  p.form = ProfileForm::eccentric;
  p.disc_radius_mm = radius_mm;
  p.eccentricity_mm = eccentricity_mm;
  return p;
}

// a polar table: radius_mm at angle_deg over one turn, angles increasing (periodic)
inline ProfileSpec polar_profile(const std::string& name, std::vector<double> angle_deg,
                                 std::vector<double> radius_mm) {
  ProfileSpec p;
  p.name = name;
  p.form = ProfileForm::polar;
  p.angle_deg = std::move(angle_deg);
  p.radius_mm = std::move(radius_mm);
  return p;
}

// a linear compression spring on a translational node: force = preload_N + rate * compression
inline SpringSpec compression_spring(const std::string& name, const std::string& node, double preload_N,
                                     double rate_N_per_mm) {
  SpringSpec s;
  s.name = name;
  s.kind = SpringKind::compression;
  s.node = node;
  s.preload_N = preload_N;
  s.rate_N_per_mm = rate_N_per_mm;
  return s;
}

}  // namespace camopt::build
