// optimize --verify as a verdict: a bundled set verified by the kinematic, rigid and flexible
// models; a design made to separate fails with its own exit code, a stderr table and
// "verified": false while its outputs are still written; a set that disagrees with its
// design's loads is an input error naming both files.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_support.hpp"
#include "support/compare.hpp"

using namespace camopt::test;

namespace {

const fs::path kBucket = source_dir() / "designs/bucket_tappet.toml";
const fs::path kBucketSet = source_dir() / "constraints/high_speed_bucket.toml";

}  // namespace

TEST_CASE("optimize --verify: the high-speed bucket set is verified at 9000 rpm", "[cli][opt][verify]") {
  TempDir tmp;
  const auto r = run_camopt({"optimize", kBucket.string(), "--constraints", kBucketSet.string(), "--out",
                             (tmp / "out").string(), "--verify"});
  INFO(r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto report = nlohmann::json::parse(read_file(tmp / "out/report.json"));
  CHECK(report["verified"] == true);
  int rigid = 0, flexible = 0;
  for (const auto& c : report["verification"]) {
    INFO(c.dump());
    CHECK(c["passed"] == true);
    rigid += c["model"] == "rigid";
    flexible += c["model"] == "flexible";
  }
  CHECK(rigid >= 2);     // separation of the cam contact, spring margin
  CHECK(flexible >= 2);  // separations while driven, coil clashes
  const auto& flex = report["verify"]["flexible_dynamics"];
  CHECK(flex["rpm"].get<double>() == 9000.0);
  CHECK(flex["connections"]["cam_tappet"]["separations_while_driven"] == 0);
  // the flexible run's kinematic lift is its path on the 0.5 deg output grid; the kinematic
  // verification's peak is refined between the grid points
  CHECK_ABS(flex["max_lift_kinematic_mm"].get<double>(), report["verify"]["kinematics"]["max_lift_mm"].get<double>(),
            tol::kVerifyPeakLiftAbs);
  CHECK(report["loads"]["source"].get<std::string>().find("the design's rigid model") == 0);
}

TEST_CASE("optimize --verify: a design made to separate exits 5 with a table and verified false, outputs written",
          "[cli][opt][verify]") {
  TempDir tmp;
  // the EHL study rig's soft spring (12.6 N, 7.13 N/mm) on the bucket, and a set without the
  // separation and margin rows: the optimiser converges, the design leaves the cam at speed
  std::string design = read_file(kBucket);
  design = std::regex_replace(design, std::regex("rate_N_per_mm = 40\n"), "rate_N_per_mm = 7.13\n");
  design = std::regex_replace(design, std::regex("preload_N = 214\n"), "preload_N = 12.6\n");
  design = std::regex_replace(design, std::regex("file = \"profiles/"), "file = \"" + (source_dir() / "designs/profiles/").string());
  write_text(tmp / "rig.toml", design);
  std::string set = read_file(kBucketSet);
  set = std::regex_replace(set, std::regex("min_separation_speed_rpm[^\n]*\n|min_spring_margin[^\n]*\n"), "");
  write_text(tmp / "set.toml", set);
  const auto r = run_camopt({"optimize", (tmp / "rig.toml").string(), "--constraints", (tmp / "set.toml").string(),
                             "--out", (tmp / "out").string(), "--verify"});
  INFO(r.all());
  CHECK(r.exit_code == cli_verification_failed);
  CHECK(r.err.find("fails its checks") != std::string::npos);
  CHECK(std::regex_search(r.err, std::regex("rigid +separation speed of cam_tappet +[0-9.]+ rpm +>= 9000 rpm")));
  for (const char* f : {"lift.csv", "profile.csv", "report.json", "design.toml"}) CHECK(fs::exists(tmp / "out" / f));
  const auto report = nlohmann::json::parse(read_file(tmp / "out/report.json"));
  CHECK(report["status"] == "converged");
  CHECK(report["verified"] == false);
  bool rigid_failed = false;
  for (const auto& c : report["verification"])
    if (c["model"] == "rigid" && c["passed"] == false) {
      rigid_failed = true;
      CHECK(c["value"].get<double>() < 9000.0);
      CHECK(c["limit"].get<double>() == 9000.0);
    }
  CHECK(rigid_failed);
}

TEST_CASE("optimize: a set whose [load] disagrees with its design exits 3 naming both files", "[cli][opt][verify]") {
  TempDir tmp;
  std::string set = read_file(source_dir() / "constraints/passenger_car_intake.toml");
  set += "\n[load]\nspring_preload_N = 230\nspring_rate_N_per_mm = 35\nmoving_mass_kg = 0.08\n";
  write_text(tmp / "set.toml", set);
  const auto r = run_camopt({"optimize", (source_dir() / "designs/roller_finger_follower.toml").string(), "--constraints",
                             (tmp / "set.toml").string(), "--out", (tmp / "out").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(std::regex_search(r.err, std::regex("set\\.toml:[0-9]+:[0-9]+: load\\.spring_preload_N: value 230 N disagrees")));
  CHECK(r.err.find("roller_finger_follower.toml:") != std::string::npos);
  CHECK(r.err.find("override_design") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("optimize: set controls on a design without them is an input error", "[cli][opt]") {
  TempDir tmp;
  std::string set = read_file(source_dir() / "constraints/passenger_car_intake.toml");
  set.replace(set.find("[set]\n"), 6, "[set]\ncontrols = [8.0]\n");
  write_text(tmp / "set.toml", set);
  const auto r = run_camopt({"optimize", (source_dir() / "designs/roller_finger_follower.toml").string(), "--constraints",
                             (tmp / "set.toml").string(), "--out", (tmp / "out").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("set.controls: 1 value(s) given, but the design") != std::string::npos);
  CHECK(r.err.find("has 0 [[control]]") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
}
