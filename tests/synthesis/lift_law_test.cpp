// lift laws and lift events: every law against its published closed form and peak
// coefficients, analytic derivatives against high-order finite differences, continuity at
// the ramp / flank / dwell joins, closure on the base circle, asymmetric events, the
// b-spline acceleration law's exact integration and closure, and input validation.
//
// published values: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009),
// double-dwell functions (formulas and the coefficients C_v, C_a, C_j); the same values
// are tabulated in H. A. Rothbart, Cam Design Handbook (2004).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/synthesis/lift_law.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "oracles/finite_difference.hpp"

namespace {

using namespace camopt::synthesis;
using camopt::InputError;

constexpr double pi = std::numbers::pi;

// named tolerances
constexpr double kClosedFormRel = 1e-12;   // law vs exact published formula, relative to the peak of d^k
constexpr double kNortonDecimalsAbs = 1e-6;  // vs norton's 8-digit decimal coefficients [unit rise]
constexpr double kPublishedCoefAbs = 6e-5;   // vs 4-5 digit published peak coefficients
constexpr double kExactCoefRel = 1e-9;       // sampled peak vs exact peak coefficient
constexpr double kFdRel = 1e-8;              // analytic vs 8th-order central differences, relative to peak
constexpr double kExactRel = 1e-12;          // identities that hold to rounding
constexpr double kJoinEps = 1e-7;            // one-sided offset at a join [cam deg]
constexpr std::uint32_t kSeed = 20240611;

// peak of |d^k| of a unit rise over a fine grid
double unit_peak(const std::function<Motion(double)>& f, int k, int samples = 200000) {
  double peak = 0.0;
  for (int i = 0; i <= samples; ++i) peak = std::max(peak, std::abs(f(static_cast<double>(i) / samples)[k]));
  return peak;
}

// ---- published closed forms (written out independently of the library) -----------------

Motion ref_345(double x) {
  return {10 * std::pow(x, 3) - 15 * std::pow(x, 4) + 6 * std::pow(x, 5),
          30 * x * x - 60 * std::pow(x, 3) + 30 * std::pow(x, 4), 60 * x - 180 * x * x + 120 * std::pow(x, 3),
          60 - 360 * x + 360 * x * x};
}

Motion ref_4567(double x) {
  return {35 * std::pow(x, 4) - 84 * std::pow(x, 5) + 70 * std::pow(x, 6) - 20 * std::pow(x, 7),
          140 * std::pow(x, 3) - 420 * std::pow(x, 4) + 420 * std::pow(x, 5) - 140 * std::pow(x, 6),
          420 * x * x - 1680 * std::pow(x, 3) + 2100 * std::pow(x, 4) - 840 * std::pow(x, 5),
          840 * x - 5040 * x * x + 8400 * std::pow(x, 3) - 4200 * std::pow(x, 4)};
}

// s = h (x - sin(2 pi x) / (2 pi))
Motion ref_cycloidal(double x) {
  return {x - std::sin(2 * pi * x) / (2 * pi), 1 - std::cos(2 * pi * x), 2 * pi * std::sin(2 * pi * x),
          4 * pi * pi * std::cos(2 * pi * x)};
}

// norton's modified sine, exact form: C = 4 pi^2 / (4 + pi)
Motion ref_modified_sine(double x) {
  const double d = 4 + pi;
  if (x <= 0.125 || x >= 0.875) {
    const double c0 = x <= 0.125 ? 0.0 : 4.0 / d;
    return {c0 + pi * x / d - std::sin(4 * pi * x) / (4 * d), pi / d * (1 - std::cos(4 * pi * x)),
            4 * pi * pi / d * std::sin(4 * pi * x), 16 * pi * pi * pi / d * std::cos(4 * pi * x)};
  }
  const double a = pi * (1 + 4 * x) / 3;
  return {2 / d + pi * x / d - 9 / (4 * d) * std::sin(a), pi / d * (1 - 3 * std::cos(a)), 4 * pi * pi / d * std::sin(a),
          16 * pi * pi * pi / (3 * d) * std::cos(a)};
}

// norton's modified trapezoid lift, with his published 8-digit coefficients
double norton_modified_trapezoid(double x) {
  if (x <= 0.125) return 0.38898448 * (x - std::sin(4 * pi * x) / (4 * pi));
  if (x <= 0.375) return 2.44406184 * x * x - 0.22203097 * x + 0.00723407;
  if (x <= 0.625) return 1.6110154 * x - 0.0309544 * std::sin(4 * pi * x - pi) - 0.3055077;
  if (x <= 0.875) return 4.6660917 * x - 2.44406184 * x * x - 1.2292648;
  return 0.6110154 + 0.3889845 * x + 0.0309544 * std::sin(4 * pi * x - 3 * pi);
}

// modified trapezoid, exact form: C = 8 pi / (2 + pi), acceleration by segments
double ref_modified_trapezoid_acc(double x) {
  const double c = 8 * pi / (2 + pi);
  if (x <= 0.125) return c * std::sin(4 * pi * x);
  if (x <= 0.375) return c;
  if (x <= 0.625) return c * std::cos(4 * pi * (x - 0.375));
  if (x <= 0.875) return -c;
  return -c * std::cos(4 * pi * (x - 0.875));
}

// 5-6-7-8-9 polynomial and its derivatives up to 5
std::array<double, 6> ref_polydyne_valve(double x) {
  auto p = [](double v, int e) { return std::pow(v, e); };
  return {126 * p(x, 5) - 420 * p(x, 6) + 540 * p(x, 7) - 315 * p(x, 8) + 70 * p(x, 9),
          630 * p(x, 4) - 2520 * p(x, 5) + 3780 * p(x, 6) - 2520 * p(x, 7) + 630 * p(x, 8),
          2520 * p(x, 3) - 12600 * p(x, 4) + 22680 * p(x, 5) - 17640 * p(x, 6) + 5040 * p(x, 7),
          7560 * p(x, 2) - 50400 * p(x, 3) + 113400 * p(x, 4) - 105840 * p(x, 5) + 35280 * p(x, 6),
          15120 * x - 151200 * p(x, 2) + 453600 * p(x, 3) - 529200 * p(x, 4) + 211680 * p(x, 5),
          15120 - 302400 * x + 1360800 * p(x, 2) - 2116800 * p(x, 3) + 1058400 * p(x, 4)};
}

// one law of each kind with a physical height and duration
constexpr double kH = 9.5;      // [mm]
constexpr double kBeta = 57.0;  // [cam deg]
constexpr double kPolydyneK = 0.0023;

// a closed acceleration shape over 8 spans (positive pulse, long negative region)
const std::vector<double> kBsplineShape = {0.0, 1.5, 3.0, 2.0, 0.2, -1.0, -1.2, -1.0, -0.6, -0.2, 0.0};

std::vector<std::shared_ptr<const RiseLaw>> all_laws() {
  return {std::make_shared<Polynomial345>(kH, kBeta),     std::make_shared<Polynomial4567>(kH, kBeta),
          std::make_shared<Cycloidal>(kH, kBeta),         std::make_shared<ModifiedTrapezoid>(kH, kBeta),
          std::make_shared<ModifiedSine>(kH, kBeta),      std::make_shared<Polydyne>(kH, kBeta, kPolydyneK),
          std::make_shared<BSplineAcceleration>(kH, kBeta, kBsplineShape, 3)};
}

// |a - b| <= tol * scale, reported with context
void check_close(double a, double b, double tol, double scale, const std::string& what) {
  INFO(what << ": " << a << " vs " << b << " (|diff| " << std::abs(a - b) << ", allowed " << tol * scale << ")");
  CHECK(std::abs(a - b) <= tol * scale);
}

}  // namespace

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
        check_close(c.law->evaluate(theta)[k], scale * c.reference(x)[k], kClosedFormRel, peak,
                    "d^" + std::to_string(k) + " at x = " + std::to_string(x));
      }
    }
  }
}

