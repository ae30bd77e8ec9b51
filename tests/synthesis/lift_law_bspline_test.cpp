// the b-spline acceleration law: it reproduces the polynomial laws exactly, integrates
// exactly twice, closes by the least change, and rejects shapes that cannot make a rise.
#include <functional>
#include <vector>

#include "synthesis/lift_law_test_support.hpp"

using namespace camopt::lift_law_test;
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
    CHECK_ABS(law.closure_change(), 0.0, kClosureChangeAbs);
    for (int i = 0; i <= 50; ++i) {
      const double theta = kBeta * i / 50.0;
      for (int k = 0; k <= 3; ++k)
        check_close(law.evaluate(theta)[k], p345.evaluate(theta)[k], kLawIdentityRel, kH / std::pow(kBeta, k) * 60.0,
                    "3-4-5 d^" + std::to_string(k) + " at " + std::to_string(theta));
    }
  }
  // 4-5-6-7: y'' = 420 x^2 - 1680 x^3 + 2100 x^4 - 840 x^5, a quintic bezier
  const std::vector<double> c4567 = bernstein({0, 0, 420, -1680, 2100, -840});
  const BSplineAcceleration law(kH, kBeta, c4567, 5);
  const Polynomial4567 p4567(kH, kBeta);
  CHECK_ABS(law.closure_change(), 0.0, kClosureChange4567Abs);
  for (int i = 0; i <= 50; ++i) {
    const double theta = kBeta * i / 50.0;
    for (int k = 0; k <= 3; ++k)
      check_close(law.evaluate(theta)[k], p4567.evaluate(theta)[k], kLawIdentityRel, kH / std::pow(kBeta, k) * 60.0,
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
      check_close(law.unit(x).acc, spline_by_basis(t, c, degree, x), kLawIdentityRel, 10.0, "acc at " + std::to_string(x));
    }
    // velocity and lift are its exact first and second integrals
    for (int i = 1; i <= 40; ++i) {
      const double x = i / 40.0 - 0.0123 * (i % 3);
      const auto acc = [&](double s) { return spline_by_basis(t, c, degree, s); };
      const double vel = integrate_by_spans(t, x, acc);
      const double lift = integrate_by_spans(t, x, [&](double s) { return (x - s) * acc(s); });
      check_close(law.unit(x).vel, vel, kLawIdentityRel, 10.0, "vel at " + std::to_string(x));
      check_close(law.unit(x).lift, lift, kLawIdentityRel, 10.0, "lift at " + std::to_string(x));
    }
    // closure: zero acceleration at both ends, zero velocity and unit lift at the end
    CHECK(c.front() == 0.0);
    CHECK(c.back() == 0.0);
    check_close(law.unit(1.0).vel, 0.0, kLawIdentityRel, 1.0, "y'(1)");
    check_close(law.unit(1.0).lift, 1.0, kLawIdentityRel, 1.0, "y(1)");
    // least change: the change lies in the span of the constraint rows e_0, e_{n-1}, w,
    // so inside the interior it is proportional to w_i = int N_i
    const std::size_t n = given.size();
    std::vector<double> ratio;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double w = (t[i + static_cast<std::size_t>(degree) + 1] - t[i]) / (degree + 1);
      ratio.push_back((c[i] / law.shape_scale() - given[i]) / w);
    }
    for (double r : ratio) check_close(r, ratio.front(), kClosureRatioRel, std::abs(ratio.front()) + 1.0, "change / w_i");
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
