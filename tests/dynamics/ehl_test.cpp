// the Dowson-Higginson minimum film thickness of a line contact (dynamics/ehl.hpp): against
// an independent evaluation of its dimensional form, its exact power laws, its Dual
// derivatives against central differences, and the rigid model's unit conversions.
//
// No worked numerical example of this formula with printed inputs and result was found in
// the stored literature searched (Hamrock NASA RP-1255, Hamrock-Schmid-Jacobson, Stachowiak &
// Batchelor, cam-tappet EHL studies): the reference below is the dimensional form written out
// independently of the library's dimensionless groups,
//   h_min = 2.65 alpha^0.54 (eta0 u_e)^0.70 R^0.43 / (E'^0.03 w^0.13)
// (Dowson & Higginson, Elasto-hydrodynamic Lubrication, SI ed., 1977).
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>

#include "camopt/dynamics/ehl.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/core/dual.hpp"
#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

using namespace camopt;
using camopt::Dual;
namespace tol = camopt::test::tol;

namespace {

// steel on steel (E 210 GPa, nu 0.3) and a warm oil (9.1 mPa s, 15.8 /GPa)
OilSpec oil() {
  OilSpec o;
  o.viscosity_mPa_s = 9.1;
  o.pressure_viscosity_per_GPa = 15.8;
  o.composite_roughness_um = 0.25;
  return o;
}
const double kEStar = dynamics::contact_modulus(210e3, 0.3, 210e3, 0.3);  // [N/mm^2]
const dynamics::EhlProperties kProps = dynamics::ehl_properties(oil(), kEStar);

// the dimensional form, written out [SI]
double reference_film_m(double u, double w, double r, double eta, double alpha, double e_prime) {
  return 2.65 * std::pow(alpha, 0.54) * std::pow(eta * u, 0.70) * std::pow(r, 0.43) /
         (std::pow(e_prime, 0.03) * std::pow(w, 0.13));
}

double film(double u, double w, double r) { return dynamics::dowson_higginson_film_m(u, w, r, kProps); }

}  // namespace

TEST_CASE("ehl: the oil and the contact modulus in SI, E' = 2 E*", "[dynamics][ehl]") {
  // 1/E* = 2 (1 - 0.09) / 210 GPa
  CHECK_REL(kEStar, 210e3 / (2 * 0.91), tol::kUlpRel);
  CHECK_REL(kProps.viscosity_Pa_s, 9.1e-3, tol::kUlpRel);
  CHECK_REL(kProps.pressure_viscosity_per_Pa, 15.8e-9, tol::kUlpRel);
  CHECK_REL(kProps.reduced_modulus_Pa, 2 * 210e9 / (2 * 0.91), tol::kUlpRel);
}

TEST_CASE("ehl: Dowson-Higginson against its dimensional form", "[dynamics][ehl]") {
  // a roller of the bundled finger follower's size on a cam: u_e 4 m/s, 900 N over 9 mm
  // (1e5 N/m), R 8 mm: U = 1.9717e-11, G = 3646.2, W = 5.4167e-5, h_min = 0.2045 um
  const double u = 4.0, w = 1e5, r = 8e-3;
  const double expected = reference_film_m(u, w, r, 9.1e-3, 15.8e-9, 2 * 210e9 / (2 * 0.91));
  CHECK_REL(expected, 0.20451e-6, tol::kPrinted5DigitsRel);
  CHECK_REL(film(u, w, r), expected, tol::kPowerLawRel);
  // the film depends on the entrainment's size, not its sense; none without entrainment
  CHECK(film(-u, w, r) == film(u, w, r));
  CHECK(film(0.0, w, r) == 0.0);
  // lambda = h / sigma, sigma = sqrt(Rq_a^2 + Rq_b^2)
  CHECK_REL(dynamics::composite_roughness(0.3, 0.4), 0.5, tol::kUlpRel);
  CHECK_REL(dynamics::film_lambda(expected * 1e6, 0.25), expected * 1e6 / 0.25, tol::kUlpRel);
}

TEST_CASE("ehl: exact power laws in speed, viscosity, pressure-viscosity, load, radius and modulus",
          "[dynamics][ehl]") {
  const double u = 3.0, w = 2e5, r = 12e-3, k = 2.0;
  const double h = film(u, w, r);
  CHECK_REL(film(k * u, w, r) / h, std::pow(k, 0.70), tol::kPowerLawRel);
  CHECK_REL(film(u, k * w, r) / h, std::pow(k, -0.13), tol::kPowerLawRel);
  CHECK_REL(film(u, w, k * r) / h, std::pow(k, 0.43), tol::kPowerLawRel);
  auto with = [&](double eta, double alpha, double e_prime) {
    return dynamics::dowson_higginson_film_m(u, w, r, dynamics::EhlProperties{eta, alpha, e_prime});
  };
  const auto& p = kProps;
  CHECK_REL(with(k * p.viscosity_Pa_s, p.pressure_viscosity_per_Pa, p.reduced_modulus_Pa) / h, std::pow(k, 0.70),
            tol::kPowerLawRel);
  CHECK_REL(with(p.viscosity_Pa_s, k * p.pressure_viscosity_per_Pa, p.reduced_modulus_Pa) / h, std::pow(k, 0.54),
            tol::kPowerLawRel);
  CHECK_REL(with(p.viscosity_Pa_s, p.pressure_viscosity_per_Pa, k * p.reduced_modulus_Pa) / h, std::pow(k, -0.03),
            tol::kPowerLawRel);
  // h^(1/0.70) is proportional to |u_e| (the optimiser's smooth row)
  const double inv = 1.0 / dynamics::kDowsonHigginsonSpeedExponent;
  CHECK_REL(std::pow(film(5 * u, w, r), inv) / std::pow(h, inv), 5.0, tol::kPowerLawRel);
}

