// quintic interpolating splines: interpolation, convergence order, c4 continuity,
// periodic wrap, jet overloads, natural end conditions, extrapolation and exact integrals.
#include "camopt/core/units.hpp"
#include "camopt/core/spline.hpp"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "camopt/core/error.hpp"
#include "support/compare.hpp"

namespace {

using camopt::InputError;
using camopt::Jet;
using camopt::PeriodicSpline;
using camopt::Spline;

constexpr double kTwoPi = 2.0 * camopt::pi;
using namespace camopt::test::tol;
constexpr std::uint32_t kSeed = 20240611;  // jittered grids

// test function sin x + 0.3 cos 3x and its derivatives
double f_exact(double x, int k) {
  switch (k) {
    case 0:
      return std::sin(x) + 0.3 * std::cos(3 * x);
    case 1:
      return std::cos(x) - 0.9 * std::sin(3 * x);
    case 2:
      return -std::sin(x) - 2.7 * std::cos(3 * x);
    case 3:
      return -std::cos(x) + 8.1 * std::sin(3 * x);
    default:
      return 0.0;
  }
}

// uniform in [-1, 1) from raw mt19937 output (portable, unlike the std distributions)
double unit(std::mt19937& gen) { return 2.0 * (gen() / 4294967296.0) - 1.0; }

// n nodes on [x0, x0 + 2 pi), each moved by up to jitter * h
std::vector<double> grid(int n, double jitter, double x0 = 0.0, std::uint32_t seed = kSeed) {
  std::mt19937 gen(seed);
  const double h = kTwoPi / n;
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = x0 + (i + jitter * unit(gen)) * h;
  return x;
}

std::vector<double> sample(const std::vector<double>& x) {
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = f_exact(x[i], 0);
  return y;
}

// max |f^(k) - s^(k)| over a fine grid, k = 0..3
std::array<double, 4> max_errors(const PeriodicSpline& s) {
  std::array<double, 4> err{};
  constexpr int kFine = 4000;
  for (int j = 0; j < kFine; ++j) {
    const double x = (j + 0.5) * kTwoPi / kFine;
    double d[4];
    s.evaluate(x, 3, d);
    for (int k = 0; k < 4; ++k) {
      err[static_cast<std::size_t>(k)] =
          std::max(err[static_cast<std::size_t>(k)], std::abs(d[k] - f_exact(x, k)));
    }
  }
  return err;
}

// left and right limits of f..f'''' at every knot agree (left limit one ulp below)
template <class S>
void check_c4(const S& s, std::span<const double> knots, double left_of_first) {
  std::array<std::vector<double>, 5> right, left;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const double xl = i == 0 ? left_of_first : std::nextafter(knots[i], -INFINITY);
    double r[5], l[5];
    s.evaluate(knots[i], 4, r);
    s.evaluate(xl, 4, l);
    for (std::size_t k = 0; k <= 4; ++k) right[k].push_back(r[k]), left[k].push_back(l[k]);
  }
  // each derivative: left limit against right limit at every knot, of the peak |right limit|
  for (std::size_t k = 0; k <= 4; ++k)
    CHECK_SERIES(camopt::test::compare_series("left limit of f^(" + std::to_string(k) + ")", left[k], right[k],
                                              {.rel = kSplineContinuityRel}, knots, "knot x"));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// periodic spline

TEST_CASE("periodic spline: interpolates the data") {
  for (const double jitter : {0.0, 0.3}) {
    for (const int n : {6, 7, 33, 100}) {
      const auto x = grid(n, jitter, -1.0);
      const auto y = sample(x);
      const auto s = PeriodicSpline::interpolate(x, y, kTwoPi);
      CHECK(s.period() == kTwoPi);
      REQUIRE(s.knots().size() == x.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        INFO("n = " << n << ", jitter = " << jitter << ", node " << i);
        CHECK_ABS(s(x[i]), y[i], kSplineNodeAbs);
        // the closing point x0 + period has the value y0
        CHECK_ABS(s(x[0] + kTwoPi), y[0], kSplineNodeAbs);
      }
    }
  }
}

TEST_CASE("periodic spline: convergence order on uniform and jittered grids") {
  // theory: (f - s)^(k) = O(h^(6-k)) (de Boor, ch. XIII); measured orders on the uniform
  // grid are 6.0, 5.0, 4.0 and 3.0 for f .. f'''
  const std::array<int, 3> sizes = {32, 64, 128};
  const auto orders = [](const std::array<std::array<double, 4>, 3>& err, std::size_t m0,
                         std::size_t m1) {
    std::array<double, 4> order{};
    const double steps = static_cast<double>(m1 - m0);  // each step halves h
    for (std::size_t k = 0; k < 4; ++k) order[k] = std::log2(err[m0][k] / err[m1][k]) / steps;
    return order;
  };
  const auto check_orders = [](const std::array<double, 4>& order) {
    CHECK(order[0] >= 5.5);
    CHECK(order[0] <= 6.5);
    CHECK(order[1] >= 4.5);
    CHECK(order[2] >= 3.5);
    CHECK(order[3] >= 2.7);
  };

  SECTION("uniform: every doubling") {
    std::array<std::array<double, 4>, 3> err{};
    for (std::size_t m = 0; m < sizes.size(); ++m) {
      const auto x = grid(sizes[m], 0.0);
      err[m] = max_errors(PeriodicSpline::interpolate(x, sample(x), kTwoPi));
    }
    for (std::size_t m = 0; m + 1 < sizes.size(); ++m) {
      const auto order = orders(err, m, m + 1);
      INFO("n = " << sizes[m] << " -> " << sizes[m + 1] << ": errors " << err[m][0] << " "
                  << err[m][1] << " " << err[m][2] << " " << err[m][3] << ", orders " << order[0]
                  << " " << order[1] << " " << order[2] << " " << order[3]);
      check_orders(order);
    }
  }

  SECTION("jittered: nested refinement, fitted over 32 -> 128") {
    // a jittered 32-node grid refined by bisecting every interval, so the local mesh
    // ratios stay fixed while h halves (independent jitter per n lets the worst mesh
    // ratio grow with n and biases the observed order low)
    std::array<std::array<double, 4>, 3> err{};
    auto x = grid(sizes[0], 0.3);
    for (std::size_t m = 0; m < sizes.size(); ++m) {
      REQUIRE(x.size() == static_cast<std::size_t>(sizes[m]));
      err[m] = max_errors(PeriodicSpline::interpolate(x, sample(x), kTwoPi));
      std::vector<double> refined;
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double next = i + 1 < x.size() ? x[i + 1] : x[0] + kTwoPi;
        refined.push_back(x[i]);
        refined.push_back(0.5 * (x[i] + next));
      }
      x = refined;
    }
    const auto order = orders(err, 0, 2);
    INFO("errors n = 32: " << err[0][0] << " " << err[0][1] << " " << err[0][2] << " " << err[0][3]
                           << ", n = 128: " << err[2][0] << " " << err[2][1] << " " << err[2][2]
                           << " " << err[2][3] << ", orders " << order[0] << " " << order[1] << " "
                           << order[2] << " " << order[3]);
    check_orders(order);
  }
}

