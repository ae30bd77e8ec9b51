// lift laws: every law against its published closed form and peak coefficients, analytic
// derivatives against high-order finite differences, unit dwell-rise-dwell ends, and the
// polydyne relation between cam and valve lift.
//
// published values: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009),
// double-dwell functions (formulas and the coefficients C_v, C_a, C_j); the same values
// are tabulated in H. A. Rothbart, Cam Design Handbook (2004).
#include "synthesis/lift_law_test_support.hpp"

using namespace camopt::lift_law_test;

// ---- laws against the published closed forms ---------------------------------------------

TEST_CASE("each law matches its published closed form in physical units", "[synthesis][lift_law]") {
  struct Case {
    std::shared_ptr<const RiseLaw> law;
    std::function<Motion(double)> reference;
  };
  const std::vector<Case> cases = {
      {std::make_shared<Polynomial345>(kH, kBeta), ref_345},
      {std::make_shared<Polynomial4567>(kH, kBeta), ref_4567},
      {std::make_shared<Cycloidal>(kH, kBeta), ref_cycloidal},
      {std::make_shared<ModifiedSine>(kH, kBeta), ref_modified_sine},
      {std::make_shared<Polydyne>(kH, kBeta, kPolydyneK),
       [](double x) {
         const auto p = ref_polydyne_valve(x);
         // cam lift y = p + K p''
         return Motion{p[0] + kPolydyneK * p[2], p[1] + kPolydyneK * p[3], p[2] + kPolydyneK * p[4],
                       p[3] + kPolydyneK * p[5]};
       }},
  };
  for (const auto& c : cases) {
    INFO("law " << to_string(c.law->kind()));
    for (int k = 0; k <= 3; ++k) {
      const double scale = kH / std::pow(kBeta, k);
      const double peak = unit_peak(c.reference, k, 2000) * scale;
      for (double x : {0.0, 0.03, 0.1, 0.125, 0.2, 0.25, 0.3, 0.4, 0.5, 0.61, 0.75, 0.875, 0.9, 0.97, 1.0}) {
        const double theta = x * kBeta;
        check_close(c.law->evaluate(theta)[k], scale * c.reference(x)[k], kLawClosedFormRel, peak,
                    "d^" + std::to_string(k) + " at x = " + std::to_string(x));
      }
    }
  }
}

TEST_CASE("cycloidal lift is h (theta/beta - sin(2 pi theta/beta) / 2 pi)", "[synthesis][lift_law]") {
  const Cycloidal law(kH, kBeta);
  for (double theta : {0.0, 5.0, 14.25, 28.5, 40.0, 57.0}) {
    const double expected = kH * (theta / kBeta - std::sin(2 * pi * theta / kBeta) / (2 * pi));
    check_close(law.evaluate(theta).lift, expected, kLawClosedFormRel, kH, "lift at " + std::to_string(theta));
  }
  // before and after the rise: dwell at 0 and at h
  CHECK(law.evaluate(-3.0).lift == 0.0);
  CHECK(law.evaluate(60.0).lift == kH);
  CHECK(law.evaluate(60.0).vel == 0.0);
}

TEST_CASE("modified trapezoid matches norton's published segment formulas", "[synthesis][lift_law]") {
  const ModifiedTrapezoid law(1.0, 1.0);
  for (int i = 0; i <= 400; ++i) {
    const double x = i / 400.0;
    check_close(law.unit(x).lift, norton_modified_trapezoid(x), kNortonDecimalsAbs, 1.0,
                "lift at x = " + std::to_string(x));
    check_close(law.unit(x).acc, ref_modified_trapezoid_acc(x), kLawClosedFormRel, 8 * pi / (2 + pi),
                "acceleration at x = " + std::to_string(x));
  }
  // symmetric: half the rise at mid-stroke
  check_close(law.unit(0.5).lift, 0.5, kLawIdentityRel, 1.0, "y(1/2)");
}

TEST_CASE("peak coefficients match the published C_v, C_a, C_j", "[synthesis][lift_law]") {
  struct Case {
    std::shared_ptr<const RiseLaw> law;
    double cv, ca, cj;  // published (4-5 digits)
    double ca_exact;    // exact where known, else 0
  };
  const std::vector<Case> cases = {
      {std::make_shared<Polynomial345>(1.0, 1.0), 1.875, 5.7735, 60.0, 10.0 * std::sqrt(3.0) / 3.0},
      {std::make_shared<Polynomial4567>(1.0, 1.0), 2.1875, 7.5132, 52.5, 0.0},
      {std::make_shared<Cycloidal>(1.0, 1.0), 2.0, 6.2832, 39.478, 2.0 * pi},
      {std::make_shared<ModifiedTrapezoid>(1.0, 1.0), 2.0, 4.8881, 61.426, 8.0 * pi / (2.0 + pi)},
      {std::make_shared<ModifiedSine>(1.0, 1.0), 1.7596, 5.5280, 69.466, 4.0 * pi * pi / (4.0 + pi)},
  };
  for (const auto& c : cases) {
    INFO("law " << to_string(c.law->kind()));
    auto f = [&](double x) { return c.law->unit(x); };
    const double cv = unit_peak(f, 1), ca = unit_peak(f, 2), cj = unit_peak(f, 3);
    check_close(cv, c.cv, kPublishedCoefAbs, 1.0, "C_v");
    check_close(ca, c.ca, kPublishedCoefAbs, 1.0, "C_a");
    check_close(cj, c.cj, kPrinted3DecimalsAbs, 1.0, "C_j");
    if (c.ca_exact > 0) check_close(ca, c.ca_exact, kSampledPeakRel, c.ca_exact, "C_a exact");
  }
  CHECK_REL(ModifiedTrapezoid::peak_acceleration_coefficient(), 8.0 * pi / (2.0 + pi), kCoefTwoFormsRel);
  CHECK_REL(ModifiedSine::peak_acceleration_coefficient(), 4.0 * pi * pi / (4.0 + pi), kCoefTwoFormsRel);
}