TEST_CASE("ehl: Dual derivatives of the film against central differences", "[dynamics][ehl]") {
  // directions: entrainment [m/s], load per length [N/m], radius [m]
  for (const double u : {4.0, -2.5, 0.3}) {
    const double w = 1.2e5, r = 6e-3;
    Dual<3> du(u), dw(w), dr(r);
    du.d = {1, 0, 0};
    dw.d = {0, 1, 0};
    dr.d = {0, 0, 1};
    const Dual<3> h = dynamics::dowson_higginson_film_m(du, dw, dr, kProps);
    CHECK_REL(h.v, film(u, w, r), tol::kPowerLawRel);
    const double hu = 1e-3 * std::abs(u);
    const double dh_du = oracles::central_difference([&](double x) { return film(x, w, r); }, u, 1, 4, hu);
    const double dh_dw = oracles::central_difference([&](double x) { return film(u, x, r); }, w, 1, 4, 1e-3 * w);
    const double dh_dr = oracles::central_difference([&](double x) { return film(u, w, x); }, r, 1, 4, 1e-3 * r);
    INFO("u_e " << u);
    CHECK_REL(h.d[0], dh_du, tol::kCentral8Step1e3Rel);
    CHECK_REL(h.d[1], dh_dw, tol::kCentral8Step1e3Rel);
    CHECK_REL(h.d[2], dh_dr, tol::kCentral8Step1e3Rel);
    // and in closed form: d ln h = 0.70 du/u - 0.13 dw/w + 0.43 dr/r
    CHECK_REL(h.d[0], 0.70 * h.v / u, tol::kPowerLawRel);
    CHECK_REL(h.d[1], -0.13 * h.v / w, tol::kPowerLawRel);
    CHECK_REL(h.d[2], 0.43 * h.v / r, tol::kPowerLawRel);
  }
  // no entrainment: zero film, its unbounded derivative reported as 0
  Dual<1> zero(0.0);
  zero.d = {1.0};
  const Dual<1> h0 = dynamics::dowson_higginson_film_m(zero, Dual<1>(1e5), Dual<1>(8e-3), kProps);
  CHECK(h0.v == 0.0);
  CHECK(h0.d[0] == 0.0);
}

TEST_CASE("ehl: a rigid-model contact in its units: N over mm, 1/mm curvature, mm per cam rad", "[dynamics][ehl]") {
  // 900 N over 9 mm, 1/R = 1/8 mm, entrainment 40 mm/rad at 100 rad/s = 4 m/s
  const OilSpec o = oil();
  const auto h = dynamics::line_contact_film_um(900, 9, kEStar, 1.0 / 8, 40, 100, o);
  REQUIRE(h);
  CHECK_REL(*h, reference_film_m(4.0, 1e5, 8e-3, 9.1e-3, 15.8e-9, 2 * 210e9 / (2 * 0.91)) * 1e6,
            tol::kRearrangedLawRel);
  // no film: a separated or tensile contact, conforming surfaces
  CHECK_FALSE(dynamics::line_contact_film_um(0, 9, kEStar, 1.0 / 8, 40, 100, o));
  CHECK_FALSE(dynamics::line_contact_film_um(-5, 9, kEStar, 1.0 / 8, 40, 100, o));
  CHECK_FALSE(dynamics::line_contact_film_um(900, 9, kEStar, 0.0, 40, 100, o));
  CHECK_FALSE(dynamics::line_contact_film_um(900, 9, kEStar, -0.01, 40, 100, o));
  // a film that exists but is not entrained
  CHECK(*dynamics::line_contact_film_um(900, 9, kEStar, 1.0 / 8, 0, 100, o) == 0.0);
}

TEST_CASE("ehl: a load, radius, property or roughness that is not positive is an input error", "[dynamics][ehl][input]") {
  CHECK_THROWS_AS(dynamics::dowson_higginson_film_m(1.0, 0.0, 0.01, kProps), camopt::InputError);
  CHECK_THROWS_WITH(dynamics::dowson_higginson_film_m(1.0, -5.0, 0.01, kProps),
                    Catch::Contains("dowson_higginson_film_m: load_N_per_m = -5 must be > 0"));
  CHECK_THROWS_WITH(dynamics::dowson_higginson_film_m(1.0, 1e5, 0.0, kProps),
                    Catch::Contains("dowson_higginson_film_m: reduced_radius_m = 0 must be > 0"));
  dynamics::EhlProperties bad = kProps;
  bad.viscosity_Pa_s = 0.0;
  CHECK_THROWS_WITH(dynamics::dowson_higginson_film_m(1.0, 1e5, 0.01, bad),
                    Catch::Contains("EhlProperties::viscosity_Pa_s = 0 must be > 0"));
  CHECK_THROWS_WITH(dynamics::film_lambda(1.0, 0.0), Catch::Contains("film_lambda: composite_roughness = 0 must be > 0"));
}
