// Dual's exp, log and pow: values bit-identical to std, derivatives in closed
// form along every direction and against central differences.
#include <catch2/catch.hpp>

#include <cmath>

#include "camopt/core/dual.hpp"
#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

using camopt::Dual;

namespace {

using namespace camopt::test::tol;

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
      CHECK_REL(e.d[k], std::exp(x0) * dx, kUlpRel);
      CHECK_REL(l.d[k], dx / x0, kUlpRel);
      CHECK_REL(p.d[k], 0.7 * std::pow(x0, -0.3) * dx, kUlpRel);
      CHECK_REL(q.d[k], -0.13 * std::pow(x0, -1.13) * dx, kUlpRel);
    }
    using camopt::oracles::central_difference;
    const double h = 1e-3;
    CHECK_REL(e.d[0], central_difference([](double t) { return std::exp(t); }, x0, 1, 4, h), kCentral8Step1e3Rel);
    CHECK_REL(l.d[0], central_difference([](double t) { return std::log(t); }, x0, 1, 4, h), kCentral8Step1e3Rel);
    CHECK_REL(p.d[0], central_difference([](double t) { return std::pow(t, 0.7); }, x0, 1, 4, h), kCentral8Step1e3Rel);
    // composed: exp(0.7 log x) is x^0.7 with the same derivatives
    const Dual<2> c = exp(0.7 * log(x));
    CHECK_REL(c.v, p.v, kUlpRel);
    CHECK_REL(c.d[1], p.d[1], kUlpRel);
  }
  // pow at 0: value 0, derivative 0 for an exponent above 1
  const Dual<2> z = pow(seeded(0.0), 2.5);
  CHECK(z.v == 0.0);
  CHECK(z.d[0] == 0.0);
}
