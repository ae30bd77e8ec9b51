// a synthesized profile reaches kinematics and dynamics through profile.csv: written and
// read back it must be the profile in memory, so the valve acceleration (and the contact
// force that follows from it) is the same to round-off.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

using camopt::pi;

// the valve acceleration [mm/deg^2] over one revolution at 0.05 deg
std::vector<double> valve_acceleration(const DesignSpec& design) {
  const kin::Mechanism m = kin::compile(design);
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = 0.05;
  spec.control_positions = {m.default_controls()};
  spec.request.derivative_order = 2;
  const kin::SweepResult r = kin::sweep(m, spec);
  REQUIRE(r.positions.front().status.ok());
  const int out = m.nodes[m.output_node].first_variable;
  std::vector<double> acc;
  for (std::size_t i = 0; i < r.driver.size(); ++i) acc.push_back(r.positions.front().value(i, out, 2));
  return acc;
}

// the profile's polar table through CSV text: as format_csv writes it, or (digits > 0) as a
// %.*g format with that many significant digits would
ProfileSpec read_back(const ProfileSpec& profile, int digits) {
  std::string text = io::format_csv({"angle_deg", "radius_mm"}, {profile.angle_deg, profile.radius_mm});
  if (digits > 0) {
    text = "angle_deg,radius_mm\n";
    char row[80];
    for (std::size_t i = 0; i < profile.angle_deg.size(); ++i) {
      std::snprintf(row, sizeof row, "%.*g,%.*g\n", digits, profile.angle_deg[i], digits, profile.radius_mm[i]);
      text += row;
    }
  }
  const io::CsvTable table = io::parse_csv(text, "profile.csv");
  ProfileSpec out = profile;
  out.angle_deg = table.values[0];
  out.radius_mm = table.values[1];
  return out;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

TEST_CASE("synthesis: a 36000-point profile read back from its CSV gives the valve acceleration of the profile "
          "in memory",
          "[synthesis][precision]") {
  const DesignSpec design = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/roller_finger_follower.toml");
  const io::AngleTable target = io::read_angle_table(
      io::read_csv(std::string(CAMOPT_SOURCE_DIR) + "/designs/targets/rff_intake_lift.csv"), {"lift_mm"});
  std::vector<double> cam_rad;
  for (const double a : target.angle_deg) cam_rad.push_back(a * pi / 180.0);
  const PeriodicSpline lift = PeriodicSpline::interpolate(cam_rad, target.value, 2 * pi);
  synthesis::SynthesisOptions options;
  options.points = options.samples = 36000;
  synthesis::SynthesisResult result;
  REQUIRE(synthesis::synthesize(design, lift, options, result).ok());
  REQUIRE(result.profile.angle_deg.size() >= 36000);

  const std::vector<double> memory = valve_acceleration(synthesis::with_profile(design, result.profile));
  const double scale = *std::max_element(memory.begin(), memory.end());
  const double tolerance = tol::kReadBackProfileRel * scale;
  const std::vector<double> full = valve_acceleration(synthesis::with_profile(design, read_back(result.profile, 0)));
  const double twelve =
      max_difference(memory, valve_acceleration(synthesis::with_profile(design, read_back(result.profile, 12))));
  INFO("peak acceleration " << scale << " mm/deg^2; read back with 12 digits: " << twelve);
  CHECK_SERIES(test::compare_series("valve acceleration read back from the shortest text [mm/deg^2]", full, memory,
                                    {.abs = tolerance}));
  // the check can fail: 12 significant digits move the acceleration by far more
  CHECK(twelve > 1e3 * tolerance);
}