TEST_CASE("cycloidal lift is h (theta/beta - sin(2 pi theta/beta) / 2 pi)", "[synthesis][lift_law]") {
  const Cycloidal law(kH, kBeta);
  for (double theta : {0.0, 5.0, 14.25, 28.5, 40.0, 57.0}) {
    const double expected = kH * (theta / kBeta - std::sin(2 * pi * theta / kBeta) / (2 * pi));
    check_close(law.evaluate(theta).lift, expected, kClosedFormRel, kH, "lift at " + std::to_string(theta));
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
    check_close(law.unit(x).acc, ref_modified_trapezoid_acc(x), kClosedFormRel, 8 * pi / (2 + pi),
                "acceleration at x = " + std::to_string(x));
  }
  // symmetric: half the rise at mid-stroke
  check_close(law.unit(0.5).lift, 0.5, kExactRel, 1.0, "y(1/2)");
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
    check_close(cj, c.cj, 1e-3, 1.0, "C_j");  // published to 3 decimals
    if (c.ca_exact > 0) check_close(ca, c.ca_exact, kExactCoefRel, c.ca_exact, "C_a exact");
  }
  CHECK(ModifiedTrapezoid::peak_acceleration_coefficient() == Approx(8.0 * pi / (2.0 + pi)).epsilon(1e-14));
  CHECK(ModifiedSine::peak_acceleration_coefficient() == Approx(4.0 * pi * pi / (4.0 + pi)).epsilon(1e-14));
}