TEST_CASE("periodic spline: the banded solve and the uniform recursive filter give the sparse LU's spline") {
  // jittered knots (a non-uniform collocation matrix: the banded solve) and uniform ones
  // (the recursive filter), from the smallest size (6: the 4 x 4 schur block wraps onto the
  // first two rows; the filter's periodic sums wrap) to a long table; values and every
  // derivative at points between the knots
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (const bool uniform : {false, true})
  for (int n : {6, 7, 9, 40, 64, 65, 1500}) {
    INFO((uniform ? "uniform" : "jittered") << " knots, n = " << n);
    std::vector<double> x(static_cast<std::size_t>(n)), y(x.size());
    const double h = 2 * std::numbers::pi / n;
    for (int i = 0; i < n; ++i) {
      x[static_cast<std::size_t>(i)] = (i + (uniform ? 0.0 : jitter(rng))) * h;
      y[static_cast<std::size_t>(i)] = std::exp(std::sin(x[static_cast<std::size_t>(i)])) + 0.1 * (i % 3);
    }
    const PeriodicSpline lu = PeriodicSpline::interpolate_by_sparse_lu(x, y, 2 * std::numbers::pi);
    const PeriodicSpline banded = PeriodicSpline::interpolate(x, y, 2 * std::numbers::pi);
    std::array<std::vector<double>, 6> by_lu, by_banded;
    std::vector<double> ats;
    for (int k = 0; k < 997; ++k) {
      const double at = 2 * std::numbers::pi * (k + 0.37) / 997;
      double a[6], b[6];
      lu.evaluate(at, 5, a);
      banded.evaluate(at, 5, b);
      ats.push_back(at);
      for (std::size_t o = 0; o < 6; ++o) by_lu[o].push_back(a[o]), by_banded[o].push_back(b[o]);
    }
    for (std::size_t o = 0; o < 6; ++o)
      CHECK_SERIES(camopt::test::compare_series("banded f^(" + std::to_string(o) + ")", by_banded[o], by_lu[o],
                                                {.rel = kSplineSolverRel}, ats, "x"));
  }
}

