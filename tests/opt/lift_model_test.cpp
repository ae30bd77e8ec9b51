// the optimiser's acceleration b-spline lift: closure, rows against evaluation and against
// finite differences, ramps joined with continuous lift, velocity and acceleration.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "camopt/core/error.hpp"
#include "camopt/opt/lift_model.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

opt::EventSpec rff_event() {
  opt::EventSpec e;
  e.start_deg = 114.0;
  e.duration_deg = 128.0;
  e.opening_ramp = {0.2, 18.0};
  e.closing_ramp = {0.25, 20.0};
  e.coefficients = 20;
  e.degree = 3;
  return e;
}

// a closed design: random variables projected onto the closure A x = b
std::vector<double> closed_random(const opt::AccelerationSplineLift& m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  Eigen::VectorXd x(m.variables());
  for (int j = 0; j < m.variables(); ++j) x(j) = u(rng);
  const auto& a = m.closure_matrix();
  const Eigen::Vector2d r = m.closure_rhs() - a * x;
  x += a.transpose() * (a * a.transpose()).ldlt().solve(r);
  return {x.data(), x.data() + x.size()};
}

}  // namespace

TEST_CASE("closure puts the main lift on the closing ramp with c2 joins", "[opt][lift]") {
  const auto m = opt::AccelerationSplineLift::compile(rff_event());
  const auto x = closed_random(m, 7);
  for (double join : {m.main_start_deg(), m.main_end_deg()}) {
    const auto left = m.evaluate(x, join - 1e-9), right = m.evaluate(x, join + 1e-9);
    CHECK_ABS(left.lift, right.lift, tol::kOptLiftJoinAbs[0]);
    CHECK_ABS(left.vel, right.vel, tol::kOptLiftJoinAbs[1]);
    CHECK_ABS(left.acc, right.acc, tol::kOptLiftJoinAbs[2]);
  }
  // base circle after the event
  const auto end = m.evaluate(x, m.event_end_deg() - 1e-9);
  CHECK_ABS(end.lift, 0.0, tol::kOptLiftJoinAbs[0]);
  CHECK_ABS(end.vel, 0.0, tol::kOptLiftJoinAbs[1]);
  // the ramps' heights
  CHECK_ABS(m.evaluate(x, m.main_start_deg()).lift, 0.2, tol::kOptOpeningRampAbs);
  CHECK_ABS(m.evaluate(x, m.main_end_deg()).lift, 0.25, tol::kOptClosingRampAbs);
}

TEST_CASE("lift rows: each derivative is the finite difference of the one below", "[opt][lift]") {
  const auto m = opt::AccelerationSplineLift::compile(rff_event());
  const auto x = closed_random(m, 11);
  const double h = 1e-4;
  for (double th = m.main_start_deg() + 0.3; th < m.main_end_deg() - 0.3; th += 3.7) {
    const auto a = m.evaluate(x, th - h), b = m.evaluate(x, th + h), c = m.evaluate(x, th);
    CHECK_ABS((b.lift - a.lift) / (2 * h), c.vel, tol::kOptLiftFdAbs);
    CHECK_ABS((b.vel - a.vel) / (2 * h), c.acc, tol::kOptLiftFdAbs);
    CHECK_ABS((b.acc - a.acc) / (2 * h), c.jerk, tol::kOptLiftFdAbs);
  }
}

TEST_CASE("fit reproduces a lift of the model space exactly", "[opt][lift]") {
  const auto m = opt::AccelerationSplineLift::compile(rff_event());
  const auto x = closed_random(m, 3);
  const auto y = m.fit([&](double deg) { return m.evaluate(x, deg).lift; }, 0.5);
  CHECK_SERIES(test::compare_series("fitted coefficient", y, x, {.abs = tol::kSplineSpaceFitAbs}));
}

TEST_CASE("event validation names the field", "[opt][lift]") {
  auto e = rff_event();
  e.duration_deg = 400;
  CHECK_THROWS_WITH(opt::AccelerationSplineLift::compile(e), Catch::Contains("event.duration_deg = 400"));
  e = rff_event();
  e.opening_ramp = {0.2, 0.0};
  CHECK_THROWS_WITH(opt::AccelerationSplineLift::compile(e), Catch::Contains("event.opening_ramp.height_mm"));
  e = rff_event();
  e.coefficients = 4;
  CHECK_THROWS_WITH(opt::AccelerationSplineLift::compile(e), Catch::Contains("event.coefficients = 4"));
  e = rff_event();
  e.opening_ramp = {0.2, 60.0};
  e.closing_ramp = {0.2, 60.0};
  CHECK_THROWS_WITH(opt::AccelerationSplineLift::compile(e), Catch::Contains("20 %"));
}