TEST_CASE("every law is a unit dwell-rise-dwell with zero velocity and acceleration at both ends",
          "[synthesis][lift_law]") {
  for (const auto& law : all_laws()) {
    INFO("law " << to_string(law->kind()));
    const auto f = [&](double x) { return law->unit(x); };
    check_close(law->unit(0.0).lift, 0.0, kExactRel, 1.0, "y(0)");
    check_close(law->unit(1.0).lift, 1.0, kExactRel, 1.0, "y(1)");
    for (int k = 1; k <= 3; ++k) {
      const double peak = unit_peak(f, k, 20000);
      if (k > law->zero_order_at_ends()) {
        // the law promises nothing here; the step into a dwell is finite
        CHECK(std::isfinite(law->unit(0.0)[k]));
        continue;
      }
      check_close(law->unit(0.0)[k], 0.0, kExactRel, peak, "y^(" + std::to_string(k) + ")(0)");
      check_close(law->unit(1.0)[k], 0.0, kExactRel, peak, "y^(" + std::to_string(k) + ")(1)");
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
        check_close(m[k], fd, kFdRel, peak[k], "d^" + std::to_string(k) + " at " + std::to_string(theta) + " deg");
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
  check_close(k, expected, kExactRel, expected, "K");

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
    check_close(law.evaluate(x * beta).lift, y + m_over_k * yddot, kExactRel, h, "cam lift at x = " + std::to_string(x));
    check_close(law.valve_motion(x).lift, p[0], kExactRel, 1.0, "valve motion");
  }
  // K = 0 is the plain 5-6-7-8-9 polynomial, with zero jerk at the ends
  const Polydyne rigid(h, beta, 0.0);
  CHECK(rigid.zero_order_at_ends() == 3);
  CHECK(rigid.unit(0.0).jerk == 0.0);
  CHECK_THROWS_AS(Polydyne(h, beta, -1.0), InputError);
}

// ---- b-spline acceleration ------------------------------------------------------------

namespace {

// cox-de boor recursion for N_{i,p}(x) (independent of the library's de boor algorithm);
// the last non-empty span is closed on the right
double basis(const std::vector<double>& t, int i, int p, double x) {
  if (p == 0) {
    const double lo = t[static_cast<std::size_t>(i)], hi = t[static_cast<std::size_t>(i + 1)];
    if (lo < hi && x >= lo && (x < hi || (hi == t.back() && x == hi))) return 1.0;
    return 0.0;
  }
  double v = 0.0;
  const double d1 = t[static_cast<std::size_t>(i + p)] - t[static_cast<std::size_t>(i)];
  const double d2 = t[static_cast<std::size_t>(i + p + 1)] - t[static_cast<std::size_t>(i + 1)];
  if (d1 > 0) v += (x - t[static_cast<std::size_t>(i)]) / d1 * basis(t, i, p - 1, x);
  if (d2 > 0) v += (t[static_cast<std::size_t>(i + p + 1)] - x) / d2 * basis(t, i + 1, p - 1, x);
  return v;
}

double spline_by_basis(const std::vector<double>& t, const std::vector<double>& c, int p, double x) {
  double s = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) s += c[i] * basis(t, static_cast<int>(i), p, x);
  return s;
}

// 5-point gauss-legendre on [a, b]: exact for polynomials of degree <= 9
double gauss_legendre(const std::function<double(double)>& f, double a, double b) {
  static const double xg[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
  static const double wg[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  double s = 0.0;
  for (int i = 0; i < 5; ++i) s += wg[i] * f(0.5 * (a + b) + 0.5 * (b - a) * xg[i]);
  return 0.5 * (b - a) * s;
}

// int_0^x g(t) w(t) dt, split at the knots so every piece is one polynomial
double integrate_by_spans(const std::vector<double>& knots, double x, const std::function<double(double)>& g) {
  double s = 0.0, a = 0.0;
  std::vector<double> cuts;
  for (double k : knots)
    if (k > 0.0 && k < x) cuts.push_back(k);
  cuts.push_back(x);
  for (double b : cuts) {
    if (b > a) s += gauss_legendre(g, a, b);
    a = b;
  }
  return s;
}

// bernstein coefficients of sum_j a_j x^j (degree n): b_k = sum_{j<=k} C(k,j)/C(n,j) a_j
std::vector<double> bernstein(const std::vector<double>& a) {
  const int n = static_cast<int>(a.size()) - 1;
  auto binom = [](int n_, int k_) {
    double r = 1.0;
    for (int i = 1; i <= k_; ++i) r = r * (n_ - k_ + i) / i;
    return r;
  };
  std::vector<double> b(a.size(), 0.0);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= k; ++j) b[static_cast<std::size_t>(k)] += binom(k, j) / binom(n, j) * a[static_cast<std::size_t>(j)];
  return b;
}

}  // namespace

TEST_CASE("b-spline acceleration reproduces the polynomial laws exactly", "[synthesis][lift_law][bspline]") {
  // 3-4-5: y'' = 60 x - 180 x^2 + 120 x^3 = cubic bezier with controls 0, 20, -20, 0
  const Polynomial345 p345(kH, kBeta);
  for (const std::vector<double>& controls : {std::vector<double>{0, 20, -20, 0}, std::vector<double>{0, 1, -1, 0}}) {
    const BSplineAcceleration law(kH, kBeta, controls, 3);
    CHECK(law.closure_change() <= 1e-15);
    for (int i = 0; i <= 50; ++i) {
      const double theta = kBeta * i / 50.0;
      for (int k = 0; k <= 3; ++k)
        check_close(law.evaluate(theta)[k], p345.evaluate(theta)[k], kExactRel, kH / std::pow(kBeta, k) * 60.0,
                    "3-4-5 d^" + std::to_string(k) + " at " + std::to_string(theta));
    }
  }
  // 4-5-6-7: y'' = 420 x^2 - 1680 x^3 + 2100 x^4 - 840 x^5, a quintic bezier
  const std::vector<double> c4567 = bernstein({0, 0, 420, -1680, 2100, -840});
  const BSplineAcceleration law(kH, kBeta, c4567, 5);
  const Polynomial4567 p4567(kH, kBeta);
  CHECK(law.closure_change() <= 1e-14);
  for (int i = 0; i <= 50; ++i) {
    const double theta = kBeta * i / 50.0;
    for (int k = 0; k <= 3; ++k)
      check_close(law.evaluate(theta)[k], p4567.evaluate(theta)[k], kExactRel, kH / std::pow(kBeta, k) * 60.0,
                  "4-5-6-7 d^" + std::to_string(k) + " at " + std::to_string(theta));
  }
}

TEST_CASE("b-spline acceleration: exact double integral, closure by the least change", "[synthesis][lift_law][bspline]") {
  std::mt19937 gen(kSeed);
  auto unit = [&] { return 2.0 * (gen() / 4294967296.0) - 1.0; };
  for (int degree = 2; degree <= 5; ++degree) {
    // a rising shape with noise, 13 values: positive pulse then a negative region
    std::vector<double> given;
    for (int i = 0; i < 13; ++i) given.push_back(std::sin(2 * pi * i / 12.0) + 0.3 * unit() + 0.5);
    INFO("degree " << degree);
    const BSplineAcceleration law(1.0, 1.0, given, degree);
    const auto& t = law.knots();
    const auto& c = law.controls();

    // acceleration is the b-spline of the closed, scaled controls (cox-de boor)
    for (int i = 0; i <= 100; ++i) {
      const double x = i / 100.0;
      check_close(law.unit(x).acc, spline_by_basis(t, c, degree, x), kExactRel, 10.0, "acc at " + std::to_string(x));
    }
    // velocity and lift are its exact first and second integrals
    for (int i = 1; i <= 40; ++i) {
      const double x = i / 40.0 - 0.0123 * (i % 3);
      const auto acc = [&](double s) { return spline_by_basis(t, c, degree, s); };
      const double vel = integrate_by_spans(t, x, acc);
      const double lift = integrate_by_spans(t, x, [&](double s) { return (x - s) * acc(s); });
      check_close(law.unit(x).vel, vel, kExactRel, 10.0, "vel at " + std::to_string(x));
      check_close(law.unit(x).lift, lift, kExactRel, 10.0, "lift at " + std::to_string(x));
    }
    // closure: zero acceleration at both ends, zero velocity and unit lift at the end
    CHECK(c.front() == 0.0);
    CHECK(c.back() == 0.0);
    check_close(law.unit(1.0).vel, 0.0, kExactRel, 1.0, "y'(1)");
    check_close(law.unit(1.0).lift, 1.0, kExactRel, 1.0, "y(1)");
    // least change: the change lies in the span of the constraint rows e_0, e_{n-1}, w,
    // so inside the interior it is proportional to w_i = int N_i
    const std::size_t n = given.size();
    std::vector<double> ratio;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double w = (t[i + static_cast<std::size_t>(degree) + 1] - t[i]) / (degree + 1);
      ratio.push_back((c[i] / law.shape_scale() - given[i]) / w);
    }
    for (double r : ratio) check_close(r, ratio.front(), 1e-10, std::abs(ratio.front()) + 1.0, "change / w_i");
    CHECK(law.closure_change() > 0.0);
  }
}