TEST_CASE("periodic spline: the uniform recursive filter solves its cyclic system to round-off") {
  // the filter alone (PeriodicSpline::interpolate falls back to the banded solve when its
  // residual is not at round-off, so the comparison above cannot see a wrong filter)
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int n : {1, 2, 5, 6, 7, 12, 63, 64, 65, 1440}) {
    INFO("n = " << n);
    std::vector<double> b(static_cast<std::size_t>(n)), x(b.size());
    for (double& v : b) v = 16.0 + value(rng);
    camopt::detail::solve_uniform_quintic_cyclic(b, x);
    std::vector<double> lhs;
    for (int i = 0; i < n; ++i) {
      auto at = [&](int k) { return x[static_cast<std::size_t>(((i + k) % n + n) % n)]; };
      lhs.push_back((at(-2) + 26 * at(-1) + 66 * at(0) + 26 * at(1) + at(2)) / 120);
    }
    CHECK_SERIES(camopt::test::compare_series("cyclic system row", lhs, b, {.rel = kCyclicFilterRel}));
  }
}

TEST_CASE("periodic spline: c4 at every knot including the seam") {
  for (const double jitter : {0.0, 0.3}) {
    const auto x = grid(40, jitter, 0.5);
    const auto s = PeriodicSpline::interpolate(x, sample(x), kTwoPi);
    // left limit at the first knot is the end of the closing piece
    check_c4(s, s.knots(), std::nextafter(x[0] + kTwoPi, -INFINITY));
  }
}

TEST_CASE("periodic spline: wraps by whole periods") {
  const auto x = grid(50, 0.3, -2.0);
  const auto s = PeriodicSpline::interpolate(x, sample(x), kTwoPi);
  for (int j = 0; j < 200; ++j) {
    const double xe = -2.0 + j * kTwoPi / 200.0 + 0.001;
    double a[6], b[6], c[6];
    s.evaluate(xe, 5, a);
    s.evaluate(xe + 3 * kTwoPi, 5, b);
    s.evaluate(xe - 7 * kTwoPi, 5, c);
    // |f^(k)| <= 25 here; x + 3 period carries a rounding of ~1e-15 [rad]
    for (int k = 0; k <= 5; ++k) {
      CHECK_NEAR(b[k], a[k], kSplineWrapRel, kSplineWrapRel);
      CHECK_NEAR(c[k], a[k], kSplineWrapRel, kSplineWrapRel);
    }
  }
}

TEST_CASE("periodic spline: jet overload equals the scalar derivatives") {
  const auto x = grid(24, 0.2);
  const auto s = PeriodicSpline::interpolate(x, sample(x), kTwoPi);
  for (const double x0 : {0.1, 1.7, 4.0, 6.2, -3.0}) {
    double d[6];
    s.evaluate(x0, 5, d);
    const Jet<3> j = s(Jet<3>::variable(x0));
    for (int k = 0; k <= 3; ++k)
      CHECK_NEAR(j.derivative(k), d[k], kSplineJetRel, kSplineJetRel);
    // chain rule for x(t) = x0 + 2t: d^k/dt^k = 2^k f^(k)
    const Jet<5> j5 = s(Jet<5>::variable(x0, 2.0));
    for (int k = 0; k <= 5; ++k) {
      CHECK_NEAR(j5.derivative(k), std::pow(2.0, k) * d[k], kSplineJetRel, kSplineJetRel);
    }
    // beyond degree 5 every derivative vanishes
    const Jet<7> j7 = s(Jet<7>::variable(x0));
    CHECK(j7.derivative(6) == 0.0);
    CHECK(j7.derivative(7) == 0.0);
  }
}

