// revolution_sin_cos: sin and cos of an evenly sampled revolution from its first octant,
// against the exact values (long double, 64-bit mantissa) at every sample: within an ulp of
// 1, as close as libm at the angle rounded to double; libm itself when n is not a multiple
// of 8; no negative zeros (they would turn atan2 by 2 pi).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "camopt/core/trig_cache.hpp"
#include "support/compare.hpp"

TEST_CASE("revolution_sin_cos matches libm at every sample of the revolution", "[core][trig]") {
  for (int n : {8, 360, 720, 1440, 2880, 100, 1442}) {
    std::vector<double> s, c;
    camopt::revolution_sin_cos(n, s, c);
    REQUIRE(static_cast<int>(s.size()) == n);
    REQUIRE(static_cast<int>(c.size()) == n);
    double worst = 0.0, worst_libm = 0.0;
    std::vector<double> error, zero;  // sin and cos of each sample minus the exact value
    int negative_zeros = 0;
    for (int i = 0; i < n; ++i) {
      const long double t = 2 * std::numbers::pi_v<long double> * i / n;
      const double t_double = 2 * std::numbers::pi * i / n;  // as the synthesis samples it
      const long double exact_s = std::sin(t), exact_c = std::cos(t);
      error.push_back(static_cast<double>(s[static_cast<std::size_t>(i)] - exact_s));
      error.push_back(static_cast<double>(c[static_cast<std::size_t>(i)] - exact_c));
      worst = std::max({worst, std::abs(error.end()[-2]), std::abs(error.back())});
      worst_libm = std::max({worst_libm, static_cast<double>(std::abs(std::sin(t_double) - exact_s)),
                             static_cast<double>(std::abs(std::cos(t_double) - exact_c))});
      if (n % 8 != 0) {
        CHECK(s[static_cast<std::size_t>(i)] == std::sin(t_double));
        CHECK(c[static_cast<std::size_t>(i)] == std::cos(t_double));
      }
      for (double v : {s[static_cast<std::size_t>(i)], c[static_cast<std::size_t>(i)]})
        negative_zeros += v == 0.0 && std::signbit(v) ? 1 : 0;
    }
    INFO("n = " << n << ": largest error " << worst << ", libm at the rounded angle " << worst_libm);
    // from the octant: libm's error at a first-octant angle (below an ulp of the value),
    // never the rounding of an angle near 2 pi (up to 1.2e-15 for libm at the sample)
    zero.assign(error.size(), 0.0);
    if (n % 8 == 0)
      CHECK_SERIES(camopt::test::compare_series("sin, cos (even, odd entries) - exact", error, zero,
                                                {.abs = camopt::test::tol::kOctantTrigAbs}));
    CHECK(worst <= worst_libm);
    CHECK(negative_zeros == 0);
    // the quarter turns are exact
    if (n % 8 == 0) {
      CHECK(s[static_cast<std::size_t>(n / 4)] == 1.0);
      CHECK(c[static_cast<std::size_t>(n / 2)] == -1.0);
      CHECK(s[static_cast<std::size_t>(3 * n / 4)] == -1.0);
      CHECK(c[0] == 1.0);
    }
  }
}

// the sin/cos memo: libm's bits on a miss, the stored entry on a hit (the first by index when
// an angle is stored twice), the oldest entry replaced after SinCosMemo::size others, and an
// empty slot (NaN) matched by nothing
TEST_CASE("memo_sin_cos returns libm on a miss and the stored entry on a hit", "[core][trig]") {
  camopt::SinCosMemo& memo = camopt::SinCosMemo::local();
  memo.clear();
  for (int i = 0; i < 40; ++i) {  // more angles than entries, each asked twice
    const double x = -7.0 + 0.37 * i;
    for (int twice = 0; twice < 2; ++twice) {
      double s = 0.0, c = 0.0;
      camopt::memo_sin_cos(x, s, c);
      CHECK(s == std::sin(x));
      CHECK(c == std::cos(x));
    }
  }
  memo.clear();
  camopt::memo_sin_cos_insert(0.5, 0.25, 0.75);  // not sin/cos of 0.5: tells a hit from a miss
  camopt::memo_sin_cos_insert(0.5, -1.0, -2.0);  // a second entry at the same angle, later index
  double s = 0.0, c = 0.0;
  camopt::memo_sin_cos(0.5, s, c);
  CHECK(s == 0.25);
  CHECK(c == 0.75);
  for (int k = 0; k < static_cast<int>(camopt::SinCosMemo::size) - 1; ++k)
    camopt::memo_sin_cos(1.0 + k, s, c);  // the first 0.5 entry is replaced, the second is not
  camopt::memo_sin_cos(0.5, s, c);
  CHECK(s == -1.0);
  CHECK(c == -2.0);
  camopt::memo_sin_cos(1.0 + camopt::SinCosMemo::size, s, c);  // replaces the second
  camopt::memo_sin_cos(0.5, s, c);
  CHECK(s == std::sin(0.5));
  CHECK(c == std::cos(0.5));
  memo.clear();
  camopt::memo_sin_cos(std::nan(""), s, c);
  CHECK(std::isnan(s));
  CHECK(std::isnan(c));
  CHECK(memo.find(std::nan("")) == -1);  // (stored, but NaN equals nothing)
  memo.clear();
}
