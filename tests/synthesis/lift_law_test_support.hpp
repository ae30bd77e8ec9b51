#pragma once
// shared by the lift-law tests (lift_law_test, lift_law_bspline_test, lift_law_event_test):
// named tolerances, the published reference laws (R. L. Norton, Cam Design and Manufacturing
// Handbook, 2nd ed. (2009), double-dwell functions), the laws under test and a reporting
// compare.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"
#include "camopt/synthesis/lift_law.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

namespace camopt::lift_law_test {

using namespace camopt::synthesis;
using camopt::InputError;
using camopt::pi;
using namespace camopt::test::tol;

inline constexpr double kJoinEps = 1e-7;            // one-sided offset at a join [cam deg]
inline constexpr std::uint32_t kSeed = 20240611;

// peak of |d^k| of a unit rise over a fine grid
inline double unit_peak(const std::function<Motion(double)>& f, int k, int samples = 200000) {
  double peak = 0.0;
  for (int i = 0; i <= samples; ++i) peak = std::max(peak, std::abs(f(static_cast<double>(i) / samples)[k]));
  return peak;
}

// ---- published closed forms (written out independently of the library) -----------------

inline Motion ref_345(double x) {
  return {10 * std::pow(x, 3) - 15 * std::pow(x, 4) + 6 * std::pow(x, 5),
          30 * x * x - 60 * std::pow(x, 3) + 30 * std::pow(x, 4), 60 * x - 180 * x * x + 120 * std::pow(x, 3),
          60 - 360 * x + 360 * x * x};
}

inline Motion ref_4567(double x) {
  return {35 * std::pow(x, 4) - 84 * std::pow(x, 5) + 70 * std::pow(x, 6) - 20 * std::pow(x, 7),
          140 * std::pow(x, 3) - 420 * std::pow(x, 4) + 420 * std::pow(x, 5) - 140 * std::pow(x, 6),
          420 * x * x - 1680 * std::pow(x, 3) + 2100 * std::pow(x, 4) - 840 * std::pow(x, 5),
          840 * x - 5040 * x * x + 8400 * std::pow(x, 3) - 4200 * std::pow(x, 4)};
}

// s = h (x - sin(2 pi x) / (2 pi))
inline Motion ref_cycloidal(double x) {
  return {x - std::sin(2 * pi * x) / (2 * pi), 1 - std::cos(2 * pi * x), 2 * pi * std::sin(2 * pi * x),
          4 * pi * pi * std::cos(2 * pi * x)};
}

// norton's modified sine, exact form: C = 4 pi^2 / (4 + pi)
inline Motion ref_modified_sine(double x) {
  const double d = 4 + pi;
  if (x <= 0.125 || x >= 0.875) {
    const double c0 = x <= 0.125 ? 0.0 : 4.0 / d;
    return {c0 + pi * x / d - std::sin(4 * pi * x) / (4 * d), pi / d * (1 - std::cos(4 * pi * x)),
            4 * pi * pi / d * std::sin(4 * pi * x), 16 * pi * pi * pi / d * std::cos(4 * pi * x)};
  }
  const double a = pi * (1 + 4 * x) / 3;
  return {2 / d + pi * x / d - 9 / (4 * d) * std::sin(a), pi / d * (1 - 3 * std::cos(a)), 4 * pi * pi / d * std::sin(a),
          16 * pi * pi * pi / (3 * d) * std::cos(a)};
}

// norton's modified trapezoid lift, with his published 8-digit coefficients
inline double norton_modified_trapezoid(double x) {
  if (x <= 0.125) return 0.38898448 * (x - std::sin(4 * pi * x) / (4 * pi));
  if (x <= 0.375) return 2.44406184 * x * x - 0.22203097 * x + 0.00723407;
  if (x <= 0.625) return 1.6110154 * x - 0.0309544 * std::sin(4 * pi * x - pi) - 0.3055077;
  if (x <= 0.875) return 4.6660917 * x - 2.44406184 * x * x - 1.2292648;
  return 0.6110154 + 0.3889845 * x + 0.0309544 * std::sin(4 * pi * x - 3 * pi);
}

// modified trapezoid, exact form: C = 8 pi / (2 + pi), acceleration by segments
inline double ref_modified_trapezoid_acc(double x) {
  const double c = 8 * pi / (2 + pi);
  if (x <= 0.125) return c * std::sin(4 * pi * x);
  if (x <= 0.375) return c;
  if (x <= 0.625) return c * std::cos(4 * pi * (x - 0.375));
  if (x <= 0.875) return -c;
  return -c * std::cos(4 * pi * (x - 0.875));
}

// 5-6-7-8-9 polynomial and its derivatives up to 5
inline std::array<double, 6> ref_polydyne_valve(double x) {
  auto p = [](double v, int e) { return std::pow(v, e); };
  return {126 * p(x, 5) - 420 * p(x, 6) + 540 * p(x, 7) - 315 * p(x, 8) + 70 * p(x, 9),
          630 * p(x, 4) - 2520 * p(x, 5) + 3780 * p(x, 6) - 2520 * p(x, 7) + 630 * p(x, 8),
          2520 * p(x, 3) - 12600 * p(x, 4) + 22680 * p(x, 5) - 17640 * p(x, 6) + 5040 * p(x, 7),
          7560 * p(x, 2) - 50400 * p(x, 3) + 113400 * p(x, 4) - 105840 * p(x, 5) + 35280 * p(x, 6),
          15120 * x - 151200 * p(x, 2) + 453600 * p(x, 3) - 529200 * p(x, 4) + 211680 * p(x, 5),
          15120 - 302400 * x + 1360800 * p(x, 2) - 2116800 * p(x, 3) + 1058400 * p(x, 4)};
}

// one law of each kind with a physical height and duration
inline constexpr double kH = 9.5;      // [mm]
inline constexpr double kBeta = 57.0;  // [cam deg]
inline constexpr double kPolydyneK = 0.0023;

// a closed acceleration shape over 8 spans (positive pulse, long negative region)
inline const std::vector<double> kBsplineShape = {0.0, 1.5, 3.0, 2.0, 0.2, -1.0, -1.2, -1.0, -0.6, -0.2, 0.0};

inline std::vector<std::shared_ptr<const RiseLaw>> all_laws() {
  return {std::make_shared<Polynomial345>(kH, kBeta),     std::make_shared<Polynomial4567>(kH, kBeta),
          std::make_shared<Cycloidal>(kH, kBeta),         std::make_shared<ModifiedTrapezoid>(kH, kBeta),
          std::make_shared<ModifiedSine>(kH, kBeta),      std::make_shared<Polydyne>(kH, kBeta, kPolydyneK),
          std::make_shared<BSplineAcceleration>(kH, kBeta, kBsplineShape, 3)};
}

// |a - b| <= tol * scale through the compare helper, the quantity named by `what`
inline void check_close(double a, double b, double tol, double scale, const std::string& what) {
  CHECK_COMPARISON(camopt::test::compare_abs(what, a, b, tol * scale));
}

}  // namespace camopt::lift_law_test