TEST_CASE("b-spline acceleration rejects shapes that cannot make a rise", "[synthesis][lift_law][bspline]") {
  using Catch::Matchers::Contains;
  // negative first: the closed shape falls
  CHECK_THROWS_WITH(BSplineAcceleration(1.0, 1.0, std::vector<double>{0, -1, 1, 0}, 3), Contains("net rise"));
  CHECK_THROWS_WITH(BSplineAcceleration(1.0, 1.0, std::vector<double>{0, 0, 0, 0, 0}, 3), Contains("net rise"));
  CHECK_THROWS_WITH(BSplineAcceleration(1.0, 1.0, std::vector<double>{0, 1, 0}, 2), Contains("at least 4"));
  CHECK_THROWS_WITH(BSplineAcceleration(1.0, 1.0, std::vector<double>{0, 1, -1, 0}, 6), Contains("bspline_degree"));
  CHECK_THROWS_WITH(BSplineAcceleration(1.0, 1.0, std::vector<double>{0, 1, NAN, -1, 0}, 3), Contains("finite"));
}

// ---- lift events ------------------------------------------------------------------------

namespace {

// an asymmetric event with ramps and a dwell, wrapped around 0 cam deg
LiftEventSpec asymmetric_spec() {
  LiftEventSpec s;
  s.max_lift_mm = 9.5;
  s.peak_deg = 40.0;  // start = 40 - 3 - 72 = -35 -> 325: the event wraps through 0
  s.dwell_deg = 6.0;
  s.ramp_blend = 0.5;
  s.opening = {LawKind::polynomial_345, 72.0, 0.25, 22.0, {}, 3};
  s.closing = {LawKind::modified_sine, 64.0, 0.18, 18.0, {}, 3};
  return s;
}

std::vector<LiftEventSpec> event_variants() {
  std::vector<LiftEventSpec> v;
  for (LawKind law : kAllLaws) {
    LiftEventSpec s = asymmetric_spec();
    s.opening.law = law;
    s.closing.law = law == LawKind::cycloidal ? LawKind::polynomial_4567 : LawKind::cycloidal;
    if (law == LawKind::bspline) s.opening.acc_controls = kBsplineShape;
    if (law == LawKind::polydyne) {
      s.polydyne_engine_rpm = 6000.0;
      s.polydyne_natural_hz = 900.0;
    }
    v.push_back(s);
  }
  LiftEventSpec no_ramp_no_dwell = asymmetric_spec();
  no_ramp_no_dwell.opening.ramp_height_mm = no_ramp_no_dwell.opening.ramp_length_deg = 0.0;
  no_ramp_no_dwell.closing.ramp_height_mm = no_ramp_no_dwell.closing.ramp_length_deg = 0.0;
  no_ramp_no_dwell.dwell_deg = 0.0;
  v.push_back(no_ramp_no_dwell);
  return v;
}

std::string describe(const LiftEventSpec& s) {
  return std::string(to_string(s.opening.law)) + " / " + to_string(s.closing.law) + ", ramps " +
         std::to_string(s.opening.ramp_height_mm) + " / " + std::to_string(s.closing.ramp_height_mm) + " mm, dwell " +
         std::to_string(s.dwell_deg);
}

std::array<double, 4> event_peaks(const LiftEvent& ev) {
  std::array<double, 4> peak{};
  for (int i = 0; i < 36000; ++i)
    for (int k = 0; k <= 3; ++k) peak[static_cast<std::size_t>(k)] = std::max(peak[static_cast<std::size_t>(k)], std::abs(ev.evaluate(i * 0.01)[k]));
  return peak;
}

}  // namespace