TEST_CASE("periodic spline: rejects misuse") {
  const std::vector<double> x = {0, 1, 2, 3, 4, 5};
  const std::vector<double> y = {0, 1, 0, 1, 0, 1};
  CHECK_NOTHROW(PeriodicSpline::interpolate(x, y, 6.0));
  CHECK_THROWS_AS(PeriodicSpline::interpolate(x, y, 5.0), InputError);
  CHECK_THROWS_AS(PeriodicSpline::interpolate(std::span(x).first(5), std::span(y).first(5), 6.0),
                  InputError);
  CHECK_THROWS_AS(PeriodicSpline::interpolate(x, std::span(y).first(5), 6.0),
                  InputError);
  const std::vector<double> xd = {0, 1, 2, 2, 4, 5};
  CHECK_THROWS_AS(PeriodicSpline::interpolate(xd, y, 6.0), InputError);
  const std::vector<double> yn = {0, 1, NAN, 1, 0, 1};
  CHECK_THROWS_AS(PeriodicSpline::interpolate(x, yn, 6.0), InputError);
  // the message names the value and the rule
  CHECK_THROWS_WITH(PeriodicSpline::interpolate(x, y, 5.0),
                    Catch::Contains("period = 5 must exceed the data span x.back() - x.front() = 5"));
  CHECK_THROWS_WITH(PeriodicSpline::interpolate(xd, y, 6.0),
                    Catch::Contains("x[3] = 2 is not greater than x[2] = 2 (x must be strictly increasing)"));
  CHECK_THROWS_WITH(PeriodicSpline::interpolate(x, yn, 6.0), Catch::Contains("point 2 (2, nan) is not finite"));
}

// ---------------------------------------------------------------------------------------
// natural (non-periodic) spline

TEST_CASE("spline: interpolates and reproduces quadratics") {
  // the natural quintic spline (f''' = f'''' = 0 at the ends) is exact for degree <= 2
  const auto q = [](double x) { return 0.7 - 1.3 * x + 0.45 * x * x; };
  for (const int n : {3, 4, 5, 6, 11, 40}) {
    auto x = grid(n, 0.3, 0.2);
    std::vector<double> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = q(x[i]);
    const auto s = Spline::interpolate(x, y);
    for (int j = 0; j <= 300; ++j) {
      const double xe = x.front() + (x.back() - x.front()) * j / 300.0;
      double d[4];
      s.evaluate(xe, 3, d);
      INFO("n = " << n << ", x = " << xe);
      CHECK_ABS(d[0], q(xe), kSplinePolyAbs);
      CHECK_ABS(d[1], -1.3 + 0.9 * xe, kSplinePolyAbs);
      CHECK_ABS(d[2], 0.9, kSplinePolyAbs);
      CHECK_ABS(d[3], 0.0, kSplinePolyAbs);
    }
  }
  // general data: nodes hit, natural end conditions hold
  const auto x = grid(30, 0.3);
  const auto y = sample(x);
  const auto s = Spline::interpolate(x, y);
  for (std::size_t i = 0; i < x.size(); ++i) CHECK_ABS(s(x[i]), y[i], kSplineNodeAbs);
  double d0[5], dn[5];
  s.evaluate(x.front(), 4, d0);
  s.evaluate(x.back(), 4, dn);
  CHECK_ABS(d0[3], 0.0, kNaturalEndThirdAbs);
  CHECK_ABS(d0[4], 0.0, kNaturalEndFourthAbs);
  CHECK_ABS(dn[3], 0.0, kNaturalEndThirdAbs);
  CHECK_ABS(dn[4], 0.0, kNaturalEndFourthAbs);
}

