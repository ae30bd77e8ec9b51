// variable gear ratio: the output angle is the integral of the ratio table. A ratio table
// sampled from a quadratic is reproduced exactly by the natural quintic spline, so
// theta_b = x + k x^3 / 3 for ratio(x) = 1 + k x^2 holds to round-off, with its derivatives.
#include <catch2/catch.hpp>
#include <cmath>

#include "kinematics/kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;

namespace {
constexpr double k = 0.1;  // [1/rad^2]

DesignSpec variable_gear_design(const std::string& driver) {
  DesignSpec d = design("vgear", driver, driver == "a" ? "b" : "a");
  d.nodes = {rotational("a", {0, 0}), rotational("b", {50, 0})};
  ConnectionSpec c;
  c.name = "vgear";
  c.kind = ConnectionKind::variable_gear;
  c.node_a = "a";
  c.node_b = "b";
  for (int i = -40; i <= 40; ++i) {
    const double x = i * 5.0;  // [deg]
    c.ratio_input_deg.push_back(x);
    c.ratio_values.push_back(1 + k * (x * deg) * (x * deg));
  }
  d.connections = {c};
  return d;
}
}  // namespace

TEST_CASE("variable gear: output is the exact integral of the ratio, from either end", "[kinematics][gear]") {
  {
    const auto m = kin::compile(variable_gear_design("a"));
    REQUIRE(m.plan.size() == 1);
    CHECK(m.plan[0].method == kin::StepMethod::variable_gear_closed_form);
    kin::Workspace ws(m);
    for (int i = -90; i <= 90; ++i) {
      const double x = i * deg;
      REQUIRE(kin::solve(m, ws, x, {3, false}).ok());
      const auto& b = node_jet(m, ws, "b");
      CHECK_ABS(b.value(), x + k * x * x * x / 3, kVariableGearAbs[0]);
      CHECK_ABS(b.derivative(1), 1 + k * x * x, kVariableGearAbs[1]);
      CHECK_ABS(b.derivative(2), 2 * k * x, kVariableGearAbs[2]);
      CHECK_ABS(b.derivative(3), 2 * k, kVariableGearAbs[3]);
    }
  }
  {
    // driving the output: the inverse is implicit (Broyden/Newton) with dx/dy = 1 / ratio
    const auto m = kin::compile(variable_gear_design("b"));
    CHECK(m.plan[0].method == kin::StepMethod::implicit);
    kin::Workspace ws(m);
    for (int i = -60; i <= 60; ++i) {
      const double x = i * deg, y = x + k * x * x * x / 3;
      REQUIRE(kin::solve(m, ws, y, {3, false}).ok());
      const auto& a = node_jet(m, ws, "a");
      const double r = 1 + k * x * x, r1 = 2 * k * x;
      CHECK_ABS(a.value(), x, kGearInverseAbs[0]);
      CHECK_ABS(a.derivative(1), 1 / r, kGearInverseAbs[1]);
      // d2x/dy2 = -r' / r^3
      CHECK_ABS(a.derivative(2), -r1 / (r * r * r), kGearInverseAbs[2]);
    }
  }
}