TEST_CASE("event: lift, velocity and acceleration are continuous at every join", "[synthesis][lift_event]") {
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const auto peak = event_peaks(ev);
    const EventJoins j = ev.joins();
    const std::vector<std::pair<const char*, double>> joins = {
        {"base circle -> opening", j.opening_start},   {"velocity blend -> ramp", j.opening_blend_end},
        {"ramp -> opening flank", j.opening_ramp_end}, {"opening flank -> dwell", j.max_lift_start},
        {"dwell -> closing flank", j.max_lift_end},    {"closing flank -> ramp", j.closing_ramp_start},
        {"ramp -> velocity blend", j.closing_blend_start}, {"closing -> base circle", j.closing_end}};
    for (const auto& [name, at] : joins) {
      INFO("join " << name << " at " << at << " cam deg");
      const Motion left = ev.evaluate(at - kJoinEps), right = ev.evaluate(at + kJoinEps);
      for (int k = 0; k <= 2; ++k) {
        // a continuous d^k changes by at most 2 eps max|d^(k+1)| across the join
        const double allowed = 2.0 * kJoinEps * peak[static_cast<std::size_t>(k + 1)] * 1.01 + 1e-13 * peak[static_cast<std::size_t>(k)];
        INFO("d^" << k << ": left " << left[k] << ", right " << right[k]);
        CHECK(std::abs(right[k] - left[k]) <= allowed);
      }
      CHECK(std::isfinite(left.jerk));
      CHECK(std::isfinite(right.jerk));
    }
  }
}