TEST_CASE("every law is a unit dwell-rise-dwell with zero velocity and acceleration at both ends",
          "[synthesis][lift_law]") {
  for (const auto& law : all_laws()) {
    INFO("law " << to_string(law->kind()));
    const auto f = [&](double x) { return law->unit(x); };
    check_close(law->unit(0.0).lift, 0.0, kLawIdentityRel, 1.0, "y(0)");
    check_close(law->unit(1.0).lift, 1.0, kLawIdentityRel, 1.0, "y(1)");
    for (int k = 1; k <= 3; ++k) {
      const double peak = unit_peak(f, k, 20000);
      if (k > law->zero_order_at_ends()) {
        // the law promises nothing here; the step into a dwell is finite
        CHECK(std::isfinite(law->unit(0.0)[k]));
        continue;
      }
      check_close(law->unit(0.0)[k], 0.0, kLawIdentityRel, peak, "y^(" + std::to_string(k) + ")(0)");
      check_close(law->unit(1.0)[k], 0.0, kLawIdentityRel, peak, "y^(" + std::to_string(k) + ")(1)");
    }
  }
}

TEST_CASE("law derivatives agree with high-order finite differences", "[synthesis][lift_law]") {
  constexpr int kHalfWidth = 4;   // 8th-order stencils
  constexpr double kStep = 0.02;  // [cam deg]
  for (const auto& law : all_laws()) {
    INFO("law " << to_string(law->kind()));
    std::vector<double> breaks;
    for (double b : law->breakpoints()) breaks.push_back(b * kBeta);
    double peak[4] = {};
    for (int i = 0; i <= 4000; ++i)
      for (int k = 0; k <= 3; ++k) peak[k] = std::max(peak[k], std::abs(law->evaluate(kBeta * i / 4000.0)[k]));
    for (int i = 1; i < 200; ++i) {
      const double theta = kBeta * i / 200.0;
      bool near_break = false;
      for (double b : breaks) near_break |= std::abs(theta - b) < (kHalfWidth + 1) * kStep;
      if (near_break) continue;  // a stencil across a segment join measures the jump
      const Motion m = law->evaluate(theta);
      for (int k = 1; k <= 3; ++k) {
        // d^k from the first difference of d^(k-1)
        const double fd = camopt::oracles::central_difference(
            [&](double t) { return law->evaluate(t)[k - 1]; }, theta, 1, kHalfWidth, kStep);
        check_close(m[k], fd, kLawFdRel, peak[k], "d^" + std::to_string(k) + " at " + std::to_string(theta) + " deg");
      }
    }
  }
}

// ---- polydyne -------------------------------------------------------------------------

TEST_CASE("polydyne: cam lift = valve lift + (m/k) valve acceleration at the design speed",
          "[synthesis][lift_law][polydyne]") {
  const double rpm = 6000.0, fn = 1000.0, beta = 60.0;  // [rpm crank], [Hz], [cam deg]
  const double k = Polydyne::dynamic_factor(rpm, fn, beta);
  // omega_cam = 3000 rpm = 100 pi rad/s; omega_n = 2000 pi rad/s; beta = pi/3 rad
  const double expected = std::pow(100.0 * pi / (2000.0 * pi * pi / 3.0), 2);
  check_close(k, expected, kLawIdentityRel, expected, "K");

  const double h = 8.0;
  const Polydyne law(h, beta, k);
  const double omega_cam = 100.0 * pi, omega_n = 2000.0 * pi;  // [rad/s]
  const double m_over_k = 1.0 / (omega_n * omega_n);           // [s^2]
  for (double x : {0.1, 0.3, 0.5, 0.7, 0.95}) {
    // valve y(t) = h p(x(t)), x = omega_cam t / beta_rad: yddot = h p'' (omega_cam / beta_rad)^2
    const auto p = ref_polydyne_valve(x);
    const double beta_rad = beta * pi / 180.0;
    const double y = h * p[0];
    const double yddot = h * p[2] * std::pow(omega_cam / beta_rad, 2);  // [mm/s^2]
    check_close(law.evaluate(x * beta).lift, y + m_over_k * yddot, kLawIdentityRel, h, "cam lift at x = " + std::to_string(x));
    check_close(law.valve_motion(x).lift, p[0], kLawIdentityRel, 1.0, "valve motion");
  }
  // K = 0 is the plain 5-6-7-8-9 polynomial, with zero jerk at the ends
  const Polydyne rigid(h, beta, 0.0);
  CHECK(rigid.zero_order_at_ends() == 3);
  CHECK(rigid.unit(0.0).jerk == 0.0);
  CHECK_THROWS_AS(Polydyne(h, beta, -1.0), InputError);
}
