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

namespace camopt::synthesis_test {

using namespace camopt::kin_test;

inline constexpr double kProfileTolerance = 1e-8;   // [mm] synthesized radius against the exact disc
inline constexpr double kRoundTripTolerance = 1e-8; // [mm] forward lift of the synthesized cam against the target

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
inline double worst_lift_difference(const DesignSpec& a, const DesignSpec& b, double control) {
  auto lift_at = [&](const DesignSpec& spec) {
    const auto mech = kin::compile(spec);
    PeriodicSpline lift;
    REQUIRE(kin::periodic_motion(mech, mech.output_node, {control}, 0.5, lift).ok());
    std::vector<double> v;
    for (int i = 0; i < 720; ++i) v.push_back(lift(i * 0.5 * deg));
    return v;
  };
  const auto la = lift_at(a), lb = lift_at(b);
  double worst = 0.0;
  for (std::size_t i = 0; i < la.size(); ++i) worst = std::max(worst, std::abs(la[i] - lb[i]));
  return worst;
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

inline void check_disc(const synthesis::SynthesisResult& res, double R, double e) {
  double worst = 0.0;
  for (std::size_t k = 0; k < res.angle_deg.size(); ++k)
    worst = std::max(worst, std::abs(res.radius_mm[k] - disc_radius(R, e, res.angle_deg[k] * deg)));
  INFO("worst radius error " << worst << " mm");
  CHECK(worst < kProfileTolerance);
  // a disc's radius of curvature is R everywhere
  CHECK(res.min_radius_of_curvature_mm == Approx(R).epsilon(1e-6));
  CHECK_FALSE(res.has_concave);
  CHECK(res.base_radius_mm == Approx(R - e).epsilon(1e-9));
  CHECK(res.max_radius_mm == Approx(R + e).epsilon(1e-9));
}

}  // namespace camopt::synthesis_test
