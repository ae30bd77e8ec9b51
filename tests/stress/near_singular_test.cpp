// near-toggle linkages, pressure angles close to 90 deg and geometry that cannot assemble:
// each run either matches the closed form (and flags its conditioning with the condition
// number the closed form predicts) or stops with a status that names the angle.
#include <catch2/catch.hpp>

#include "stress_support.hpp"

namespace camopt::stress {
namespace {

using kin_test::deg;

// crank-rocker with ground d, crank a and rocker c; the coupler b makes the grashof sum
// s + l = p + q - slack * d (slack > 0: crank-rocker, 0: change point, < 0: not grashof)
oracles::FourBar change_point_four_bar(double slack) {
  const double d = 60, a = 20, c = 50;
  const double b = c + d - a - slack * d;  // longest is b: a + b = c + d - slack d
  return {{0, 0}, {d, 0}, a, b, c, 1};
}

// the block condition of the rocker's closed form: 1 / |sin beta|, beta the angle at the
// rocker pivot between the crank pin and the rocker pin (solver.cpp link_closed_form)
double link_condition(const oracles::FourBar& f, double crank_angle) {
  const Eigen::Vector2d A = f.crank_pivot + polar(f.crank, crank_angle);
  const Eigen::Vector2d B = f.rocker_pivot + polar(f.rocker, f.solve(crank_angle).rocker_angle[0]);
  const Eigen::Vector2d u = A - f.rocker_pivot, v = B - f.rocker_pivot;
  return u.norm() * v.norm() / std::abs(u.x() * v.y() - u.y() * v.x());
}

}  // namespace

TEST_CASE("near-toggle four-bars: exact to the closed form, condition number as predicted", "[stress][toggle]") {
  const double crank_drawing = 90 * deg;
  double previous_condition = 0;
  for (const double slack : {1e-1, 1e-2, 1e-4, 1e-6}) {
    const oracles::FourBar f = change_point_four_bar(slack);
    const kin::Mechanism m = compile_text(four_bar_design(f, crank_drawing));
    const kin::SweepResult result = revolution(m, 0.5, false);
    const kin::PositionResult& p = result.positions[0];
    INFO("slack " << slack << ": " << p.status.str());
    REQUIRE(p.status.ok());
    require_finite(p);
    const double th4_0 = f.solve(crank_drawing).rocker_angle[0];
    kin_test::SweepCompare rocker("near-toggle four-bar", true);
    double max_condition = 0;
    for (std::size_t i = 0; i < result.driver.size(); ++i) {
      const double crank = crank_drawing + result.driver[i] * deg;
      oracles::Motion ref = f.solve(crank).rocker_angle;
      ref[0] = oracles::wrap_angle(ref[0] - th4_0);
      rocker.add(result.driver[i], node_motion(m, p, i, "rocker", true), ref);
      const double expected = link_condition(f, crank);
      CHECK_REL(p.condition[i], expected, test::tol::kConditionRel);
      max_condition = std::max(max_condition, p.condition[i]);
    }
    // near toggle the derivatives grow like 1/sqrt(slack): relative to their own peaks the
    // issue's accuracy still holds
    CHECK_COMPARISONS(rocker.compare());
    CHECK(max_condition > previous_condition);
    const kin::PositionSummary summary = kin::summarize(m, result, 0);
    CHECK_REL(summary.max_condition, max_condition, test::tol::kSummaryOfSameRel);
    previous_condition = max_condition;
  }
}

TEST_CASE("a four-bar past the change point stops where the closed form stops assembling", "[stress][toggle]") {
  const double crank_drawing = 90 * deg;
  const oracles::FourBar f = change_point_four_bar(-0.02);  // not grashof: the crank cannot turn fully
  REQUIRE(f.assembles(crank_drawing));
  const kin::Mechanism m = compile_text(four_bar_design(f, crank_drawing));
  const kin::SweepResult result = revolution(m, 0.5, false);
  const kin::PositionResult& p = result.positions[0];
  REQUIRE_FALSE(p.status.ok());
  CHECK(p.status.code == StatusCode::cannot_assemble);
  // the first sweep angle where the closed form has no solution
  double first_bad = -1;
  for (const double driver : result.driver)
    if (!f.assembles(crank_drawing + driver * deg)) {
      first_bad = driver;
      break;
    }
  REQUIRE(first_bad > 0);
  INFO(p.status.str() << "; closed form first fails at sweep angle " << first_bad);
  CHECK(p.status.where.find("driver " + format_value(first_bad, 6) + " deg") != std::string::npos);
  CHECK(p.status.message.find("coupler") != std::string::npos);
  CHECK(p.status.message.find("cannot close") != std::string::npos);
}

TEST_CASE("pressure angle close to 90 deg: exact to the closed form, conditioning reported", "[stress][pressure_angle]") {
  // offset roller on an eccentric disc: tan(alpha) = |s' - offset| / Y (norton); the
  // offset pushes the largest pressure angle towards 90 deg
  const double R = 20, e = 4, r = 8;
  double previous = 0;
  for (const double offset : {10.0, 20.0, 23.0, 23.9}) {  // reach: offset < R + r - e = 24
    const oracles::EccentricOffsetRoller o{R, e, 0.0, r, offset};
    const kin::Mechanism m = compile_text(roller_design(o, {0.3, {5, -7}}));
    const kin::SweepResult result = revolution(m, 0.5);
    const kin::PositionResult& p = result.positions[0];
    INFO("offset " << offset << ": " << p.status.str());
    REQUIRE(p.status.ok());
    require_finite(p);
    kin_test::SweepCompare lift("offset roller", false);
    kin_test::ScalarCompare alpha("offset roller pressure angle [rad]");
    double max_alpha = 0;
    for (std::size_t i = 0; i < result.driver.size(); ++i) {
      const double t = result.driver[i] * deg;
      lift.add(result.driver[i], node_motion(m, p, i, "tappet", false), o.lift(t));
      alpha.add(result.driver[i], p.contacts[i].pressure_angle, o.pressure_angle(t));
      max_alpha = std::max(max_alpha, o.pressure_angle(t));
    }
    CHECK_COMPARISONS(lift.compare());
    CHECK_SERIES(alpha.compare(0.0, test::tol::kPressureAngleAbs));
    CHECK(max_alpha > previous);
    previous = max_alpha;
    const kin::PositionSummary summary = kin::summarize(m, result, 0);
    CHECK_REL(summary.max_pressure_angle_deg, max_alpha / deg, test::tol::kRefinedExtremeRel);
  }
  CHECK(previous > 80 * deg);  // the last case is within 10 deg of 90
}

TEST_CASE("a roller the cam cannot reach is reported with the angle", "[stress][pressure_angle]") {
  // offset beyond R + r - e: the follower line leaves the reach of the disc on part of the turn
  const double R = 20, e = 4, r = 8, offset = 27.5;
  const oracles::EccentricOffsetRoller o{R, e, 0.0, r, offset};
  REQUIRE(std::abs(offset - e) < R + r);  // drawable at cam 0 (disc centre at (e, 0))
  const kin::Mechanism m = compile_text(roller_design(o, {0.0, {0, 0}}));
  const kin::SweepResult result = revolution(m, 0.5);
  const kin::PositionResult& p = result.positions[0];
  REQUIRE_FALSE(p.status.ok());
  INFO(p.status.str());
  CHECK((p.status.code == StatusCode::cannot_assemble || p.status.code == StatusCode::singular ||
         p.status.code == StatusCode::no_convergence));
  CHECK(p.status.where.find("driver ") == 0);
  CHECK(p.status.str().find("cam_roller") != std::string::npos);
}

}  // namespace camopt::stress
