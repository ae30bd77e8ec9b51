// the Hertz line contact (hertz.hpp): pressure and half-width against a hand computation,
// the approach law against an independent fixed point with its stiffness and energy as its
// derivative and integral, and Hunt-Crossley damping's restitution against an RK4 impact
#include <catch2/catch.hpp>

#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/model.hpp"
#include "dynamics/dynamics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using camopt::dyn_test::hertz_force_fixed_point;
namespace tol = camopt::test::tol;

namespace {

// one impact of a mass [kg] at speed v [mm/s] on a Hunt-Crossley line contact, integrated by RK4
// (dt 1e-8 s, ~3600 steps per contact): the rebound speed over the impact speed
double hunt_crossley_rebound(double mass_kg, double v, double alpha, double e_star) {
  const double m = mass_kg * 1e-3;  // N per mm/s^2
  auto acc = [&](double x, double xd) {
    return -dynamics::hunt_crossley_force(dynamics::line_contact_force(x, 10, e_star, 5), xd, alpha) / m;
  };
  double x = 0, xd = v;
  const double dt = 1e-8;
  for (int i = 0; i < 1000000; ++i) {
    const double a1 = acc(x, xd), x2 = x + 0.5 * dt * xd, v2 = xd + 0.5 * dt * a1;
    const double a2 = acc(x2, v2), x3 = x + 0.5 * dt * v2, v3 = xd + 0.5 * dt * a2;
    const double a3 = acc(x3, v3), x4 = x + dt * v3, v4 = xd + dt * a3;
    const double a4 = acc(x4, v4);
    x += dt / 6 * (xd + 2 * v2 + 2 * v3 + v4);
    xd += dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    if (x <= 0 && i > 2) return -xd / v;
  }
  return -1;
}

}  // namespace

TEST_CASE("rigid (a): Hertz line contact against a hand computation", "[dynamics][hertz]") {
  // steel on steel: E* = 210000 / (2 (1 - 0.3^2)) = 115384.6 MPa; F = 1000 N over L = 10 mm,
  // R 20 mm on a flat: p0 = sqrt(100 * 115384.6 / (pi 20)) = 428.533 MPa,
  // b = sqrt(4 * 100 * 20 / (pi 115384.6)) = 0.148558 mm (Johnson 1985, eqs. 4.43-4.45)
  const double e_star = dynamics::contact_modulus(210000, 0.3, 210000, 0.3);
  CHECK_REL(e_star, 115384.615, tol::kPrinted9DigitsRel);
  const auto h = dynamics::hertz_line(1000, 10, e_star, 1.0 / 20);
  CHECK_REL(h.max_pressure, 428.5327513, tol::kPrinted10DigitsRel);
  CHECK_REL(h.half_width, 0.1485580205, tol::kPrinted10DigitsRel);
  // the elliptical pressure carries the load: F / L = pi p0 b / 2
  CHECK_REL(camopt::pi * h.max_pressure * h.half_width / 2, 100.0, tol::kRearrangedLawRel);
  // a convex roller r 8 on a concave flank of radius 20: 1/R* = 1/8 - 1/20
  const auto k = dynamics::hertz_line(1000, 10, e_star, 1.0 / 8 - 1.0 / 20);
  CHECK_REL(k.max_pressure, std::sqrt(100 * e_star * (1.0 / 8 - 1.0 / 20) / camopt::pi), tol::kRearrangedLawRel);
  // tension or conforming surfaces: no Hertz pressure
  CHECK(dynamics::hertz_line(-5, 10, e_star, 0.1).max_pressure == 0.0);
  CHECK(dynamics::hertz_line(5, 10, e_star, -0.01).max_pressure == 0.0);
}

TEST_CASE("Hertz line law: force and approach are inverse, stiffness and energy are its derivative / integral") {
  const double e_star = dynamics::contact_modulus(210e3, 0.3, 210e3, 0.3);
  for (double f : {1.0, 100.0, 1000.0, 20000.0}) {
    const double d = dynamics::line_contact_approach(f, 8, e_star, 12);
    CHECK_REL(dynamics::line_contact_force(d, 8, e_star, 12), f, tol::kRearrangedLawRel);
    CHECK_REL(hertz_force_fixed_point(d, 8, e_star, 12), f, tol::kHertzFixedPointRel);
    const double h = 1e-6 * f;
    const double kd = 2 * h / (dynamics::line_contact_approach(f + h, 8, e_star, 12) -
                               dynamics::line_contact_approach(f - h, 8, e_star, 12));
    CHECK_REL(dynamics::line_contact_tangent_stiffness(f, 8, e_star, 12), kd, tol::kCentral2Step1e6Rel);
    // dU/dF = F d(delta)/dF
    const double du = (dynamics::line_contact_energy(f + h, 8, e_star, 12) -
                       dynamics::line_contact_energy(f - h, 8, e_star, 12)) / (2 * h);
    CHECK_REL(du, f / kd, tol::kCentral2Step1e6Rel);
    // a warm start (the load length a = F / (pi L E*) of a nearby or far-off solution) gives
    // the cold start's force; a returns the solution
    const double a = f / (camopt::pi * 8 * e_star);
    for (double start : {a, a * (1 + 1e-6), a * 0.9, a * 3, a * 1e-6, a * 1e3, 1e9}) {
      double warm = start;
      INFO("F " << f << " N, start " << start / a << " a");
      CHECK_REL(dynamics::line_contact_force(d, 8, e_star, 12, warm), f, tol::kRearrangedLawRel);
      CHECK_REL(warm, a, tol::kRearrangedLawRel);
    }
  }
  double none = 1e-3;
  CHECK(dynamics::line_contact_force(-1e-3, 8, e_star, 12, none) == 0.0);
  CHECK(none == 0.0);
}

TEST_CASE("Hunt-Crossley contact damping: no force jump at touch-down, restitution e = 1 - alpha v") {
  const double e_star = dynamics::contact_modulus(210e3, 0.3, 210e3, 0.3);
  // the damping force vanishes with the elastic one (the linear c v law jumped by c v at touch-down)
  CHECK(dynamics::hunt_crossley_force(0.0, 1000.0, 1e-3) == 0.0);
  CHECK(dynamics::hunt_crossley_force(100.0, -1e4, 1e-3) == 0.0);  // no tension while parting fast
  CHECK_REL(dynamics::hunt_crossley_alpha(0.8, 500.0), 4e-4, tol::kUlpRel);
  // Hunt & Crossley 1975: e = 1 - alpha v to first order; the remainder is second order in alpha v
  for (const double alpha_v : {0.01, 0.05}) {
    const double v = 500.0;
    const double e = hunt_crossley_rebound(0.05, v, alpha_v / v, e_star);
    CHECK_ABS(e, 1 - alpha_v, tol::kRestitutionSecondOrder * alpha_v * alpha_v);
    CHECK(std::abs(e - (1 - alpha_v)) >= 0.5 * alpha_v * alpha_v);  // and it is there: not a kinematic identity
  }
}