TEST_CASE("event: the jerk step at a join is what the laws promise", "[synthesis][lift_event]") {
  LiftEventSpec s = asymmetric_spec();
  const LiftEvent ev = LiftEvent::compile(s);
  const EventJoins j = ev.joins();
  auto jump = [&](double at) { return ev.evaluate(at + kJoinEps).jerk - ev.evaluate(at - kJoinEps).jerk; };
  const double jerk_scale = event_peaks(ev)[3];
  // cycloidal velocity blend: jerk continuous at the base circle and at the blend end
  CHECK(std::abs(jump(j.opening_start)) <= 1e-6 * jerk_scale);
  CHECK(std::abs(jump(j.opening_blend_end)) <= 1e-6 * jerk_scale);
  CHECK(std::abs(jump(j.closing_end)) <= 1e-6 * jerk_scale);
  // ramp -> 3-4-5 flank: the jerk steps (c2 join), finite
  CHECK(std::abs(jump(j.opening_ramp_end)) > 1e-3 * jerk_scale);
  // a 4-5-6-7 flank without ramp meets the base circle and the dwell with zero jerk (c3)
  s.opening = {LawKind::polynomial_4567, 72.0, 0.0, 0.0, {}, 3};
  const LiftEvent c3 = LiftEvent::compile(s);
  const EventJoins j3 = c3.joins();
  CHECK(std::abs(c3.evaluate(j3.opening_start + kJoinEps).jerk) <= 1e-6 * jerk_scale);
  CHECK(std::abs(c3.evaluate(j3.max_lift_start - kJoinEps).jerk) <= 1e-6 * jerk_scale);
}

TEST_CASE("event derivatives agree with high-order finite differences", "[synthesis][lift_event]") {
  constexpr int kHalfWidth = 4;
  constexpr double kStep = 0.02;  // [cam deg]
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const auto peak = event_peaks(ev);
    const EventJoins j = ev.joins();
    std::vector<double> avoid = {j.opening_start,      j.opening_blend_end,   j.opening_ramp_end,
                                 j.max_lift_start,     j.max_lift_end,        j.closing_ramp_start,
                                 j.closing_blend_start, j.closing_end};
    for (const auto* flank : {&ev.opening(), &ev.closing()}) {
      for (double b : flank->law().breakpoints()) {
        const double off = flank->ramp_length_deg() + b * flank->law().duration_deg();
        avoid.push_back(flank == &ev.opening() ? j.opening_start + off : j.closing_end - off);
      }
    }
    for (int i = 0; i < 720; ++i) {
      const double theta = j.opening_start + ev.length_deg() * (i + 0.37) / 720.0;
      bool near = false;
      for (double a : avoid) near |= std::abs(theta - a) < (kHalfWidth + 1) * kStep;
      if (near) continue;
      const Motion m = ev.evaluate(theta);
      for (int k = 1; k <= 3; ++k) {
        const double fd = camopt::oracles::central_difference([&](double t) { return ev.evaluate(t)[k - 1]; }, theta,
                                                              1, kHalfWidth, kStep);
        check_close(m[k], fd, kFdRel, peak[static_cast<std::size_t>(k)], "d^" + std::to_string(k) + " at " + std::to_string(theta));
      }
    }
  }
}

TEST_CASE("event closes on the base circle and repeats every 360 cam deg", "[synthesis][lift_event]") {
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const EventJoins j = ev.joins();
    CHECK(std::abs(ev.evaluate(j.opening_start).lift) <= 1e-15);
    CHECK(std::abs(ev.evaluate(j.closing_end).lift) <= 1e-15);
    // approaching the end of the closing ramp: lift and velocity go to zero
    const Motion end = ev.evaluate(j.closing_end - 1e-6);
    CHECK(std::abs(end.lift) <= 1e-12);
    CHECK(std::abs(end.vel) <= 1e-9);
    // the base circle is exactly zero
    for (double a = j.closing_end + 0.5; a < j.opening_start + 360.0; a += 0.5) {
      const Motion m = ev.evaluate(a);
      CHECK(m.lift == 0.0);
      CHECK(m.vel == 0.0);
      CHECK(m.acc == 0.0);
    }
    // max lift at the peak angle, with zero velocity
    CHECK(ev.evaluate(spec.peak_deg).lift == Approx(spec.max_lift_mm).epsilon(1e-14));
    CHECK(std::abs(ev.evaluate(spec.peak_deg).vel) <= 1e-14);
    // periodic, and the lift never exceeds the max lift nor goes negative
    for (int i = 0; i < 3600; ++i) {
      const double a = 0.1 * i;
      const Motion m = ev.evaluate(a), m2 = ev.evaluate(a + 360.0), m3 = ev.evaluate(a - 720.0);
      CHECK(m2.lift == Approx(m.lift).margin(1e-12));
      CHECK(m3.acc == Approx(m.acc).margin(1e-12));
      CHECK(m.lift >= -1e-15);
      CHECK(m.lift <= spec.max_lift_mm * (1 + 1e-14));
    }
  }
}

