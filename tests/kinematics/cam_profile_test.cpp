// an xy cam profile (points traced around the cam centre, interpolated by chord length)
// against the same cam given as an exact circle: the eccentric disc of
// designs/eccentric_offset_roller.toml sampled at N points must give the disc's lift under
// the offset roller to the interpolation's O(h^4) accuracy (or better).
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "support/compare.hpp"

using namespace camopt;

namespace {

std::string bundled_text() {
  std::ifstream in(std::string(CAMOPT_SOURCE_DIR) + "/designs/eccentric_offset_roller.toml");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// the design with its disc (radius 20 mm, centre 4 mm along +x of the profile frame) given
// as `n` xy points at equal polar angles about the cam centre
std::string with_xy_disc(const std::string& text, int n) {
  const std::string disc = "form = \"eccentric\"\ndisc_radius_mm = 20\neccentricity_mm = 4\n";
  const std::size_t at = text.find(disc);
  REQUIRE(at != std::string::npos);
  std::ostringstream x, y;
  x.precision(17);
  y.precision(17);
  for (int i = 0; i < n; ++i) {
    // the ray at polar angle phi meets the circle |p - (4, 0)| = 20 at r = 4 cos + sqrt(400 - 16 sin^2)
    const double phi = 2 * camopt::pi * i / n;
    const double r = 4 * std::cos(phi) + std::sqrt(400 - 16 * std::sin(phi) * std::sin(phi));
    x << (i ? ", " : "") << r * std::cos(phi);
    y << (i ? ", " : "") << r * std::sin(phi);
  }
  return text.substr(0, at) + "form = \"xy\"\nx_mm = [" + x.str() + "]\ny_mm = [" + y.str() + "]\n" +
         text.substr(at + disc.size());
}

// the valve lift over one revolution at 1 deg steps
std::vector<double> lift_of(const std::string& text) {
  const kin::Mechanism m = kin::compile(io::parse_design(text, "xy_test.toml", std::string(CAMOPT_SOURCE_DIR) + "/designs"));
  kin::SweepSpec spec;
  spec.step = 1.0;
  const kin::SweepResult r = kin::sweep(m, spec);
  REQUIRE(r.positions[0].status.ok());
  const int out = m.nodes[static_cast<std::size_t>(m.output_node)].first_variable;
  std::vector<double> lift;
  for (std::size_t i = 0; i < r.driver.size(); ++i) lift.push_back(r.positions[0].value(i, out, 0));
  return lift;
}

}  // namespace

TEST_CASE("xy profile: an eccentric disc given as points gives the exact disc's lift to O(h^4)", "[kinematics][xy]") {
  const std::string text = bundled_text();
  const std::vector<double> exact = lift_of(text);
  double max_lift = 0.0;
  for (double v : exact) max_lift = std::max(max_lift, v);
  REQUIRE_ABS(max_lift, 8.047, camopt::test::tol::kPrintedLiftAbs);  // the design's documented max lift

  double previous = 0.0;
  for (int n : {24, 48, 96}) {
    const std::vector<double> lift = lift_of(with_xy_disc(text, n));
    REQUIRE(lift.size() == exact.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < lift.size(); ++i) worst = std::max(worst, std::abs(lift[i] - exact[i]));
    INFO(n << " points: largest lift difference " << worst << " mm");
    // O(h^4) at least (the periodic cubic spline on the chord length; measured: 1.4e-6,
    // 2.0e-8, 3.0e-10 mm, about 2^6 per halving on this smooth closed curve)
    CHECK_SERIES(camopt::test::compare_series(std::to_string(n) + "-point contour lift [mm]", lift, exact,
                                              {.abs = camopt::test::tol::kChordSpline24Abs * std::pow(24.0 / n, 4)}));
    if (previous > 0.0) CHECK(worst < previous / 16.0);
    previous = worst;
  }
}
