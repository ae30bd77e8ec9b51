#pragma once
// shared pieces of the stress suite (tests/stress): the run count and seed (raised from the
// environment: CAMOPT_STRESS_COUNT, CAMOPT_STRESS_SEED), designs written as TOML text and
// read by the real parser, and a check that a result holds no NaN / Inf.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"

namespace camopt::stress {

inline long env_long(const char* name, long fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  REQUIRE(end != text);
  REQUIRE(*end == '\0');
  return value;
}

// number of random cases per family; CAMOPT_STRESS_COUNT raises it for a longer run
inline int stress_count(int fallback) { return static_cast<int>(env_long("CAMOPT_STRESS_COUNT", fallback)); }
inline std::mt19937_64 stress_rng() { return std::mt19937_64(static_cast<unsigned long>(env_long("CAMOPT_STRESS_SEED", 20261121))); }

// full precision for coordinates written into TOML
inline std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
inline std::string point(double x, double y) { return "[" + num(x) + ", " + num(y) + "]"; }

inline kin::Mechanism compile_text(const std::string& toml) {
  return kin::compile(io::parse_design(toml, "stress.toml", CAMOPT_SOURCE_DIR "/designs"));
}

// a sweep of the default control position over one revolution, every output
inline kin::SweepResult revolution(const kin::Mechanism& mech, double step_deg, bool contacts = true) {
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = step_deg;
  spec.request.derivative_order = 3;
  spec.request.contacts = contacts;
  return kin::sweep(mech, spec);
}

// every number of a successful position is finite
inline void require_finite(const kin::PositionResult& position) {
  std::size_t bad = 0;
  for (const double v : position.data) bad += std::isfinite(v) ? 0 : 1;
  for (const auto& c : position.contacts)
    for (const double v : {c.pressure_angle, c.curvature_a, c.curvature_b, c.sliding, c.roller_speed, c.entrainment})
      bad += std::isfinite(v) ? 0 : 1;
  INFO("non-finite values in a position reported ok");
  REQUIRE(bad == 0);
}

// ---- designs as TOML text --------------------------------------------------------------

inline Eigen::Vector2d polar(double r, double a) { return {r * std::cos(a), r * std::sin(a)}; }

inline double uniform(std::mt19937_64& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

inline kin_test::Placement random_placement(std::mt19937_64& rng, double size) {
  return {uniform(rng, -kin_test::pi, kin_test::pi), {uniform(rng, -2 * size, 2 * size), uniform(rng, -2 * size, 2 * size)}};
}

inline std::string header(const std::string& name, const std::string& driver, const std::string& output) {
  return "schema = 1\n[design]\nname = \"" + name + "\"\noutput_node = \"" + output + "\"\n[driver]\nnode = \"" + driver +
         "\"\ncrank_per_cam = 1\n";
}

inline std::string rotational_node(const std::string& name, const Eigen::Vector2d& pivot) {
  return "[[node]]\nname = \"" + name + "\"\ntype = \"rotational\"\npivot_mm = " + point(pivot.x(), pivot.y()) + "\n";
}

inline std::string translational_node(const std::string& name, const Eigen::Vector2d& origin, const Eigen::Vector2d& dir) {
  return "[[node]]\nname = \"" + name + "\"\ntype = \"translational\"\norigin_mm = " + point(origin.x(), origin.y()) +
         "\ndirection = " + point(dir.x(), dir.y()) + "\n";
}

inline std::string pin_connection(const std::string& name, const std::string& type, const std::string& node_a,
                           const Eigen::Vector2d& a, const std::string& node_b, const Eigen::Vector2d& b) {
  return "[[connection]]\nname = \"" + name + "\"\ntype = \"" + type + "\"\na = { node = \"" + node_a +
         "\", point_mm = " + point(a.x(), a.y()) + " }\nb = { node = \"" + node_b + "\", point_mm = " + point(b.x(), b.y()) +
         " }\nlength_mm = " + num((b - a).norm()) + "\n";
}

// sweep data of a node's variable as a Motion per rad of driver, in rad or mm
inline oracles::Motion node_motion(const kin::Mechanism& m, const kin::PositionResult& p, std::size_t point_index, const std::string& node,
                   bool angle) {
  const int v = m.nodes[static_cast<std::size_t>(m.node_index(node))].first_variable;
  oracles::Motion out;
  for (int k = 0; k <= 3; ++k)
    out[static_cast<std::size_t>(k)] = p.value(point_index, v, k) * std::pow(kin_test::deg, (angle ? 1 : 0) - k);
  return out;
}

// the four-bar drawn at crank angle crank_drawing [rad]
inline std::string four_bar_design(const oracles::FourBar& f, double crank_drawing) {
  const double th4 = f.solve(crank_drawing).rocker_angle[0];
  const Eigen::Vector2d A = f.crank_pivot + polar(f.crank, crank_drawing), B = f.rocker_pivot + polar(f.rocker, th4);
  return header("random_four_bar", "crank", "rocker") + rotational_node("crank", f.crank_pivot) +
         rotational_node("rocker", f.rocker_pivot) + pin_connection("coupler", "link", "crank", A, "rocker", B);
}

// the cam of `o` placed into the drawing by `p`, drawn at cam angle 0
inline std::string roller_design(const oracles::EccentricOffsetRoller& o, const kin_test::Placement& p) {
  const Eigen::Vector2d centre = p.point({o.offset, o.centre_height(0)[0]}), pivot = p.point({0, 0});
  const Eigen::Vector2d up = p.direction({0, 1});
  return header("random_roller", "cam", "tappet") + rotational_node("cam", pivot) + translational_node("tappet", centre, up) +
         "[[profile]]\nname = \"disc\"\nform = \"eccentric\"\ndisc_radius_mm = " + num(o.disc_radius) +
         "\neccentricity_mm = " + num(o.eccentricity) +
         "\n[[connection]]\nname = \"cam_roller\"\ntype = \"contact\"\na = { node = \"cam\", shape = \"profile\", "
         "profile = \"disc\", origin_mm = " +
         point(pivot.x(), pivot.y()) + ", orientation_deg = " + num(p.degrees(o.phase)) +
         " }\nb = { node = \"tappet\", shape = \"circle\", center_mm = " + point(centre.x(), centre.y()) +
         ", radius_mm = " + num(o.roller_radius) + ", roller = true }\n";
}

}  // namespace camopt::stress