TEST_CASE("event ramps: constant velocity, the given height at the given length", "[synthesis][lift_event]") {
  const LiftEventSpec s = asymmetric_spec();
  const LiftEvent ev = LiftEvent::compile(s);
  const EventJoins j = ev.joins();
  // vr = Hr / (Lr (1 - b/2))
  const double vr_open = 0.25 / (22.0 * 0.75), vr_close = 0.18 / (18.0 * 0.75);
  check_close(ev.opening().ramp_velocity(), vr_open, kExactRel, vr_open, "opening ramp velocity");
  check_close(ev.closing().ramp_velocity(), vr_close, kExactRel, vr_close, "closing ramp velocity");
  check_close(ev.evaluate(j.opening_ramp_end).lift, 0.25, kExactRel, 1.0, "lift at the end of the opening ramp");
  check_close(ev.evaluate(j.closing_ramp_start).lift, 0.18, kExactRel, 1.0, "lift at the start of the closing ramp");
  for (double f : {0.55, 0.7, 0.9, 0.99}) {
    const Motion o = ev.evaluate(j.opening_start + f * 22.0);
    check_close(o.vel, vr_open, kExactRel, vr_open, "opening ramp velocity at " + std::to_string(f));
    CHECK(o.acc == 0.0);
    const Motion c = ev.evaluate(j.closing_end - f * 18.0);
    check_close(c.vel, -vr_close, kExactRel, vr_close, "closing ramp velocity at " + std::to_string(f));
  }
  // the main flank starts at the ramp velocity with zero acceleration
  const Motion start = ev.evaluate(j.opening_ramp_end);
  check_close(start.vel, vr_open, kExactRel, vr_open, "flank start velocity");
  CHECK(std::abs(start.acc) <= 1e-15);
}

TEST_CASE("asymmetric event: each side follows its own law and duration", "[synthesis][lift_event]") {
  LiftEventSpec s;
  s.max_lift_mm = 11.0;
  s.peak_deg = 200.0;
  s.dwell_deg = 4.0;
  s.opening = {LawKind::cycloidal, 75.0, 0.0, 0.0, {}, 3};
  s.closing = {LawKind::modified_trapezoid, 55.0, 0.0, 0.0, {}, 3};
  const LiftEvent ev = LiftEvent::compile(s);
  CHECK(ev.length_deg() == Approx(75.0 + 4.0 + 55.0));
  CHECK(ev.start_deg() == Approx(200.0 - 2.0 - 75.0));
  const ModifiedTrapezoid trap(1.0, 1.0);
  for (double phi : {1.0, 10.0, 30.0, 50.0, 70.0}) {
    // opening side: phi cam deg before the dwell
    const double xo = 1.0 - phi / 75.0;
    check_close(ev.evaluate(198.0 - phi).lift, 11.0 * ref_cycloidal(xo).lift, kExactRel, 11.0, "opening lift");
    check_close(ev.evaluate(198.0 - phi).acc, 11.0 / (75.0 * 75.0) * ref_cycloidal(xo).acc, kExactRel,
                11.0 / (75.0 * 75.0) * 2 * pi, "opening acceleration");
    if (phi < 55.0) {
      // closing side: phi cam deg after the dwell, mirrored (velocity and jerk change sign)
      const double xc = 1.0 - phi / 55.0;
      const Motion m = ev.evaluate(202.0 + phi);
      check_close(m.lift, 11.0 * trap.unit(xc).lift, kExactRel, 11.0, "closing lift");
      check_close(m.vel, -11.0 / 55.0 * trap.unit(xc).vel, kExactRel, 11.0 / 55.0 * 2.0, "closing velocity");
      check_close(m.acc, 11.0 / (55.0 * 55.0) * ref_modified_trapezoid_acc(xc), kExactRel, 11.0 / (55.0 * 55.0) * 5.0,
                  "closing acceleration");
    }
  }
  // dwell
  for (double a : {198.0, 199.0, 201.9}) CHECK(ev.evaluate(a).lift == 11.0);

  // durations at a lift level, against an independent bisection on the reference laws
  for (double level : {0.1, 1.0, 5.5, 10.9}) {
    auto solve = [&](const std::function<double(double)>& y) {
      double lo = 0.0, hi = 1.0;
      for (int i = 0; i < 200; ++i) (y(0.5 * (lo + hi)) < level / 11.0 ? lo : hi) = 0.5 * (lo + hi);
      return 0.5 * (lo + hi);
    };
    const double xo = solve([](double x) { return ref_cycloidal(x).lift; });
    const double xc = solve([](double x) { return norton_modified_trapezoid(x); });
    const double expected = 75.0 * (1 - xo) + 4.0 + 55.0 * (1 - xc);
    // norton's decimals are good to ~1e-7 in lift, i.e. ~1e-5 deg near the base
    CHECK(ev.duration_above(level) == Approx(expected).margin(2e-4));
  }
  CHECK(ev.duration_above(0.0) == Approx(134.0));
  CHECK(ev.duration_above(11.5) == 0.0);

  const LiftEventSummary sum = summarize(ev);
  CHECK(sum.max_lift_mm == 11.0);
  CHECK(sum.max_lift_at_deg == 200.0);
  CHECK(sum.event_deg == Approx(134.0));
  // peak accelerations: cycloidal 2 pi h / beta_o^2 (opening), modified trapezoid C_a h / beta_c^2
  CHECK(sum.max_acc == Approx(std::max(2 * pi * 11.0 / (75.0 * 75.0), 8 * pi / (2 + pi) * 11.0 / (55.0 * 55.0))).epsilon(1e-6));
  CHECK(sum.min_acc == Approx(-std::max(2 * pi * 11.0 / (75.0 * 75.0), 8 * pi / (2 + pi) * 11.0 / (55.0 * 55.0))).epsilon(1e-6));
}

