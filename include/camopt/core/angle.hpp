#pragma once
// atan2 through std::atan of a ratio of magnitude <= 1. glibc 2.36's atan2 costs about 160
// instructions a call, its atan about 70; the kinematic kernel takes several angles per
// point (body angles, pressure angles). Within 2 ulp of std::atan2 (the ratio's rounding
// and atan's own, the argument's condition number being <= 1); zeros, infinities and NaN
// go to std::atan2, so every special case keeps its IEEE result.
#include <cmath>
#include <numbers>

namespace camopt {

inline double atan2_by_atan(double y, double x) noexcept {
  const double ay = std::abs(y), ax = std::abs(x);
  if (!(ax > 0.0 && ay > 0.0 && ax <= 1e300 && ay <= 1e300)) return std::atan2(y, x);
  // the first octant, then reflected: |angle| = atan(r) or pi/2 - atan(1/r), then pi - . for x < 0
  double a = ay <= ax ? std::atan(ay / ax) : std::numbers::pi / 2 - std::atan(ax / ay);
  if (x < 0.0) a = std::numbers::pi - a;
  return std::copysign(a, y);
}

}  // namespace camopt
