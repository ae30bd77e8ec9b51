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

namespace camopt::dynamics {

namespace {
// a = F / (pi L E*) [mm]
double load_length(double force, double length, double e_star) { return force / (std::numbers::pi * length * e_star); }
}  // namespace

double line_contact_approach(double force, double length, double e_star, double reduced_radius) {
  if (!(force > 0.0)) return 0.0;
  const double a = load_length(force, length, e_star);
  return a * (std::log(4.0 * reduced_radius / a) - 1.0);
}

double line_contact_force(double approach, double length, double e_star, double reduced_radius) {
  double cold = 0.0;
  return line_contact_force(approach, length, e_star, reduced_radius, cold);
}

double line_contact_force(double approach, double length, double e_star, double reduced_radius, double& load_length_mm) {
  if (!(approach > 0.0)) {
    load_length_mm = 0.0;
    return 0.0;
  }
  const double c = 4.0 * reduced_radius;
  const bool warm = load_length_mm > 0.0 && load_length_mm < c;
  // a = approach / (ln(c/a) - 1): without a start, one fixed-point pass from a = approach / 10
  // (the log varies slowly); then Newton on f(a) = a (ln(c/a) - 1) - approach, f' = ln(c/a) - 2
  double a = load_length_mm;
  if (!warm) {
    a = approach / std::max(std::log(c / (0.1 * approach)) - 1.0, 1.0);
    a = approach / std::max(std::log(c / a) - 1.0, 1.0);
  }
  bool converged = false;
  for (int it = 0; it < 8 && !converged; ++it) {
    const double l = std::log(c / a);
    const double slope = std::max(l - 2.0, 1e-3);
    const double da = (a * (l - 1.0) - approach) / slope;
    a = std::max(a - da, 0.5 * a);
    converged = std::abs(da) <= 1e-15 * a;
  }
  if (warm && !converged) {  // a start too far off: the cold start's iterations
    load_length_mm = 0.0;
    return line_contact_force(approach, length, e_star, reduced_radius, load_length_mm);
  }
  load_length_mm = a;
  return std::numbers::pi * length * e_star * a;
}

double line_contact_tangent_stiffness(double force, double length, double e_star, double reduced_radius) {
  const double k = std::numbers::pi * length * e_star;
  if (!(force > 0.0)) return 0.0;
  return k / std::max(std::log(4.0 * reduced_radius / load_length(force, length, e_star)) - 2.0, 1e-3);
}

double line_contact_secant_stiffness(double force, double length, double e_star, double reduced_radius) {
  const double k = std::numbers::pi * length * e_star;
  return k / std::max(std::log(4.0 * reduced_radius / load_length(force, length, e_star)) - 1.0, 1.0);
}

double line_contact_energy(double force, double length, double e_star, double reduced_radius) {
  if (!(force > 0.0)) return 0.0;
  const double k = std::numbers::pi * length * e_star;
  return force * force / (2.0 * k) * (std::log(4.0 * reduced_radius / load_length(force, length, e_star)) - 1.5);
}

}  // namespace camopt::dynamics