TEST_CASE("spline: c4 at every interior knot") {
  for (const double jitter : {0.0, 0.35}) {
    const auto x = grid(45, jitter, 1.0);
    const auto s = Spline::interpolate(x, sample(x));
    const auto k = s.knots();
    // interior knots only: the ends switch to linear extrapolation
    check_c4(s, k.subspan(1, k.size() - 2), std::nextafter(k[1], -INFINITY));
  }
}

TEST_CASE("spline: linear extrapolation with the end slope") {
  const auto x = grid(20, 0.25);
  const auto s = Spline::interpolate(x, sample(x));
  double a[3], b[3];
  s.evaluate(x.front(), 2, a);
  s.evaluate(x.back(), 2, b);
  for (const double d : {1e-9, 0.1, 3.0}) {
    double l[4], r[4];
    s.evaluate(x.front() - d, 3, l);
    s.evaluate(x.back() + d, 3, r);
    CHECK_ABS(l[0], a[0] - a[1] * d, kSplineExtrapolationAbs);
    CHECK(l[1] == a[1]);
    CHECK(l[2] == 0.0);
    CHECK(l[3] == 0.0);
    CHECK_ABS(r[0], b[0] + b[1] * d, kSplineExtrapolationAbs);
    CHECK(r[1] == b[1]);
    CHECK(r[2] == 0.0);
    CHECK(r[3] == 0.0);
  }
  // jets outside the range: value and slope only
  const Jet<3> j = s(Jet<3>::variable(x.back() + 1.0));
  CHECK(j.derivative(1) == b[1]);
  CHECK(j.derivative(2) == 0.0);
}

TEST_CASE("spline: exact integral against gauss-legendre of the spline") {
  // 5-point gauss-legendre on [a, b]: exact for degree <= 9, so exact per polynomial piece
  // (Abramowitz & Stegun 25.4.29)
  const auto gauss5 = [](const Spline& s, double a, double b) {
    constexpr std::array<double, 5> node = {0.0, -0.5384693101056831, 0.5384693101056831,
                                            -0.9061798459386640, 0.9061798459386640};
    constexpr std::array<double, 5> weight = {0.5688888888888889, 0.4786286704993665,
                                              0.4786286704993665, 0.2369268850561891,
                                              0.2369268850561891};
    double sum = 0.0;
    for (std::size_t i = 0; i < 5; ++i)
      sum += weight[i] * s(0.5 * (a + b) + 0.5 * (b - a) * node[i]);
    return 0.5 * (b - a) * sum;
  };
  // quadrature split at every breakpoint (and at the ends of the data range)
  const auto quadrature = [&](const Spline& s, double a, double b) {
    std::vector<double> cuts = {a, b};
    for (const double k : s.knots()) {
      if (k > std::min(a, b) && k < std::max(a, b)) cuts.push_back(k);
    }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) sum += gauss5(s, cuts[i], cuts[i + 1]);
    return a <= b ? sum : -sum;
  };

  const auto x = grid(25, 0.3, 0.5);
  std::vector<double> y = sample(x);
  for (double& v : y) v += 2.0;  // keep integrals away from zero for a relative check
  const auto s = Spline::interpolate(x, y);
  const double x0 = x.front();
  const double xn = x.back();
  const std::array<std::array<double, 2>, 7> ranges = {{{x0, xn},
                                                        {x0 + 0.3, xn - 1.1},
                                                        {2.0, 2.05},
                                                        {x[3], x[9]},
                                                        {x0 - 1.5, x0 + 2.0},
                                                        {3.0, xn + 2.5},
                                                        {xn - 0.4, 1.0}}};
  for (const auto& [a, b] : ranges) {
    const double expected = quadrature(s, a, b);
    INFO("integral over [" << a << ", " << b << "] = " << s.integral(a, b) << ", quadrature "
                           << expected);
    CHECK_REL(s.integral(a, b), expected, kSplineIntegralRel);
    CHECK(s.integral(b, a) == -s.integral(a, b));
  }
  CHECK(s.integral(1.3, 1.3) == 0.0);

  // antiderivative jet: F(x) = int_{x0}^{x} f, F' = f, F'' = f', F''' = f''
  for (const double xe : {x0 - 0.5, x0, 1.234, 4.0, xn, xn + 0.7}) {
    const Jet<3> F = s.antiderivative(Jet<3>::variable(xe));
    double d[3];
    s.evaluate(xe, 2, d);
    INFO("x = " << xe);
    CHECK_NEAR(F.value(), s.integral(x0, xe), kUlpAbs, kUlpRel);
    CHECK_REL(F.derivative(1), d[0], kSplineJetRel);
    CHECK_NEAR(F.derivative(2), d[1], kSplineJetRel, kSplineJetRel);
    CHECK_NEAR(F.derivative(3), d[2], kSplineJetRel, kSplineJetRel);
  }
}

