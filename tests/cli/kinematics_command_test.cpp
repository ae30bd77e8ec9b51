// camopt kinematics on a four-bar near its change point with a floating coupler
// (tests/data/kinematics/floating_coupler_four_bar.toml; the closed-form check over a
// revolution is tests/kinematics/branch_test.cpp): whatever outputs are asked for, the run
// stays on the drawing's branch (the rocker is back at its drawing angle after a revolution)
// with the same lift bits, and it is reported near toggle in summary.json and on stderr.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/io/csv.hpp"
#include "cli_support.hpp"

using namespace camopt::test;

namespace {

const std::string kDesign = (source_dir() / "tests/data/kinematics/floating_coupler_four_bar.toml").string();

}  // namespace

TEST_CASE("kinematics: a near-change-point four-bar stays on its branch and is flagged near toggle",
          "[cli][kinematics][branch]") {
  TempDir tmp;
  std::vector<std::vector<double>> lifts;
  for (const std::string outputs : {"lift", "all"}) {
    INFO("--outputs " << outputs);
    const fs::path out = tmp / outputs;
    const RunResult r = run_camopt({"kinematics", kDesign, "--out", out.string(), "--outputs", outputs});
    INFO(r.command << "\n" << r.all());
    REQUIRE(r.exit_code == cli_ok);
    const auto table = camopt::io::read_csv((out / "kinematics.csv").string());
    const auto& cam = table.column("cam_deg");
    const auto& lift = table.column("lift_deg");
    REQUIRE(cam.size() == 73);  // 0 .. 360 deg at the design's 5 deg
    // back at the drawing after a revolution (the crossed branch is 141 deg away there)
    CHECK(cam.back() == 360.0);
    CHECK(std::abs(lift.back()) < 1e-9);
    lifts.push_back(lift);

    const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
    const auto& position = summary["positions"][0];
    CHECK(position["near_toggle"] == true);
    CHECK(position["min_toggle_margin"].get<double>() < 0.02);
    CHECK(position["min_toggle_margin_at_deg"].get<double>() == 180.0);
    CHECK(r.err.find("warning: near a singular configuration") != std::string::npos);
    CHECK(r.err.find(" at 180 deg") != std::string::npos);
  }
  // the same continuation whatever the outputs: the same lift, bit for bit
  CHECK(lifts[0] == lifts[1]);
}

TEST_CASE("kinematics: a comfortable four-bar is not flagged near toggle", "[cli][kinematics][branch]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const RunResult r = run_camopt({"kinematics", (source_dir() / "designs/four_bar.toml").string(), "--out",
                                  out.string(), "--outputs", "lift"});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
  const auto& position = summary["positions"][0];
  CHECK(position["near_toggle"] == false);
  // transmission angles 34.0 .. 81.8 deg (designs/four_bar.toml): sin 34.0 deg
  CHECK(position["min_toggle_margin"].get<double>() == Approx(0.5592).margin(1e-3));
  CHECK(r.err.find("near a singular configuration") == std::string::npos);
}
