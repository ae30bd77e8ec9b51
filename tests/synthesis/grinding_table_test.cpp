// the grinding table against closed forms: an eccentric disc under a master roller and
// under a flat master; bad arguments are input errors.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "camopt/synthesis/envelope.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::kin_test;

TEST_CASE("synthesis: grinding table of an eccentric disc with a master roller matches the closed form",
          "[synthesis][export]") {
  const double R = 20, e = 4, master = 12;
  const ProfileSpec disc = eccentric_profile("disc", R, e);
  std::vector<double> a, lift;
  REQUIRE(synthesis::grinding_table(disc, master, 0.5, a, lift).ok());
  REQUIRE(a.size() == 720);
  std::vector<double> exact;
  for (std::size_t i = 0; i < a.size(); ++i) {
    // master centre on +x at d: |(d, 0) - e (cos t, sin t)| = R + master
    const double t = a[i] * deg;
    const double d = e * std::cos(t) + std::sqrt((R + master) * (R + master) - e * e * std::sin(t) * std::sin(t));
    exact.push_back(d - (R + master - e));
  }
  CHECK_SERIES(test::compare_series("master roller lift [mm]", lift, exact, {.abs = test::tol::kGrindingLiftAbs}, a,
                                    "cam [deg]"));
  // a flat master: d = R + e cos t (support function of the disc)
  REQUIRE(synthesis::grinding_table(disc, 0.0, 0.5, a, lift).ok());
  exact.clear();
  for (std::size_t i = 0; i < a.size(); ++i) exact.push_back(e * std::cos(a[i] * deg) + e);
  CHECK_SERIES(test::compare_series("flat master lift [mm]", lift, exact, {.abs = test::tol::kGrindingLiftAbs}, a,
                                    "cam [deg]"));
}

TEST_CASE("synthesis: a grinding table with a negative master radius or a step outside (0, 360) deg is an input error",
          "[synthesis][export]") {
  const ProfileSpec disc = eccentric_profile("disc", 20, 4);
  std::vector<double> a, lift;
  CHECK_THROWS_WITH((void)synthesis::grinding_table(disc, -1.0, 0.5, a, lift),
                    Catch::Contains("grinding table master_radius_mm = -1 mm must be finite and >= 0"));
  CHECK_THROWS_AS((void)synthesis::grinding_table(disc, -1.0, 0.5, a, lift), InputError);
  for (const double step : {0.0, -0.5, 360.0}) {
    CHECK_THROWS_AS((void)synthesis::grinding_table(disc, 12.0, step, a, lift), InputError);
    CHECK_THROWS_WITH((void)synthesis::grinding_table(disc, 12.0, step, a, lift),
                      Catch::Contains("grinding table step_deg = " + format_value(step) + " cam deg must be > 0 and < 360"));
  }
}
