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
#include "camopt/core/spline.hpp"
#include "camopt/kinematics/cam_profile.hpp"
#include "support/compare.hpp"
#include "support/tolerances.hpp"

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

// a long table is fitted once per process and later builds copy that fit: the copy must be
// the fit of its own data (the spline through it, to the bit), and a table that differs in
// one value must be fitted anew
TEST_CASE("cam profile: a long table built twice is the same fit, a changed one is fitted anew",
          "[kinematics][profile]") {
  ProfileSpec spec;
  spec.name = "dense";
  spec.form = ProfileForm::polar;
  constexpr int n = 1800;  // 0.2 deg: above the length from which fits are kept
  for (int i = 0; i < n; ++i) {
    const double a = 360.0 * i / n;
    spec.angle_deg.push_back(a);
    spec.radius_mm.push_back(20.0 + 3.0 * std::pow(std::sin(a * camopt::pi / 360.0), 6));
  }
  // the reference: the periodic spline through the same data, fitted here
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i) u[i] = spec.angle_deg[i] * rad_per_deg;
  const PeriodicSpline reference = PeriodicSpline::interpolate(u, spec.radius_mm, 2 * camopt::pi);
  const kin::CamProfile first = kin::CamProfile::build(spec);
  const kin::CamProfile second = kin::CamProfile::build(spec);
  for (int k = 0; k < 997; ++k) {
    const double a = 2 * camopt::pi * k / 997.0;
    CHECK(first.radius_at(a) == reference(a));
    CHECK(second.radius_at(a) == reference(a));
  }
  // one radius moved by 0.01 mm: the new profile passes through the new value
  ProfileSpec changed = spec;
  changed.radius_mm[900] += 0.01;
  const kin::CamProfile moved = kin::CamProfile::build(changed);
  // (the radius is ~23 mm: the node tolerance of a spline of size 1, scaled)
  const double node_abs = test::tol::kSplineNodeAbs * 23.0;
  const auto at_new = test::compare_abs("changed table at its moved point [mm]", moved.radius_at(u[900]),
                                        changed.radius_mm[900], node_abs);
  INFO(at_new.describe());
  CHECK(at_new.pass);
  const auto at_old = test::compare_abs("first table at that point [mm]", kin::CamProfile::build(spec).radius_at(u[900]),
                                        spec.radius_mm[900], node_abs);
  INFO(at_old.describe());
  CHECK(at_old.pass);
}
