#include "camopt/dynamics/ehl.hpp"

#include <cmath>

namespace camopt::dynamics {

EhlProperties ehl_properties(const OilSpec& oil, double e_star_N_per_mm2) {
  // mPa s -> Pa s, 1/GPa -> 1/Pa, E' = 2 E* [MPa -> Pa]
  return {oil.viscosity_mPa_s * 1e-3, oil.pressure_viscosity_per_GPa * 1e-9, 2.0 * e_star_N_per_mm2 * 1e6};
}

double composite_roughness(double rq_a, double rq_b) { return std::hypot(rq_a, rq_b); }

std::optional<double> line_contact_film_um(double force_N, double width_mm, double e_star_N_per_mm2,
                                           double curvature_sum_per_mm, double entrainment_mm_per_rad,
                                           double cam_rad_per_s, const OilSpec& oil) {
  if (!(force_N > 0.0) || !(curvature_sum_per_mm > 0.0)) return std::nullopt;
  const double speed = entrainment_mm_per_rad * cam_rad_per_s * 1e-3;  // [m/s]
  const double load = force_N / (width_mm * 1e-3);                      // [N/m]
  const double radius = 1e-3 / curvature_sum_per_mm;                    // [m]
  return dowson_higginson_film_m(speed, load, radius, ehl_properties(oil, e_star_N_per_mm2)) * 1e6;
}

}  // namespace camopt::dynamics
