#pragma once
// elastohydrodynamic (EHL) minimum film thickness of a line contact: the Dowson-Higginson
// formula, fitted to their isothermal numerical solutions of two cylinders (or a cylinder
// on a flat) in steady rolling and sliding, fully flooded:
//     H_min = h_min / R = 2.65 U^0.70 G^0.54 W^-0.13
//     U = eta0 u_e / (E' R)   speed parameter
//     G = alpha E'            material parameter
//     W = w / (E' R)          load parameter, w the load per unit length
// with u_e = |u_a + u_b| / 2 the mean entrainment speed of the two surfaces relative to the
// contact point, R the reduced radius of curvature (1/R = 1/R_a + 1/R_b), E' = 2 E*
// (2/E' = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b), eta0 the inlet viscosity at ambient
// pressure and alpha the Barus pressure-viscosity coefficient (eta = eta0 exp(alpha p)).
// Dowson & Higginson, Elasto-hydrodynamic Lubrication, SI ed., Pergamon, 1977 (the minimum
// film formula of their line-contact solutions; first published as "New roller-bearing
// lubrication formula", Engineering 192 (1961) 158); the same groups and E' in Hamrock,
// Schmid & Jacobson, Fundamentals of Fluid Film Lubrication, 2nd ed., Dekker, 2004, and
// Hamrock, Fundamentals of Fluid Film Lubrication, NASA RP-1255, 1991.
// In dimensional form h_min = 2.65 alpha^0.54 (eta0 u_e)^0.70 R^0.43 / (E'^0.03 w^0.13).
//
// units: SI inside the formula (m, m/s, N/m, Pa, Pa s, 1/Pa); the names say so.
// The formula is written on a template scalar so it also runs on Dual<M>
// (gradients for the optimiser; the optimiser can also build h^(1/0.70), which is
// proportional to |u_e|, from the constants below).
#include <cmath>
#include <optional>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"

namespace camopt::dynamics {

// H_min = kDowsonHigginsonCoefficient U^kSpeed G^kMaterial W^kLoad
inline constexpr double kDowsonHigginsonCoefficient = 2.65;
inline constexpr double kDowsonHigginsonSpeedExponent = 0.70;
inline constexpr double kDowsonHigginsonMaterialExponent = 0.54;
inline constexpr double kDowsonHigginsonLoadExponent = -0.13;

// the fluid and the solids of one contact [SI]
struct EhlProperties {
  double viscosity_Pa_s = 0.0;             // eta0, dynamic viscosity at the inlet, ambient pressure
  double pressure_viscosity_per_Pa = 0.0;  // alpha, Barus
  double reduced_modulus_Pa = 0.0;         // E' = 2 E*
};

// from a design's [oil] (mPa s, 1/GPa) and a contact modulus E* [N/mm^2 = MPa]
EhlProperties ehl_properties(const OilSpec& oil, double e_star_N_per_mm2);

// h_min [m] at entrainment speed u_e [m/s] (its sign is ignored: the film depends on |u_e|),
// load per unit length w [N/m] > 0 and reduced radius R [m] > 0 (else InputError, as for
// properties that are not positive). At u_e = 0 the film is 0;
// its derivative there is unbounded and is returned as 0 (build on h^(1/0.70) ~ |u_e| for a
// smooth constraint).
template <class T>
T dowson_higginson_film_m(const T& entrainment_m_per_s, const T& load_N_per_m, const T& reduced_radius_m,
                          const EhlProperties& p) {
  using std::pow;
  CAMOPT_THROW_UNLESS(value(load_N_per_m) > 0.0, "dowson_higginson_film_m: load_N_per_m = " +
                                                     format_value(value(load_N_per_m)) + " must be > 0");
  CAMOPT_THROW_UNLESS(value(reduced_radius_m) > 0.0, "dowson_higginson_film_m: reduced_radius_m = " +
                                                         format_value(value(reduced_radius_m)) + " must be > 0");
  CAMOPT_THROW_UNLESS(p.viscosity_Pa_s > 0.0,
                      "EhlProperties::viscosity_Pa_s = " + format_value(p.viscosity_Pa_s) + " must be > 0");
  CAMOPT_THROW_UNLESS(p.pressure_viscosity_per_Pa > 0.0, "EhlProperties::pressure_viscosity_per_Pa = " +
                                                             format_value(p.pressure_viscosity_per_Pa) + " must be > 0");
  CAMOPT_THROW_UNLESS(p.reduced_modulus_Pa > 0.0,
                      "EhlProperties::reduced_modulus_Pa = " + format_value(p.reduced_modulus_Pa) + " must be > 0");
  if (value(entrainment_m_per_s) == 0.0) return T(0.0);
  const T speed = value(entrainment_m_per_s) < 0.0 ? -entrainment_m_per_s : entrainment_m_per_s;
  const T u = p.viscosity_Pa_s * speed / (p.reduced_modulus_Pa * reduced_radius_m);
  const double g = p.pressure_viscosity_per_Pa * p.reduced_modulus_Pa;
  const T w = load_N_per_m / (p.reduced_modulus_Pa * reduced_radius_m);
  return kDowsonHigginsonCoefficient * reduced_radius_m * pow(u, kDowsonHigginsonSpeedExponent) *
         std::pow(g, kDowsonHigginsonMaterialExponent) * pow(w, kDowsonHigginsonLoadExponent);
}

// composite roughness sigma = sqrt(Rq_a^2 + Rq_b^2) of two surfaces' rms roughnesses (any unit)
double composite_roughness(double rq_a, double rq_b);

// film thickness ratio lambda = h_min / sigma (film and roughness in the same unit); below ~1
// the asperities carry load (boundary), 1-3 mixed, above ~3 a full film
template <class T>
T film_lambda(const T& film, double composite_roughness) {
  CAMOPT_THROW_UNLESS(composite_roughness > 0.0,
                      "film_lambda: composite_roughness = " + format_value(composite_roughness) + " must be > 0");
  return film / composite_roughness;
}

// the film of a contact of the rigid model [um], in its units: normal force [N] over the
// contact width [mm], contact modulus E* [N/mm^2], curvature sum 1/R = k_a + k_b [1/mm],
// entrainment [mm per cam rad] at cam speed [rad/s]. nullopt where the formula has no
// meaning: a separated or tensile contact (force <= 0) or conforming surfaces (1/R <= 0).
std::optional<double> line_contact_film_um(double force_N, double width_mm, double e_star_N_per_mm2,
                                           double curvature_sum_per_mm, double entrainment_mm_per_rad,
                                           double cam_rad_per_s, const OilSpec& oil);

}  // namespace camopt::dynamics
