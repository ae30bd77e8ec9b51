// camopt kinematics: the summary keys and numbers (durations at chosen heights against the
// closed form of tests/data/cli/eccentric_flat.toml, lift = 5 sin(theta) mm), the cam
// surfaces named by contact and profile, and the option's input errors.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "cli/cli_support.hpp"
#include "support/compare.hpp"

using namespace camopt::test;

namespace {

constexpr double kE = 5.0;  // eccentricity of eccentric_flat.toml [mm]: lift 5 sin(theta)

std::string flat_design() { return (source_dir() / "tests" / "data" / "cli" / "eccentric_flat.toml").string(); }
std::string bundled(const std::string& name) { return (source_dir() / "designs" / name).string(); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// the closed-form duration of 5 sin(theta) above h [cam deg]
double duration(double h_mm) { return 180.0 - 2.0 * std::asin(h_mm / kE) * 180.0 / camopt::pi; }

// run kinematics and return the first position of summary.json
nlohmann::json run_summary(const std::vector<std::string>& extra, std::string* err = nullptr) {
  TempDir tmp;
  const fs::path out = tmp / "out";
  std::vector<std::string> args = extra;
  args.insert(args.begin() + 2, {"--out", out.string()});
  const auto r = run_camopt(args);
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  if (err) *err = r.err;
  return nlohmann::json::parse(read_file(out / "summary.json"))["positions"][0];
}

const nlohmann::json& surface(const nlohmann::json& list, const std::string& contact, const std::string& name) {
  for (const auto& s : list)
    if (s["contact"] == contact && s["surface"] == name) return s;
  FAIL("no surface " << name << " at contact " << contact << " in " << list.dump());
  return list;
}

}  // namespace

TEST_CASE("kinematics summary: durations at 1 and 0.1 mm by default, refined to the closed form",
          "[cli][kinematics][summary]") {
  const auto j = run_summary({"kinematics", flat_design(), "--step", "5"});
  INFO(j.dump(1));
  REQUIRE(j.contains("duration_at_1mm_cam_deg"));
  REQUIRE(j.contains("duration_at_0.1mm_cam_deg"));
  CHECK_FALSE(j.contains("duration_at_1mm_deg"));
  CHECK_REL(j["duration_at_1mm_cam_deg"].get<double>(), duration(1.0), tol::kRefinedSummaryRel);
  CHECK_REL(j["duration_at_0.1mm_cam_deg"].get<double>(), duration(0.1), tol::kRefinedSummaryRel);
  CHECK_REL(j["max_lift_mm"].get<double>(), kE, tol::kRefinedSummaryRel);
  // every lift value is refined; nothing here is a grid value but the solver's conditioning
  CHECK(j["grid_values"].size() == 2);
  CHECK(j["grid_values"][0] == "max_condition_number");
  CHECK(j["grid_values"][1] == "min_toggle_margin");
  CHECK(j["notes"].empty());
}

TEST_CASE("kinematics summary: --duration-at heights in mm and inches name their height and unit in the keys",
          "[cli][kinematics][summary]") {
  std::string err;
  const auto j = run_summary({"kinematics", flat_design(), "--step", "5", "--duration-at", "0.040in,0.004in,2,0.5mm"},
                             &err);
  INFO(j.dump(1));
  for (const auto& [key, h] : std::vector<std::pair<std::string, double>>{{"duration_at_0.04in_cam_deg", 1.016},
                                                                          {"duration_at_0.004in_cam_deg", 0.1016},
                                                                          {"duration_at_2mm_cam_deg", 2.0},
                                                                          {"duration_at_0.5mm_cam_deg", 0.5}}) {
    INFO(key);
    REQUIRE(j.contains(key));
    CHECK_REL(j[key].get<double>(), duration(h), tol::kRefinedSummaryRel);
  }
  CHECK_FALSE(j.contains("duration_at_1mm_cam_deg"));
  // the terminal line carries the same numbers
  CHECK(contains(err, "at 0.04in"));
  CHECK(contains(err, "at 0.5mm"));
}

TEST_CASE("kinematics summary: a bad --duration-at is an input error naming the option and the value",
          "[cli][kinematics][summary]") {
  for (const auto& [value, says] : std::vector<std::pair<std::string, std::string>>{
           {"0", "'0'"},
           {"-1", "'-1'"},
           {"1furlong", "unknown unit 'furlong'"},
           {"0.040 in", "unknown unit ' in'"},
           {"mm", "'mm'"},
           {"1,,2", "''"},
           {"1,1mm", "twice"},
           {"nan", "nan"},
           {"1e999", "1e999"},
           {"5.5", "not below the maximum lift 5"},
           {"0.25in", "not below the maximum lift"}}) {
    TempDir tmp;
    const fs::path out = tmp / "out";
    const auto r = run_camopt({"kinematics", flat_design(), "--out", out.string(), "--duration-at", value});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(contains(r.err, "--duration-at"));
    CHECK(contains(r.err, says));
    CHECK(files_under(out).empty());
  }
}

TEST_CASE("kinematics summary: the RFF's cam radius is the lobe's, the finger pad is a follower surface",
          "[cli][kinematics][summary]") {
  std::string err;
  const auto j = run_summary({"kinematics", bundled("roller_finger_follower.toml"), "--step", "1", "--outputs",
                              "lift,contacts"},
                             &err);
  INFO(j.dump(1));
  CHECK_FALSE(j.contains("min_cam_radius_of_curvature_mm"));
  const auto& lobe = surface(j["cam_surfaces"], "cam_roller", "lobe");
  CHECK(lobe["body"] == "cam");
  const double r = lobe["min_convex_radius_mm"].get<double>();
  CHECK(r > 13.0);  // the lobe's nose, not the 12 mm pad
  CHECK(r < 14.5);
  CHECK(j["min_convex_cam_radius_mm"].get<double>() == r);
  CHECK(j["min_convex_cam_radius_contact"] == "cam_roller");
  CHECK(surface(j["follower_surfaces"], "pad_valve", "circle")["min_convex_radius_mm"].get<double>() == 12.0);
  CHECK(surface(j["follower_surfaces"], "cam_roller", "roller")["min_convex_radius_mm"].get<double>() == 8.5);
  // the contact extremes are refined between the grid points: only the condition number and
  // the toggle margin are grid values
  const auto& grid = j["grid_values"];
  CHECK(grid == nlohmann::json({"max_condition_number", "min_toggle_margin"}));
  CHECK(contains(err, "min convex cam radius"));
  CHECK(contains(err, "(cam_roller: lobe)"));
}

TEST_CASE("kinematics summary: the CVVL swing cam's concave foot and the lash opening are reported",
          "[cli][kinematics][summary]") {
  std::string err;
  // at 1 deg the grid meets -14.83 mm; the refined foot is the 0.01 deg grid's -14.701 mm
  const auto j = run_summary({"kinematics", bundled("cvvl_swing_cam.toml"), "--step", "1", "--outputs",
                              "lift,contacts"},
                             &err);
  INFO(j.dump(1));
  const auto& swing = surface(j["cam_surfaces"], "swing_roller", "swing_cam");
  CHECK(swing["body"] == "swing");
  CHECK_ABS(swing["sharpest_concave_radius_mm"].get<double>(), -14.701, tol::kPrintedRadiusAbs);
  const auto& grid = j["grid_values"];
  CHECK(std::find(grid.begin(), grid.end(), "cam_surfaces") == grid.end());
  CHECK(contains(err, "sharpest concave cam radius"));
  CHECK(contains(err, "(swing_roller: swing_cam)"));
  // the pad/valve lash opens while the roller is on the dwell; the spans add up
  REQUIRE(j["separations"].size() == 1);
  const auto& sep = j["separations"][0];
  CHECK(sep["contact"] == "pad_valve");
  double total = 0.0;
  for (const auto& iv : sep["open_intervals_deg"]) total += iv[1].get<double>() - iv[0].get<double>();
  CHECK_ABS(total, sep["open_span_deg"].get<double>(), tol::kIntervalSumAbs);
  CHECK(sep["open_span_deg"].get<double>() > 0.0);
}
