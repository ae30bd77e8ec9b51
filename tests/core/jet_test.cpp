// jets against closed-form derivatives. every reference below is d^k/dt^k of an explicit
// function of t, differentiated symbolically (sympy 1.14, factored) and pasted as code.
#include "camopt/core/jet.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include "support/compare.hpp"

namespace {

using camopt::Jet;
using J3 = Jet<3>;

using namespace camopt::test::tol;

// sample points t where the test functions are smooth
constexpr std::array<double, 5> kPoints = {-1.3, -0.4, 0.25, 0.7, 1.6};

using Reference = std::array<std::function<double(double)>, 4>;

// checks f(jet of t) against the 4 reference derivatives at every sample point
void check(const std::string& name, const std::function<J3(const J3&)>& f, const Reference& ref,
           double rel = kJetRecurrenceRel) {
  for (const double t0 : kPoints) {
    const J3 v = f(J3::variable(t0));
    for (int k = 0; k <= 3; ++k) {
      const double expected = ref[static_cast<std::size_t>(k)](t0);
      INFO(name << ": t = " << t0 << ", d^" << k << "/dt^" << k << " = " << v.derivative(k)
                << ", expected " << expected);
      CHECK_NEAR(v.derivative(k), expected, kJetRecurrenceAbs, rel);
    }
  }
}

}  // namespace

TEST_CASE("jet: construction, value and derivative") {
  constexpr J3 a = J3::variable(2.0, 3.0);
  STATIC_REQUIRE(a.value() == 2.0);
  STATIC_REQUIRE(a.derivative(1) == 3.0);
  STATIC_REQUIRE(a.derivative(2) == 0.0);
  STATIC_REQUIRE(a.derivative(7) == 0.0);

  // constexpr arithmetic: (2 + 3t)^2 = 4 + 12 t + 9 t^2
  constexpr J3 sq = a * a;
  STATIC_REQUIRE(sq.c[0] == 4.0);
  STATIC_REQUIRE(sq.c[1] == 12.0);
  STATIC_REQUIRE(sq.c[2] == 9.0);
  STATIC_REQUIRE(sq.derivative(2) == 18.0);

  const J3 k(5.0);
  CHECK(k.value() == 5.0);
  CHECK(k.c[1] == 0.0);
  CHECK(camopt::value(k) == 5.0);
  CHECK(camopt::value(1.5) == 1.5);

  // derivative(k) = k! c[k]
  J3 p;
  p.c = {1.0, 2.0, 3.0, 4.0};
  CHECK(p.derivative(0) == 1.0);
  CHECK(p.derivative(1) == 2.0);
  CHECK(p.derivative(2) == 6.0);
  CHECK(p.derivative(3) == 24.0);

  // truncate keeps the low coefficients
  const Jet<1> q = camopt::truncate<1>(p);
  CHECK(q.c[0] == 1.0);
  CHECK(q.c[1] == 2.0);

  // order 0 works as a plain number
  const Jet<0> z = sin(Jet<0>(0.5)) * 2.0;
  CHECK(z.value() == 2.0 * std::sin(0.5));
}

