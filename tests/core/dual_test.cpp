// Dual's exp, log and pow: values bit-identical to std, derivatives in closed
// form along every direction and against central differences.
#include <catch2/catch.hpp>

#include <cmath>

#include "camopt/core/dual.hpp"
#include "oracles/finite_difference.hpp"

using camopt::Dual;

namespace {

constexpr double kRoundOff = 1e-15;
// 8th-order central differences (half-width 4) at step 1e-3: truncation ~1e-24 x the 9th
// derivative, round-off ~1e-13
constexpr double kDifference = 1e-11;

// x carrying the directions (1, 0) and (0, 2): x = x0 + s + 2 t
Dual<2> seeded(double x0) {
  Dual<2> x(x0);
  x.d = {1.0, 2.0};
  return x;
}

}  // namespace

TEST_CASE("Dual: exp, log and pow by the chain rule along every direction", "[kinematics][dual]") {
  using std::exp;
  using std::log;
  using std::pow;
  for (const double x0 : {0.37, 1.0, 2.9}) {
    INFO("x0 " << x0);
    const Dual<2> x = seeded(x0);
    const Dual<2> e = exp(x), l = log(x), p = pow(x, 0.7), q = pow(x, -0.13);
    CHECK(e.v == std::exp(x0));
    CHECK(l.v == std::log(x0));
    CHECK(p.v == std::pow(x0, 0.7));
    CHECK(value(q) == std::pow(x0, -0.13));
    for (int k = 0; k < 2; ++k) {
      const double dx = x.d[k];
      CHECK(e.d[k] == Approx(std::exp(x0) * dx).epsilon(kRoundOff));
      CHECK(l.d[k] == Approx(dx / x0).epsilon(kRoundOff));
      CHECK(p.d[k] == Approx(0.7 * std::pow(x0, -0.3) * dx).epsilon(kRoundOff));
      CHECK(q.d[k] == Approx(-0.13 * std::pow(x0, -1.13) * dx).epsilon(kRoundOff));
    }
    using camopt::oracles::central_difference;
    const double h = 1e-3;
    CHECK(e.d[0] == Approx(central_difference([](double t) { return std::exp(t); }, x0, 1, 4, h)).epsilon(kDifference));
    CHECK(l.d[0] == Approx(central_difference([](double t) { return std::log(t); }, x0, 1, 4, h)).epsilon(kDifference));
    CHECK(p.d[0] ==
          Approx(central_difference([](double t) { return std::pow(t, 0.7); }, x0, 1, 4, h)).epsilon(kDifference));
    // composed: exp(0.7 log x) is x^0.7 with the same derivatives
    const Dual<2> c = exp(0.7 * log(x));
    CHECK(c.v == Approx(p.v).epsilon(kRoundOff));
    CHECK(c.d[1] == Approx(p.d[1]).epsilon(kRoundOff));
  }
  // pow at 0: value 0, derivative 0 for an exponent above 1
  const Dual<2> z = pow(seeded(0.0), 2.5);
  CHECK(z.v == 0.0);
  CHECK(z.d[0] == 0.0);
}
