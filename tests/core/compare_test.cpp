// the tests' compare helper (tests/support/compare.hpp) itself: each check passes inside its
// tolerance, fails outside it, and fails on a value, reference or tolerance that is not
// finite; a series reports its worst point. Read through the Comparison it returns, not
// through a failing CHECK.
#include <catch2/catch.hpp>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/compare.hpp"

namespace {

using camopt::test::Comparison;
using camopt::test::compare;
using camopt::test::compare_abs;
using camopt::test::compare_matrix;
using camopt::test::compare_rel;
using camopt::test::compare_series;
using camopt::test::Tolerance;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// every non-finite way of breaking a comparison of 1 against 1 with tolerance 0.5
void check_fails_when_not_finite(Comparison (*cmp)(double value, double reference, double tol)) {
  CHECK(cmp(1.0, 1.0, 0.5).pass);
  for (const double bad : {kNaN, kInf, -kInf}) {
    INFO("non-finite " << bad);
    CHECK_FALSE(cmp(bad, 1.0, 0.5).pass);
    CHECK_FALSE(cmp(1.0, bad, 0.5).pass);
    CHECK_FALSE(cmp(bad, bad, 0.5).pass);
    CHECK_FALSE(cmp(1.0, 1.0, bad).pass);
  }
}

}  // namespace

TEST_CASE("compare helper: absolute check passes inside and fails outside its tolerance", "[core][compare]") {
  CHECK(compare_abs("x", 1.0 + 0.9e-3, 1.0, 1e-3).pass);
  CHECK(compare_abs("x", 0.5, 1.0, 0.5).pass);  // the bound itself passes
  CHECK_FALSE(compare_abs("x", 1.0 + 1.1e-3, 1.0, 1e-3).pass);
  CHECK_FALSE(compare_abs("x", -1.0, 1.0, 1e-3).pass);
  // absolute means independent of the reference's size
  CHECK_FALSE(compare_abs("x", 1e6 + 1.0, 1e6, 1e-3).pass);
  const Comparison c = compare_abs("lift [mm]", 2.5, 2.0, 0.1);
  CHECK(c.error == 0.5);
  CHECK(c.allowed == 0.1);
  check_fails_when_not_finite([](double v, double r, double t) { return compare_abs("x", v, r, t); });
}

TEST_CASE("compare helper: relative check scales with the reference", "[core][compare]") {
  CHECK(compare_rel("x", 100.0 + 0.9e-4, 100.0, 1e-6).pass);
  CHECK_FALSE(compare_rel("x", 100.0 + 1.1e-4, 100.0, 1e-6).pass);
  CHECK(compare_rel("x", -100.0 - 0.9e-4, -100.0, 1e-6).pass);  // the scale is |reference|
  // a reference of 0 leaves no room: only an exact 0 passes
  CHECK(compare_rel("x", 0.0, 0.0, 1e-6).pass);
  CHECK_FALSE(compare_rel("x", 1e-300, 0.0, 1e-6).pass);
  CHECK(compare_rel("x", 3.0, 2.0, 0.5).allowed == 1.0);
  check_fails_when_not_finite([](double v, double r, double t) { return compare_rel("x", v, r, t); });
}

TEST_CASE("compare helper: abs-or-rel check allows the larger of the two", "[core][compare]") {
  const Tolerance tol{.abs = 1e-3, .rel = 1e-6};
  CHECK(compare("x", 0.9e-3, 0.0, tol).pass);       // near 0: the absolute part
  CHECK_FALSE(compare("x", 1.1e-3, 0.0, tol).pass);
  CHECK(compare("x", 1e4 + 0.9e-2, 1e4, tol).pass);  // large: the relative part (1e-2)
  CHECK_FALSE(compare("x", 1e4 + 1.1e-2, 1e4, tol).pass);
  CHECK(compare("x", 1.0, 1e4, tol).allowed == 1e-2);
  check_fails_when_not_finite([](double v, double r, double t) { return compare("x", v, r, {.abs = t, .rel = t}); });
  CHECK_FALSE(compare("x", 1.0, 1.0, {.abs = 0.5, .rel = kNaN}).pass);
  CHECK_FALSE(compare("x", 1.0, 1.0, {.abs = kNaN, .rel = 0.5}).pass);
  CHECK_FALSE(compare("x", 1.0, 1.0, {.abs = -1.0}).pass);  // a negative tolerance is a mistake
}

