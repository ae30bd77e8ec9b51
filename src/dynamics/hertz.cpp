#include "camopt/dynamics/hertz.hpp"

#include <cmath>
#include <numbers>

namespace camopt::dynamics {

HertzLine hertz_line(double force, double length, double e_star, double curvature_sum) {
  if (!(force > 0.0) || !(curvature_sum > 0.0)) return {};
  const double p = force / length;         // load per unit length [N/mm]
  const double r = 1.0 / curvature_sum;    // reduced radius R* [mm]
  constexpr double pi = std::numbers::pi;
  return {std::sqrt(p * e_star / (pi * r)), std::sqrt(4.0 * p * r / (pi * e_star))};
}

}  // namespace camopt::dynamics