TEST_CASE("spline: rejects misuse") {
  const std::vector<double> x = {0, 1, 2};
  const std::vector<double> y = {0, 1, 0};
  CHECK_NOTHROW(Spline::interpolate(x, y));
  CHECK_THROWS_AS(Spline::interpolate(std::span(x).first(2), std::span(y).first(2)),
                  InputError);
  const std::vector<double> xd = {0, 2, 1};
  CHECK_THROWS_AS(Spline::interpolate(xd, y), InputError);
  CHECK_THROWS_AS(Spline::interpolate(x, std::span(y).first(2)), InputError);
  CHECK_THROWS_WITH(Spline::interpolate(std::span(x).first(2), std::span(y).first(2)),
                    Catch::Contains("Spline::interpolate: 2 points given, at least 3 required"));
  CHECK_THROWS_WITH(Spline::interpolate(x, std::span(y).first(2)),
                    Catch::Contains("Spline::interpolate: x has 3 points but y has 2"));
}

TEST_CASE("value_range: the extremes of a spline, inside its pieces too") {
  // the extreme on a dense scan of the spline refined by golden-section search on it
  auto extreme = [](const auto& f, double from, double to, double sign) {
    constexpr int scan = 20000;
    double best = from;
    for (int k = 0; k <= scan; ++k) {
      const double u = from + (to - from) * k / scan;
      if (sign * f(u) > sign * f(best)) best = u;
    }
    double a = std::max(from, best - (to - from) / scan), b = std::min(to, best + (to - from) / scan);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 200; ++it) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      if (sign * f(c) > sign * f(d)) b = d;
      else a = c;
    }
    return f(0.5 * (a + b));
  };
  // a periodic spline through 2 + cos(u - 0.37) at 40 jittered knots: extremes between knots
  const auto x = grid(40, 0.3, 0.5);
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = 2.0 + std::cos(x[i] - 0.37);
  const auto s = PeriodicSpline::interpolate(x, y, kTwoPi);
  double lo = 0.0, hi = 0.0;
  s.value_range(x.front() + kTwoPi, lo, hi);
  CHECK_REL(hi, extreme(s, x.front(), x.front() + kTwoPi, 1.0), kUlpRel);
  CHECK_REL(lo, extreme(s, x.front(), x.front() + kTwoPi, -1.0), kUlpRel);
  // those of the function to the interpolation error, and not at a knot
  CHECK_ABS(hi, 3.0, kSplineExtremeAbs);
  CHECK_ABS(lo, 1.0, kSplineExtremeAbs);
  CHECK(hi > *std::max_element(y.begin(), y.end()));
  CHECK(lo < *std::min_element(y.begin(), y.end()));
  // a natural spline through sin: its last piece ends at x.back(); the minimum at an end
  const std::vector<double> xn = {0.0, 0.7, 1.3, 2.2, 3.0, 3.9, 4.4};
  std::vector<double> yn(xn.size());
  for (std::size_t i = 0; i < xn.size(); ++i) yn[i] = std::sin(xn[i]);
  const auto n = Spline::interpolate(xn, yn);
  n.value_range(xn.back(), lo, hi);
  CHECK_REL(hi, extreme(n, xn.front(), xn.back(), 1.0), kUlpRel);
  CHECK_REL(lo, extreme(n, xn.front(), xn.back(), -1.0), kUlpRel);
}
