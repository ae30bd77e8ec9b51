// the contact solver on a real, measured-looking polar table (MBSim's cam_contact contour,
// offset polar origin) against an independent brute-force formulation of the roller lift:
// the roller centre height is the largest height at which the roller still touches the cam,
//   y_c(theta) = max over phi with |P_x| <= r of  P_y(phi) + sqrt(r^2 - P_x(phi)^2),
// P(phi) the rotated profile point; found by a dense scan refined by golden section.
#include <catch2/catch.hpp>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::test::tol;
using camopt::test::ScalarCompare;

namespace {

double touching_height(const kin::CamProfile& prof, double theta, double roller, double ox, double oy) {
  auto height = [&](double phi) {
    const auto c = prof.point(phi);  // profile frame, polar origin at (ox, oy) on the cam
    const double bx = ox + c.x, by = oy + c.y;
    const double px = std::cos(theta) * bx - std::sin(theta) * by;
    const double py = std::sin(theta) * bx + std::cos(theta) * by;
    if (std::abs(px) > roller) return -1e300;
    return py + std::sqrt(roller * roller - px * px);
  };
  constexpr int samples = 20000;
  int best = 0;
  double best_h = -1e300;
  for (int i = 0; i < samples; ++i) {
    const double h = height(2 * camopt::pi * i / samples);
    if (h > best_h) best_h = h, best = i;
  }
  // golden-section refinement of the maximum
  double a = 2 * camopt::pi * (best - 1) / samples, b = 2 * camopt::pi * (best + 1) / samples;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  for (int it = 0; it < 100; ++it) {
    if (height(c) > height(d)) b = d;
    else a = c;
    c = b - g * (b - a);
    d = a + g * (b - a);
  }
  return height(0.5 * (a + b));
}
}  // namespace

TEST_CASE("roller lift on the MBSim polar contour matches a brute-force envelope", "[kinematics][real]") {
  const auto spec = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/tests/data/kinematics/mbsim_roller.toml");
  const auto mech = kin::compile(spec);
  REQUIRE(mech.profiles.size() == 1);
  // the table is 361 rows with the 0-deg point repeated at 360 deg: the repeat is dropped
  CHECK_ABS(mech.profiles[0].base_radius_mm(), 22.0, kPrintedRadiusAbs);
  CHECK_ABS(mech.profiles[0].max_radius_mm(), 26.517, kPrintedMaxRadiusAbs);
  kin::Workspace ws(mech);
  const int follower = mech.nodes[mech.output_node].first_variable;
  ScalarCompare lift("follower centre height [mm]");
  for (int i = 0; i <= 720; ++i) {
    const double theta = i * camopt::pi / 360.0;
    const auto st = kin::solve(mech, ws, theta, {3, true});
    REQUIRE(st.ok());
    const double centre = 45.0 + ws.vars[follower].value();
    const double expected = touching_height(mech.profiles[0], theta, 10.0, 3.0, 10.0);
    lift.add(theta, centre, expected);
  }
  CHECK_SERIES(lift.compare(0.0, kBruteForceLiftAbs));
}
