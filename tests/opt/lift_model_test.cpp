// the optimiser's acceleration b-spline lift: closure, rows against evaluation and against
// finite differences, ramps joined with continuous lift, velocity and acceleration.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "camopt/core/error.hpp"
#include "camopt/opt/lift_model.hpp"

using namespace camopt;

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
    CHECK(left.lift == Approx(right.lift).margin(1e-9));
    CHECK(left.vel == Approx(right.vel).margin(1e-9));
    CHECK(left.acc == Approx(right.acc).margin(1e-7));
  }
  // base circle after the event
  const auto end = m.evaluate(x, m.event_end_deg() - 1e-9);
  CHECK(std::abs(end.lift) < 1e-9);
  CHECK(std::abs(end.vel) < 1e-9);
  // the ramps' heights
  CHECK(m.evaluate(x, m.main_start_deg()).lift == Approx(0.2).margin(1e-12));
  CHECK(m.evaluate(x, m.main_end_deg()).lift == Approx(0.25).margin(1e-10));
}

TEST_CASE("lift rows: each derivative is the finite difference of the one below", "[opt][lift]") {
  const auto m = opt::AccelerationSplineLift::compile(rff_event());
  const auto x = closed_random(m, 11);
  const double h = 1e-4;
  for (double th = m.main_start_deg() + 0.3; th < m.main_end_deg() - 0.3; th += 3.7) {
    const auto a = m.evaluate(x, th - h), b = m.evaluate(x, th + h), c = m.evaluate(x, th);
    CHECK((b.lift - a.lift) / (2 * h) == Approx(c.vel).margin(1e-8));
    CHECK((b.vel - a.vel) / (2 * h) == Approx(c.acc).margin(1e-8));
    CHECK((b.acc - a.acc) / (2 * h) == Approx(c.jerk).margin(1e-8));
  }
}

TEST_CASE("fit reproduces a lift of the model space exactly", "[opt][lift]") {
  const auto m = opt::AccelerationSplineLift::compile(rff_event());
  const auto x = closed_random(m, 3);
  const auto y = m.fit([&](double deg) { return m.evaluate(x, deg).lift; }, 0.5);
  for (std::size_t j = 0; j < x.size(); ++j) CHECK(y[j] == Approx(x[j]).margin(1e-10));
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