// ---- validation ------------------------------------------------------------------------

TEST_CASE("event validation names the field, the value and the rule", "[synthesis][lift_event]") {
  using Catch::Matchers::Contains;
  struct Case {
    const char* what;
    std::function<void(LiftEventSpec&)> edit;
    std::vector<std::string> expect;  // substrings of the message
  };
  const std::vector<Case> cases = {
      {"negative lift", [](LiftEventSpec& s) { s.max_lift_mm = -1.0; }, {"max_lift_mm", "-1", "positive"}},
      {"nan lift", [](LiftEventSpec& s) { s.max_lift_mm = NAN; }, {"max_lift_mm", "finite"}},
      {"zero duration", [](LiftEventSpec& s) { s.opening.duration_deg = 0.0; }, {"opening.duration_deg", "positive"}},
      {"negative closing duration", [](LiftEventSpec& s) { s.closing.duration_deg = -5.0; },
       {"closing.duration_deg", "-5"}},
      {"ramp longer than flank", [](LiftEventSpec& s) { s.opening.ramp_length_deg = 80.0; },
       {"opening.ramp_length_deg", "80", "shorter than opening.duration_deg"}},
      {"ramp as high as the lift", [](LiftEventSpec& s) { s.closing.ramp_height_mm = 9.5; },
       {"closing.ramp_height_mm", "below max_lift_mm"}},
      {"ramp without length", [](LiftEventSpec& s) { s.opening.ramp_length_deg = 0.0; },
       {"opening.ramp_height_mm", "needs a length"}},
      {"ramp without height", [](LiftEventSpec& s) { s.closing.ramp_height_mm = 0.0; },
       {"closing.ramp_length_deg", "needs a height"}},
      {"event of 360 deg", [](LiftEventSpec& s) { s.opening.duration_deg = 200.0; s.closing.duration_deg = 154.0; },
       {"opening.duration_deg + dwell_deg + closing.duration_deg", "360"}},
      {"negative dwell", [](LiftEventSpec& s) { s.dwell_deg = -1.0; }, {"dwell_deg", ">= 0"}},
      {"peak outside the cycle", [](LiftEventSpec& s) { s.peak_deg = 360.0; }, {"peak_deg", "[0, 360)"}},
      {"zero blend", [](LiftEventSpec& s) { s.ramp_blend = 0.0; }, {"ramp_blend", "(0, 1]"}},
      {"polydyne without speed", [](LiftEventSpec& s) { s.opening.law = LawKind::polydyne; },
       {"polydyne_engine_rpm", "positive"}},
      {"bspline without controls", [](LiftEventSpec& s) { s.closing.law = LawKind::bspline; },
       {"closing.acc_controls", "at least 4"}},
      {"controls for another law", [](LiftEventSpec& s) { s.opening.acc_controls = {0, 1, -1, 0}; },
       {"opening.acc_controls", "bspline only"}},
      {"bspline shape without rise",
       [](LiftEventSpec& s) {
         s.opening.law = LawKind::bspline;
         s.opening.acc_controls = {0, -1, 1, 0};
       },
       {"opening.acc_controls", "net rise"}},
      {"ramp too fast for the flank",
       [](LiftEventSpec& s) {
         s.opening.law = LawKind::polynomial_4567;
         s.opening.ramp_height_mm = 3.0;
         s.opening.ramp_length_deg = 6.0;
       },
       {"opening", "monotonically", "ramp_height_mm"}},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    LiftEventSpec s = asymmetric_spec();
    c.edit(s);
    try {
      (void)LiftEvent::compile(s);
      FAIL_CHECK("no InputError");
    } catch (const InputError& e) {
      const std::string message = e.what();
      INFO("message: " << message);
      for (const auto& part : c.expect) CHECK_THAT(message, Contains(part));
    }
  }
  CHECK_THROWS_WITH(parse_law("parabolic", "--law"), Contains("parabolic") && Contains("cycloidal"));
  for (LawKind k : kAllLaws) CHECK(parse_law(to_string(k), "law") == k);
  CHECK_THROWS_AS(Cycloidal(0.0, 10.0), InputError);
  CHECK_THROWS_AS(Cycloidal(1.0, -10.0), InputError);
}