TEST_CASE("compare helper: a series reports its worst point and fails on any non-finite point",
          "[core][compare]") {
  const std::vector<double> at{0.0, 10.0, 20.0, 30.0};
  const std::vector<double> ref{1.0, -4.0, 2.0, 0.5};
  std::vector<double> val{1.0, -4.0 + 3e-6, 2.0 - 1e-6, 0.5};
  // absolute, and relative to the peak |reference| (4)
  CHECK(compare_series("s", val, ref, {.abs = 3e-6}).pass);
  CHECK_FALSE(compare_series("s", val, ref, {.abs = 2.9e-6}).pass);
  CHECK(compare_series("s", val, ref, {.rel = 0.75e-6}).pass);
  CHECK_FALSE(compare_series("s", val, ref, {.rel = 0.74e-6}).pass);
  const Comparison c = compare_series("lift [mm]", val, ref, {.abs = 1e-6}, at, "angle [deg]");
  CHECK_FALSE(c.pass);
  CHECK(c.where == "index 1, angle [deg] 10");
  CHECK(c.value == val[1]);
  CHECK(c.reference == -4.0);
  const std::string message = c.describe();
  for (const char* part : {"lift [mm]", "FAILED", "index 1", "angle [deg] 10", "value", "reference", "error", "allowed"})
    CHECK(message.find(part) != std::string::npos);
  // a non-finite point anywhere fails, and is the point reported
  for (const double bad : {kNaN, kInf}) {
    std::vector<double> v = val, r = ref;
    v[3] = bad;
    const Comparison cv = compare_series("s", v, ref, {.abs = 1.0});
    CHECK_FALSE(cv.pass);
    CHECK(cv.where == "index 3");
    r[2] = bad;
    CHECK_FALSE(compare_series("s", val, r, {.abs = 1.0}).pass);
    CHECK_FALSE(compare_series("s", val, r, {.rel = 1.0}).pass);
  }
  CHECK_FALSE(compare_series("s", val, ref, {.abs = kNaN}).pass);
  CHECK_FALSE(compare_series("s", val, ref, {.rel = kInf}).pass);
  // an empty series, or series of different lengths, fail
  CHECK_FALSE(compare_series("s", std::vector<double>{}, std::vector<double>{}, {.abs = 1.0}).pass);
  CHECK_FALSE(compare_series("s", val, std::vector<double>{1.0}, {.abs = 1.0}).pass);
  CHECK_FALSE(compare_series("s", val, ref, {.abs = 1.0}, std::vector<double>{0.0}).pass);
}

TEST_CASE("compare helper: Eigen matrices entry by entry with the worst row and column", "[core][compare]") {
  Eigen::Matrix2d ref;
  ref << 1.0, 2.0, 3.0, 4.0;
  Eigen::Matrix2d val = ref;
  val(0, 1) += std::ldexp(1.0, -30);  // ~0.93e-9, exact
  CHECK(compare_matrix("K", val, ref, {.abs = 1e-9}).pass);
  const Comparison c = compare_matrix("K", val, ref, {.abs = 0.5e-9});
  CHECK_FALSE(c.pass);
  CHECK(c.where == "row 0, column 1");
  CHECK(compare_matrix("K", val, ref, {.rel = 0.25e-9}).pass);  // of the largest |entry| (4)
  val(1, 0) = kNaN;
  CHECK_FALSE(compare_matrix("K", val, ref, {.abs = 1.0}).pass);
  CHECK_FALSE(compare_matrix("K", Eigen::Vector2d(1.0, 2.0), ref, {.abs = 1.0}).pass);
}

TEST_CASE("compare helper: a sweep compares each order against its own peak and angles modulo 2 pi",
          "[core][compare]") {
  using camopt::test::SweepCompare;
  const double two_pi = 2.0 * std::numbers::pi;
  SweepCompare angle("rocker", true), plain("slider", false);
  for (int i = 0; i < 3; ++i) {
    const SweepCompare::Motion oracle{0.1 * i, 1.0, 2.0, 3.0};
    angle.add(i, {0.1 * i + two_pi, 1.0, 2.0, 3.0}, oracle);
    plain.add(i, {0.1 * i + two_pi, 1.0, 2.0, 3.0}, oracle);
  }
  for (const Comparison& c : angle.compare()) CHECK(c.pass);
  const std::vector<Comparison> p = plain.compare();
  REQUIRE(p.size() == 4);
  CHECK_FALSE(p[0].pass);
  CHECK(p[1].pass);
  SweepCompare broken("rocker", true);
  broken.add(0.0, {0.0, kNaN, 2.0, 3.0}, {0.0, 1.0, 2.0, 3.0});
  CHECK_FALSE(broken.compare()[1].pass);
  CHECK(SweepCompare("empty", false).compare()[0].pass == false);
}
