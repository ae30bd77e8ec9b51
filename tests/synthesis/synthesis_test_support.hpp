#pragma once
// shared by the synthesis tests: closed-form eccentric-disc designs, the bundled designs'
// own lifts as targets, and lift comparisons between designs.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

namespace camopt::synthesis_test {

using namespace camopt::kin_test;

// polar radius of a disc (radius R, centre at distance e on the 0 deg axis) at polar angle a
inline double disc_radius(double R, double e, double a) {
  return e * std::cos(a) + std::sqrt(R * R - e * e * std::sin(a) * std::sin(a));
}

// the target: the design's own forward lift (output node) at 0.5 deg, interpolated periodically
inline PeriodicSpline forward_lift(const DesignSpec& d) {
  const auto m = kin::compile(d);
  PeriodicSpline lift;
  REQUIRE(kin::periodic_motion(m, m.output_node, {}, 0.5, lift).ok());
  return lift;
}

// a bundled design without lash, compiled, and its own lift at one control position [deg]
// sampled every step_deg: the target for synthesizing its cams
struct BundledCase {
  DesignSpec design;
  kin::Mechanism mechanism;
  PeriodicSpline lift;
  BundledCase(const std::string& name, double control, double step_deg = 0.25) {
    design = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml");
    for (auto& c : design.connections) c.lash_mm = 0.0;
    mechanism = kin::compile(design);
    REQUIRE(kin::periodic_motion(mechanism, mechanism.output_node, {control}, step_deg, lift).ok());
  }
};

// largest |lift_a - lift_b| [mm] over a revolution at 0.5 deg, both designs at one control
// position [deg]: a synthesized cam against the original away from the synthesis position
inline camopt::test::Comparison compare_lifts(const DesignSpec& a, const DesignSpec& b, double control, double abs_tol) {
  auto lift_at = [&](const DesignSpec& spec) {
    const auto mech = kin::compile(spec);
    PeriodicSpline lift;
    REQUIRE(kin::periodic_motion(mech, mech.output_node, {control}, 0.5, lift).ok());
    std::vector<double> v;
    for (int i = 0; i < 720; ++i) v.push_back(lift(i * 0.5 * deg));
    return v;
  };
  const auto la = lift_at(a), lb = lift_at(b);
  std::vector<double> cam_deg;
  for (int i = 0; i < 720; ++i) cam_deg.push_back(i * 0.5);
  return camopt::test::compare_series("lift of the synthesized design [mm]", lb, la, {.abs = abs_tol}, cam_deg,
                                      "cam [deg]");
}

inline DesignSpec eccentric_design(bool flat, double R, double e, double roller, double offset) {
  DesignSpec d = design("ecc", "cam", "follower");
  d.nodes = {rotational("cam", {0, 0}), translational("follower", {offset, 0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", R, e)};
  // drawing at cam 0: the disc centre is at (e, 0); the follower touches it
  const double y0 = flat ? R : std::sqrt((R + roller) * (R + roller) - (offset - e) * (offset - e));
  d.nodes[1].origin_mm = {offset, y0};
  d.connections = {contact("cam_follower", profile_surface("cam", "disc", {0, 0}, 0),
                           flat ? line_surface("follower", {offset, y0}, {0, -1})
                                : circle_surface("follower", {offset, y0}, roller, true))};
  return d;
}

// a synthesized profile against the radius of a reference cam at its polar angles [mm]
template <class Radius>
test::Comparison compare_radius(const synthesis::SynthesisResult& res, Radius radius, double abs) {
  std::vector<double> reference;
  for (const double a : res.angle_deg) reference.push_back(radius(a * deg));
  return test::compare_series("synthesized radius [mm]", res.radius_mm, reference, {.abs = abs}, res.angle_deg,
                              "cam [deg]");
}

inline void check_disc(const synthesis::SynthesisResult& res, double R, double e) {
  CHECK_SERIES(compare_radius(res, [&](double a) { return disc_radius(R, e, a); }, test::tol::kDiscProfileAbs));
  // a disc's radius of curvature is R everywhere
  CHECK_REL(res.min_radius_of_curvature_mm, R, test::tol::kDiscCurvatureRel);
  CHECK_FALSE(res.has_concave);
  CHECK_REL(res.base_radius_mm, R - e, test::tol::kDiscExtremeRadiusRel);
  CHECK_REL(res.max_radius_mm, R + e, test::tol::kDiscExtremeRadiusRel);
}

}  // namespace camopt::synthesis_test
