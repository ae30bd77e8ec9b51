// random valid designs (fixed seed; CAMOPT_STRESS_COUNT raises the count): each is written
// as a design file, read by the real parser, compiled and swept over a revolution, and
// compared with its closed form (tests/oracles) to the accuracy the kinematics issue asks
// for: displacement 1e-9, velocity and acceleration 1e-7, jerk 1e-5 of their peaks.
#include <catch2/catch.hpp>

#include "kinematics/kinematics_test_support.hpp"
#include "stress_support.hpp"

namespace camopt::stress {
namespace {

using kin_test::deg;
using kin_test::Placement;
using kin_test::SweepCompare;
using oracles::Motion;

// a grashof crank-rocker whose transmission angle stays within [20, 160] deg
struct RandomFourBar {
  oracles::FourBar linkage;
  double crank_drawing = 0;
};

RandomFourBar random_four_bar(std::mt19937_64& rng, double scale) {
  for (;;) {
    const double d = uniform(rng, 40, 120) * scale, a = uniform(rng, 0.1, 0.3) * d;
    const double b = uniform(rng, 0.5, 1.5) * d, c = uniform(rng, 0.5, 1.5) * d;
    const double longest = std::max({b, c, d});
    if (a + longest >= b + c + d - longest - 0.05 * d) continue;  // grashof with margin, crank shortest
    const double cos_min = (b * b + c * c - (d - a) * (d - a)) / (2 * b * c);
    const double cos_max = (b * b + c * c - (d + a) * (d + a)) / (2 * b * c);
    const double limit = std::cos(20 * deg);
    if (std::abs(cos_min) > limit || std::abs(cos_max) > limit) continue;
    const Eigen::Vector2d O2 = polar(uniform(rng, 0, d), uniform(rng, -3, 3));
    const Eigen::Vector2d O4 = O2 + polar(d, uniform(rng, -3, 3));
    const int branch = uniform(rng, 0, 1) < 0.5 ? 1 : -1;
    return {{O2, O4, a, b, c, branch}, uniform(rng, 0, 2 * kin_test::pi)};
  }
}

void check_four_bar(const RandomFourBar& r, double step_deg) {
  const kin::Mechanism m = compile_text(four_bar_design(r.linkage, r.crank_drawing));
  const kin::SweepResult result = revolution(m, step_deg, false);
  INFO(result.positions[0].status.str());
  REQUIRE(result.positions[0].status.ok());
  require_finite(result.positions[0]);
  const double th4_0 = r.linkage.solve(r.crank_drawing).rocker_angle[0];
  SweepCompare rocker("random four-bar", true);
  for (std::size_t i = 0; i < result.driver.size(); ++i) {
    Motion ref = r.linkage.solve(r.crank_drawing + result.driver[i] * deg).rocker_angle;
    ref[0] = oracles::wrap_angle(ref[0] - th4_0);
    rocker.add(result.driver[i], node_motion(m, result.positions[0], i, "rocker", true), ref);
  }
  CHECK_COMPARISONS(rocker.compare());
}

// eccentric disc + offset translating roller with the pressure angle below 60 deg
struct RandomRoller {
  oracles::EccentricOffsetRoller cam;
  Placement place;
};

RandomRoller random_roller(std::mt19937_64& rng, double scale) {
  for (;;) {
    const double R = uniform(rng, 10, 30) * scale, e = uniform(rng, 0.05, 0.3) * R, r = uniform(rng, 0.2, 0.6) * R;
    const double offset = uniform(rng, -0.3, 0.3) * R;
    const oracles::EccentricOffsetRoller o{R, e, uniform(rng, -kin_test::pi, kin_test::pi), r, offset};
    double worst = 0;
    for (int i = 0; i < 360; ++i) worst = std::max(worst, o.pressure_angle(i * deg));
    if (worst > 60 * deg) continue;
    return {o, random_placement(rng, R)};
  }
}

void check_roller(const RandomRoller& c, double step_deg) {
  const kin::Mechanism m = compile_text(roller_design(c.cam, c.place));
  const kin::SweepResult result = revolution(m, step_deg);
  INFO(result.positions[0].status.str());
  REQUIRE(result.positions[0].status.ok());
  require_finite(result.positions[0]);
  SweepCompare lift("random offset roller", false);
  kin_test::ScalarCompare pressure("random offset roller pressure angle");
  const std::size_t connections = m.connections.size();
  for (std::size_t i = 0; i < result.driver.size(); ++i) {
    const double t = result.driver[i] * deg;
    lift.add(result.driver[i], node_motion(m, result.positions[0], i, "tappet", false), c.cam.lift(t));
    pressure.add(result.driver[i], result.positions[0].contacts[i * connections].pressure_angle, c.cam.pressure_angle(t));
  }
  CHECK_COMPARISONS(lift.compare());
  CHECK_SERIES(pressure.compare(0.0, 1e-9));
}

// offset slider-crank with the rod angle below 45 deg
struct RandomSliderCrank {
  oracles::SliderCrank linkage;
  double crank_drawing = 0;
};

RandomSliderCrank random_slider_crank(std::mt19937_64& rng, double scale) {
  const double a = uniform(rng, 10, 60) * scale, offset = uniform(rng, -0.5, 0.5) * a;
  const double b = (a + std::abs(offset)) / std::sin(45 * deg) * uniform(rng, 1.0, 2.0);
  const Eigen::Vector2d O2 = polar(uniform(rng, 0, 2 * a), uniform(rng, -3, 3));
  const Eigen::Vector2d u = polar(1, uniform(rng, -3, 3));
  const Eigen::Vector2d S0 = O2 + offset * Eigen::Vector2d(-u.y(), u.x());
  return {{O2, a, b, S0, u, 1, 1}, uniform(rng, 0, 2 * kin_test::pi)};
}

void check_slider_crank(const RandomSliderCrank& r, double step_deg) {
  const oracles::SliderCrank& s = r.linkage;
  const double x0 = s.solve(r.crank_drawing).slider[0];
  const Eigen::Vector2d A = s.crank_pivot + polar(s.crank, r.crank_drawing), B = s.slide_point + x0 * s.slide_direction;
  const kin::Mechanism m = compile_text(header("random_slider_crank", "crank", "slider") +
                                        rotational_node("crank", s.crank_pivot) +
                                        translational_node("slider", B, s.slide_direction) +
                                        pin_connection("rod", "crank_slider", "crank", A, "slider", B));
  const kin::SweepResult result = revolution(m, step_deg, false);
  INFO(result.positions[0].status.str());
  REQUIRE(result.positions[0].status.ok());
  require_finite(result.positions[0]);
  SweepCompare slider("random slider-crank", false);
  for (std::size_t i = 0; i < result.driver.size(); ++i) {
    Motion ref = s.solve(r.crank_drawing + result.driver[i] * deg).slider;
    ref[0] -= x0;
    slider.add(result.driver[i], node_motion(m, result.positions[0], i, "slider", false), ref);
  }
  CHECK_COMPARISONS(slider.compare());
}

}  // namespace

TEST_CASE("random grashof four-bars match freudenstein's closed form", "[stress][random]") {
  auto rng = stress_rng();
  const int count = stress_count(20);
  for (int i = 0; i < count; ++i) {
    const RandomFourBar r = random_four_bar(rng, 1.0);
    INFO("case " << i << ": ground " << (r.linkage.rocker_pivot - r.linkage.crank_pivot).norm() << " crank "
                 << r.linkage.crank << " coupler " << r.linkage.coupler << " rocker " << r.linkage.rocker << " branch "
                 << r.linkage.branch);
    check_four_bar(r, 0.5);
  }
}

TEST_CASE("random eccentric cams with offset roller followers match the closed form", "[stress][random]") {
  auto rng = stress_rng();
  const int count = stress_count(20);
  for (int i = 0; i < count; ++i) {
    const RandomRoller c = random_roller(rng, 1.0);
    INFO("case " << i << ": R " << c.cam.disc_radius << " e " << c.cam.eccentricity << " r " << c.cam.roller_radius
                 << " offset " << c.cam.offset);
    check_roller(c, 0.5);
  }
}

TEST_CASE("random offset slider-cranks match the closed form", "[stress][random]") {
  auto rng = stress_rng();
  const int count = stress_count(20);
  for (int i = 0; i < count; ++i) {
    const RandomSliderCrank r = random_slider_crank(rng, 1.0);
    INFO("case " << i << ": crank " << r.linkage.crank << " rod " << r.linkage.rod);
    check_slider_crank(r, 0.5);
  }
}

TEST_CASE("tiny and huge mechanisms: the same accuracy from 1e-3 to 1e3 times the size", "[stress][scale]") {
  auto rng = stress_rng();
  for (const double scale : {1e-3, 1e-2, 1e2, 1e3}) {
    INFO("scale " << scale);
    check_four_bar(random_four_bar(rng, scale), 0.5);
    check_roller(random_roller(rng, scale), 0.5);
    check_slider_crank(random_slider_crank(rng, scale), 0.5);
  }
}

TEST_CASE("very coarse and very fine grids give the closed form at every point", "[stress][grid]") {
  auto rng = stress_rng();
  for (const double step : {0.01, 10.0, 30.0}) {
    INFO("step " << step << " deg");
    check_four_bar(random_four_bar(rng, 1.0), step);
    check_roller(random_roller(rng, 1.0), step);
    check_slider_crank(random_slider_crank(rng, 1.0), step);
  }
}

}  // namespace camopt::stress