TEST_CASE("jet: arithmetic with doubles on either side and compound assignment") {
  const J3 t = J3::variable(0.5);
  const J3 u = 2.0 + t * 3.0 - 1.0;  // 1 + 3t
  CHECK(u.value() == 2.5);
  CHECK(u.derivative(1) == 3.0);

  const J3 w = 1.0 - t;  // 1 - t
  CHECK(w.value() == 0.5);
  CHECK(w.derivative(1) == -1.0);

  const J3 m = -(2.0 * t);
  CHECK(m.derivative(1) == -2.0);

  // 1 / t: derivatives -1/t^2, 2/t^3, -6/t^4 at t = 0.5
  const J3 r = 1.0 / t;
  CHECK_NEAR(r.derivative(0), 2.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_NEAR(r.derivative(1), -4.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_NEAR(r.derivative(2), 16.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_NEAR(r.derivative(3), -96.0, kJetRecurrenceAbs, kJetRecurrenceRel);

  const J3 h = t / 4.0;
  CHECK(h.derivative(1) == 0.25);

  // compound forms agree with the binary ones
  J3 c = t;
  c += t * t;
  c -= 0.5;
  c *= t;
  c /= (t + 2.0);
  c += 1.0;
  c -= t;
  c *= 3.0;
  c /= 2.0;
  const J3 ref = ((((t + t * t) - 0.5) * t) / (t + 2.0) + 1.0 - t) * 3.0 / 2.0;
  for (int k = 0; k <= 3; ++k) CHECK_NEAR(c.derivative(k), ref.derivative(k), kJetRecurrenceAbs, kJetRecurrenceRel);

  // self-aliasing compound assignment
  J3 s = t + 1.0;
  const J3& alias = s;
  s *= alias;  // (t + 1)^2
  CHECK_NEAR(s.derivative(1), 3.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_NEAR(s.derivative(2), 2.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK(s.derivative(3) == 0.0);
  s /= alias;
  CHECK_NEAR(s.value(), 1.0, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_ABS(s.derivative(1), 0.0, kJetRecurrenceAbs);
}

TEST_CASE("jet: sin, cos, sincos of t^2 + 1") {
  const auto u = [](const J3& t) { return t * t + 1.0; };
  const Reference sin_ref = {
      [](double t) { return std::sin(t * t + 1); },
      [](double t) { return 2 * t * std::cos(t * t + 1); },
      [](double t) { return -2 * (2 * t * t * std::sin(t * t + 1) - std::cos(t * t + 1)); },
      [](double t) {
        return -4 * t * (2 * t * t * std::cos(t * t + 1) + 3 * std::sin(t * t + 1));
      }};
  const Reference cos_ref = {
      [](double t) { return std::cos(t * t + 1); },
      [](double t) { return -2 * t * std::sin(t * t + 1); },
      [](double t) { return -2 * (2 * t * t * std::cos(t * t + 1) + std::sin(t * t + 1)); },
      [](double t) { return 4 * t * (2 * t * t * std::sin(t * t + 1) - 3 * std::cos(t * t + 1)); }};
  check(
      "sin", [&](const J3& t) { return sin(u(t)); }, sin_ref);
  check(
      "cos", [&](const J3& t) { return cos(u(t)); }, cos_ref);
  check(
      "sincos.s",
      [&](const J3& t) {
        J3 s, c;
        sincos(u(t), s, c);
        return s;
      },
      sin_ref);
  check(
      "sincos.c",
      [&](const J3& t) {
        J3 s, c;
        sincos(u(t), s, c);
        return c;
      },
      cos_ref);
}

TEST_CASE("jet: exp and log") {
  check("exp(t^2/2 - t)", [](const J3& t) { return exp(0.5 * t * t - t); },
        {[](double t) { return std::exp(0.5 * t * t - t); },
         [](double t) { return (t - 1) * std::exp(0.5 * t * t - t); },
         [](double t) { return (t * t - 2 * t + 2) * std::exp(0.5 * t * t - t); },
         [](double t) { return (t - 1) * (t * t - 2 * t + 4) * std::exp(0.5 * t * t - t); }});
  check("exp(sin t)", [](const J3& t) { return exp(sin(t)); },
        {[](double t) { return std::exp(std::sin(t)); },
         [](double t) { return std::exp(std::sin(t)) * std::cos(t); },
         [](double t) { return (std::cos(t) * std::cos(t) - std::sin(t)) * std::exp(std::sin(t)); },
         [](double t) {
           return -(std::sin(t) + 3) * std::exp(std::sin(t)) * std::sin(t) * std::cos(t);
         }});
  check("log(2 + t^2)", [](const J3& t) { return log(2.0 + t * t); },
        {[](double t) { return std::log(t * t + 2); }, [](double t) { return 2 * t / (t * t + 2); },
         [](double t) { return -2 * (t * t - 2) / std::pow(t * t + 2, 2); },
         [](double t) { return 4 * t * (t * t - 6) / std::pow(t * t + 2, 3); }});
}

TEST_CASE("jet: sqrt, hypot and a sqrt chain") {
  check("sqrt(4 + t + t^3)", [](const J3& t) { return sqrt(4.0 + t + t * t * t); },
        {[](double t) { return std::sqrt(t * t * t + t + 4); },
         [](double t) { return 0.5 * (3 * t * t + 1) / std::sqrt(t * t * t + t + 4); },
         [](double t) {
           return 0.25 * (3 * std::pow(t, 4) + 6 * t * t + 48 * t - 1) /
                  std::pow(t * t * t + t + 4, 1.5);
         },
         [](double t) {
           return -3.0 / 8.0 *
                  (std::pow(t, 6) + 5 * std::pow(t, 4) + 80 * std::pow(t, 3) - 5 * t * t - 16 * t -
                   129) /
                  std::pow(t * t * t + t + 4, 2.5);
         }});
  // sqrt(1 + sqrt(t^2 + 2))
  check("sqrt(1 + sqrt(t^2 + 2))", [](const J3& t) { return sqrt(1.0 + sqrt(t * t + 2.0)); },
        {[](double t) { return std::sqrt(std::sqrt(t * t + 2) + 1); },
         [](double t) {
           const double r = std::sqrt(t * t + 2);
           return 0.5 * t / (r * std::sqrt(r + 1));
         },
         [](double t) {
           const double r = std::sqrt(t * t + 2);
           return -0.25 * (std::pow(t, 4) - 2 * t * t - 4 * r - 8) /
                  (std::pow(t * t + 2, 2) * std::pow(r + 1, 1.5));
         },
         [](double t) {
           const double r = std::sqrt(t * t + 2);
           return 3.0 / 8.0 * t * (std::pow(t, 4) - 10 * t * t - 20 * r - 32) /
                  (std::pow(t * t + 2, 2) * std::sqrt(r + 1) * (t * t * r + 2 * t * t + 3 * r + 4));
         }});
  // hypot(t^2 - 1, 2t + 1/2)
  check(
      "hypot", [](const J3& t) { return hypot(t * t - 1.0, 2.0 * t + 0.5); },
      {[](double t) { return 0.5 * std::sqrt((2 * t * t - 2 * t + 5) * (2 * t * t + 2 * t + 1)); },
       [](double t) {
         return 2 * (2 * t * t * t + 2 * t + 1) /
                std::sqrt((2 * t * t - 2 * t + 5) * (2 * t * t + 2 * t + 1));
       },
       [](double t) {
         return 4 *
                (4 * std::pow(t, 6) + 12 * std::pow(t, 4) + 16 * std::pow(t, 3) + 15 * t * t + 3) /
                std::pow((2 * t * t - 2 * t + 5) * (2 * t * t + 2 * t + 1), 1.5);
       },
       [](double t) {
         const double a = 2 * t * t - 2 * t + 5;
         const double b = 2 * t * t + 2 * t + 1;
         return -24 * (2 * t * t - 4 * t - 3) * (2 * t * t + t + 2) * (2 * t * t + 4 * t - 1) /
                (std::sqrt(a * b) * a * a * b * b);
       }});
  // hypot agrees with sqrt(x^2 + y^2) and does not overflow in the value
  const J3 big = hypot(J3::variable(3e200), J3(4e200));
  CHECK_NEAR(big.value(), 5e200, kJetRecurrenceAbs, kJetRecurrenceRel);
}

TEST_CASE("jet: division chains") {
  check("(t^2 + 1) / (t^3 - 2t + 3) / (1 + t)",
        [](const J3& t) { return (t * t + 1.0) / (t * t * t - 2.0 * t + 3.0) / (1.0 + t); },
        {[](double t) { return (t * t + 1) / ((t + 1) * (t * t * t - 2 * t + 3)); },
         [](double t) {
           const double q = t * t * t - 2 * t + 3;
           return -(t - 1) * (2 * std::pow(t, 4) + 3 * std::pow(t, 3) + 7 * t * t + 9 * t - 1) /
                  (std::pow(t + 1, 2) * q * q);
         },
         [](double t) {
           const double q = t * t * t - 2 * t + 3;
           return 2 *
                  (3 * std::pow(t, 8) + 3 * std::pow(t, 7) + 13 * std::pow(t, 6) +
                   9 * std::pow(t, 5) - 51 * std::pow(t, 4) - 33 * std::pow(t, 3) + 15 * t * t -
                   15 * t + 16) /
                  (std::pow(t + 1, 3) * q * q * q);
         },
         [](double t) {
           const double q = t * t * t - 2 * t + 3;
           return -6 * (t - 1) *
                  (4 * std::pow(t, 10) + 10 * std::pow(t, 9) + 42 * std::pow(t, 8) +
                   73 * std::pow(t, 7) - 79 * std::pow(t, 6) - 303 * std::pow(t, 5) -
                   335 * std::pow(t, 4) - 317 * std::pow(t, 3) - 129 * t * t + 73 * t - 31) /
                  (std::pow(t + 1, 4) * std::pow(q, 4));
         }});
}

TEST_CASE("jet: square and integer powers") {
  const auto u = [](const J3& t) { return t * t + 1.0; };
  check("square", [&](const J3& t) { return square(u(t)); },
        {[](double t) { return std::pow(t * t + 1, 2); },
         [](double t) { return 4 * t * (t * t + 1); }, [](double t) { return 12 * t * t + 4; },
         [](double t) { return 24 * t; }});
  check("pow 3", [&](const J3& t) { return pow(u(t), 3); },
        {[](double t) { return std::pow(t * t + 1, 3); },
         [](double t) { return 6 * t * std::pow(t * t + 1, 2); },
         [](double t) { return 6 * (t * t + 1) * (5 * t * t + 1); },
         [](double t) { return 24 * t * (5 * t * t + 3); }});
  check("pow -2", [&](const J3& t) { return pow(u(t), -2); },
        {[](double t) { return std::pow(t * t + 1, -2); },
         [](double t) { return -4 * t / std::pow(t * t + 1, 3); },
         [](double t) { return 4 * (5 * t * t - 1) / std::pow(t * t + 1, 4); },
         [](double t) { return -24 * t * (5 * t * t - 3) / std::pow(t * t + 1, 5); }});
  check("pow 0", [&](const J3& t) { return pow(u(t), 0); },
        {[](double) { return 1.0; }, [](double) { return 0.0; }, [](double) { return 0.0; },
         [](double) { return 0.0; }});
  // t^5 at t0 = 0 (exact, the value is zero)
  const J3 p5 = pow(J3::variable(0.0), 5);
  for (int k = 0; k <= 3; ++k) CHECK(p5.derivative(k) == 0.0);
  CHECK(camopt::square(3.0) == 9.0);
}

TEST_CASE("jet: atan, asin, acos") {
  check(
      "atan(t^3 - t)", [](const J3& t) { return atan(t * t * t - t); },
      {[](double t) { return std::atan(t * t * t - t); },
       [](double t) { return (3 * t * t - 1) / (std::pow(t, 6) - 2 * std::pow(t, 4) + t * t + 1); },
       [](double t) {
         const double d = std::pow(t, 6) - 2 * std::pow(t, 4) + t * t + 1;
         return -2 * t * (6 * std::pow(t, 6) - 9 * std::pow(t, 4) + 4 * t * t - 4) / (d * d);
       },
       [](double t) {
         const double d = std::pow(t, 6) - 2 * std::pow(t, 4) + t * t + 1;
         return 2 *
                (30 * std::pow(t, 12) - 75 * std::pow(t, 10) + 72 * std::pow(t, 8) -
                 117 * std::pow(t, 6) + 105 * std::pow(t, 4) - 24 * t * t + 4) /
                (d * d * d);
       }});
  check("asin(2/5 sin t)", [](const J3& t) { return asin(0.4 * sin(t)); },
        {[](double t) { return std::asin(0.4 * std::sin(t)); },
         [](double t) { return 2 * std::cos(t) / std::sqrt(25 - 4 * std::pow(std::sin(t), 2)); },
         [](double t) {
           return -42 * std::sin(t) / std::pow(25 - 4 * std::pow(std::sin(t), 2), 1.5);
         },
         [](double t) {
           const double w = 25 - 4 * std::pow(std::sin(t), 2);
           return 42 * (4 * std::cos(2 * t) - 29) * std::cos(t) / (std::sqrt(w) * w * w);
         }});
  check("acos(3/10 t^2)", [](const J3& t) { return acos(0.3 * t * t); },
        {[](double t) { return std::acos(0.3 * t * t); },
         [](double t) { return -6 * t / std::sqrt(100 - 9 * std::pow(t, 4)); },
         [](double t) {
           return -6 * (9 * std::pow(t, 4) + 100) / std::pow(100 - 9 * std::pow(t, 4), 1.5);
         },
         [](double t) {
           return -108 * std::pow(t, 3) * (9 * std::pow(t, 4) + 500) /
                  std::pow(100 - 9 * std::pow(t, 4), 2.5);
         }});
}

TEST_CASE("jet: atan2 in all four quadrants") {
  // theta = atan2(y, x) for x = X + t - t^3/2, y = Y + 2t + t^2, derivatives by hand:
  // theta' = n / d with n = x y' - y x', d = x^2 + y^2, n' = x y'' - y x'',
  // n'' = x' y'' + x y''' - y' x'' - y x''', d' = 2 (x x' + y y'), d'' = 2 (x'^2 + x x'' + y'^2 + y
  // y'') theta'' = (n' d - n d') / d^2, theta''' = (n'' d - n d'') / d^2 - 2 d' (n' d - n d') / d^3
  const std::array<std::array<double, 2>, 4> quadrants = {
      {{2.0, 1.5}, {-2.0, 1.5}, {-2.0, -1.5}, {2.0, -1.5}}};
  for (const auto& [X, Y] : quadrants) {
    for (const double t0 : kPoints) {
      const double tt = 0.2 * t0;  // stay inside the quadrant
      const double x = X + tt - 0.5 * tt * tt * tt, x1 = 1 - 1.5 * tt * tt, x2 = -3 * tt, x3 = -3;
      const double y = Y + 2 * tt + tt * tt, y1 = 2 + 2 * tt, y2 = 2, y3 = 0;
      const double n = x * y1 - y * x1, n1 = x * y2 - y * x2,
                   n2 = x1 * y2 + x * y3 - y1 * x2 - y * x3;
      const double d = x * x + y * y, d1 = 2 * (x * x1 + y * y1),
                   d2 = 2 * (x1 * x1 + x * x2 + y1 * y1 + y * y2);
      const std::array<double, 4> expected = {
          std::atan2(y, x), n / d, (n1 * d - n * d1) / (d * d),
          (n2 * d - n * d2) / (d * d) - 2 * d1 * (n1 * d - n * d1) / (d * d * d)};

      const J3 t = J3::variable(tt);
      const J3 theta = atan2(Y + 2.0 * t + t * t, X + t - 0.5 * t * t * t);
      INFO("quadrant X = " << X << ", Y = " << Y << ", t = " << tt);
      for (int k = 0; k <= 3; ++k)
        CHECK_NEAR(theta.derivative(k), expected[static_cast<std::size_t>(k)], kJetRecurrenceAbs, kJetRecurrenceRel);
      // the value keeps the quadrant
      CHECK(std::signbit(theta.value()) == std::signbit(Y));
      CHECK((std::abs(theta.value()) > std::numbers::pi / 2) == (X < 0));
    }
  }
  // on the negative x axis the derivatives stay finite (no atan(y/x) branch issue)
  const J3 t = J3::variable(0.0);
  const J3 th = atan2(t, -1.0 + 0.0 * t);
  CHECK_NEAR(th.value(), std::numbers::pi, kJetRecurrenceAbs, kJetRecurrenceRel);
  CHECK_NEAR(th.derivative(1), -1.0, kJetRecurrenceAbs, kJetRecurrenceRel);
}

TEST_CASE("jet: atan2 matches atan(y / x) for x > 0") {
  for (const double t0 : kPoints) {
    const J3 t = J3::variable(t0);
    const J3 y = sin(t) + 0.3;
    const J3 x = 2.0 + cos(3.0 * t);
    const J3 a = atan2(y, x);
    const J3 b = atan(y / x);
    for (int k = 0; k <= 3; ++k) CHECK_NEAR(a.derivative(k), b.derivative(k), kJetRecurrenceAbs, kJetTwoFormsRel);
  }
}

TEST_CASE("jet: compose matches direct jet evaluation") {
  for (const double t0 : kPoints) {
    const J3 x = J3::variable(t0) * J3::variable(t0) + 1.0;  // t^2 + 1
    const double x0 = x.value();

    // sin through its derivatives sin, cos, -sin, -cos
    const double fs[4] = {std::sin(x0), std::cos(x0), -std::sin(x0), -std::cos(x0)};
    const J3 a = camopt::compose(fs, x);
    const J3 b = sin(x);
    for (int k = 0; k <= 3; ++k) CHECK_NEAR(a.derivative(k), b.derivative(k), kJetRecurrenceAbs, kJetRecurrenceRel);

    // exp(x) / x through f = e^x / x: f' = e^x (x - 1) / x^2, f'' = e^x (x^2 - 2x + 2) / x^3,
    // f''' = e^x (x^3 - 3x^2 + 6x - 6) / x^4
    const double e = std::exp(x0);
    const double fe[4] = {e / x0, e * (x0 - 1) / (x0 * x0),
                          e * (x0 * x0 - 2 * x0 + 2) / std::pow(x0, 3),
                          e * (std::pow(x0, 3) - 3 * x0 * x0 + 6 * x0 - 6) / std::pow(x0, 4)};
    const J3 c = camopt::compose(fe, x);
    const J3 d = exp(x) / x;
    for (int k = 0; k <= 3; ++k) CHECK_NEAR(c.derivative(k), d.derivative(k), kJetRecurrenceAbs, kJetRecurrenceRel);
  }
  // higher order: Jet<5> of sin(2t + t^2) composed vs direct
  const Jet<5> x = 2.0 * Jet<5>::variable(0.3) + square(Jet<5>::variable(0.3));
  const double x0 = x.value();
  const double f[6] = {std::sin(x0),  std::cos(x0), -std::sin(x0),
                       -std::cos(x0), std::sin(x0), std::cos(x0)};
  const Jet<5> a = camopt::compose(f, x);
  const Jet<5> b = sin(x);
  for (int k = 0; k <= 5; ++k) CHECK_NEAR(a.derivative(k), b.derivative(k), kJetRecurrenceAbs, kJetTwoFormsRel);
}

TEST_CASE("jet: generic code runs on double and on jets") {
  // one body for both scalar kinds
  const auto f = [](const auto& t) {
    using std::atan2;
    using std::cos;
    using std::sin;
    using std::sqrt;
    return atan2(sin(t), 2.0 + cos(t)) * sqrt(1.0 + t * t);
  };
  const double t0 = 0.8;
  const J3 j = f(J3::variable(t0));
  CHECK_REL(camopt::value(j), f(t0), kUlpRel);
  // derivative against a central finite difference (test-only check)
  const double h = 1e-5;
  CHECK_REL(j.derivative(1), (f(t0 + h) - f(t0 - h)) / (2 * h), kCentral2Step1e5Rel);
}
