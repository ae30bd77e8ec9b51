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

TEST_CASE("revolution_sin_cos matches libm at every sample of the revolution", "[core][trig]") {
  for (int n : {8, 360, 720, 1440, 2880, 100, 1442}) {
    std::vector<double> s, c;
    camopt::revolution_sin_cos(n, s, c);
    REQUIRE(static_cast<int>(s.size()) == n);
    REQUIRE(static_cast<int>(c.size()) == n);
    double worst = 0.0, worst_libm = 0.0;
    int negative_zeros = 0;
    for (int i = 0; i < n; ++i) {
      const long double t = 2 * std::numbers::pi_v<long double> * i / n;
      const double t_double = 2 * std::numbers::pi * i / n;  // as the synthesis samples it
      const long double exact_s = std::sin(t), exact_c = std::cos(t);
      worst = std::max({worst, static_cast<double>(std::abs(s[static_cast<std::size_t>(i)] - exact_s)),
                        static_cast<double>(std::abs(c[static_cast<std::size_t>(i)] - exact_c))});
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
    if (n % 8 == 0) CHECK(worst <= 2.3e-16);
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
