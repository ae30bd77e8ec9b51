// atan2_by_atan (include/camopt/core/angle.hpp) against std::atan2: within 2 ulp on random
// points of every octant and scale, the IEEE special cases unchanged.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "camopt/core/angle.hpp"

namespace {

// distance in units in the last place between two doubles of the same sign
std::int64_t ulps_apart(double a, double b) {
  std::int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  if ((ia < 0) != (ib < 0)) return a == b ? 0 : std::numeric_limits<std::int64_t>::max();
  return ia > ib ? ia - ib : ib - ia;
}

}  // namespace

TEST_CASE("atan2_by_atan: within 2 ulp of std::atan2 in every octant and at every scale", "[core][angle]") {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-30.0, 30.0);
  std::int64_t worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double scale = std::pow(10.0, exponent(rng));
    const double y = unit(rng) * scale, x = unit(rng) * scale * std::pow(10.0, 0.5 * unit(rng));
    const std::int64_t d = ulps_apart(camopt::atan2_by_atan(y, x), std::atan2(y, x));
    worst = std::max(worst, d);
    if (d > 2) FAIL_CHECK("y " << y << " x " << x << ": " << d << " ulp");
  }
  // near the octant boundaries |y| = |x| and the axes
  for (double t : {1.0, 1.0 + 1e-15, 1.0 - 1e-15, 1e-12, 1e12}) {
    for (double sy : {1.0, -1.0})
      for (double sx : {1.0, -1.0}) {
        const double y = sy * t, x = sx * 1.0;
        CHECK(ulps_apart(camopt::atan2_by_atan(y, x), std::atan2(y, x)) <= 2);
      }
  }
  INFO("worst " << worst << " ulp");
  CHECK(worst <= 2);
  CHECK(worst >= 1);  // not std::atan2 itself: the comparison can fail
}

TEST_CASE("atan2_by_atan: zeros, infinities and NaN as std::atan2", "[core][angle]") {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double values[] = {0.0, -0.0, 1.0, -1.0, 1e-310, -1e-310, 1e308, -1e308, inf, -inf};
  for (double y : values)
    for (double x : values) {
      INFO("y " << y << " x " << x);
      const double a = camopt::atan2_by_atan(y, x), b = std::atan2(y, x);
      CHECK(std::signbit(a) == std::signbit(b));
      CHECK(ulps_apart(a, b) <= 2);
    }
  CHECK(std::isnan(camopt::atan2_by_atan(nan, 1.0)));
  CHECK(std::isnan(camopt::atan2_by_atan(1.0, nan)));
}
