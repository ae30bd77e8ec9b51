// camopt dynamics --model rigid end to end: files written, columns with units, one row per
// (rpm, control, cam angle), the summary's fields, bad input and the flexible stub.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli/cli_support.hpp"

using namespace camopt::test;

namespace {
bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("camopt dynamics --model rigid writes dynamics.csv and summary.json", "[dynamics][cli]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/cvvl_swing_cam.toml").string(), "--model", "rigid",
                             "--rpm", "3000,6000", "--control", "0:16:2", "--step", "2", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto lines = split_lines(read_file(out / "dynamics.csv"));
  REQUIRE(lines.size() == 1 + 2 * 2 * 181);
  const std::string& header = lines[0];
  for (const char* column : {"rpm,control_deg,cam_deg,crank_deg,lift_mm", "contact_cam_roller_force_N",
                             "contact_swing_roller_hertz_MPa", "contact_pad_valve_sliding_m_per_s", "cam_torque_Nm",
                             "spring_valve_spring_margin_N", "spring_swing_torsion_spring_margin_Nm",
                             "node_finger_reaction_N", "node_valve_guide_N"})
    CHECK(has(header, column));
  CHECK_FALSE(has(read_file(out / "dynamics.csv"), "nan"));
  // the last row: 6000 rpm, control 16, cam 360
  CHECK(lines.back().rfind("6000,16,360,720,", 0) == 0);

  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  REQUIRE(j["results"].size() == 4);
  const auto& first = j["results"][0];
  CHECK(first["rpm"] == 3000.0);
  CHECK(first["control_deg"] == 0.0);
  CHECK(first["connections"]["cam_roller"]["max_force_N"].get<double>() > 0.0);
  CHECK(first["connections"]["cam_roller"]["max_hertz_MPa"].get<double>() > 0.0);
  CHECK(first["springs"]["valve_spring"].contains("min_margin_N"));
  CHECK(first.contains("max_cam_torque_Nm"));
  REQUIRE(j["separation"].size() == 2);
  const auto& sep = j["separation"][0]["contacts"]["pad_valve"]["separation_rpm"];
  REQUIRE(sep.is_number());
  // the valve train stays closed at 3000 rpm: its separation speed lies above
  CHECK(sep.get<double>() > 3000.0);
}

TEST_CASE("camopt dynamics: missing mass is an input error naming the field",
          "[dynamics][cli]") {
  TempDir tmp;
  std::string text = read_file(source_dir() / "designs/bucket_tappet.toml");
  text = std::regex_replace(text, std::regex("mass_kg = 0.0573[^\n]*\n"), "\n");
  text = std::regex_replace(text, std::regex("file = \"profiles/"), "file = \"" + (source_dir() / "designs/profiles/").string());
  const fs::path design = tmp / "no_mass.toml";
  write_text(design, text);
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", design.string(), "--rpm", "3000", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(has(r.err, "node 'tappet': mass_kg is required"));
  CHECK((!fs::exists(out) || fs::is_empty(out)));
}

TEST_CASE("camopt dynamics --model flexible: valve motion, seat, surge and an rpm map", "[dynamics][cli]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/cvvl_swing_cam.toml").string(), "--model",
                             "flexible", "--rpm", "2000,6000", "--step", "1", "--revolutions", "2", "--out",
                             out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string csv = read_file(out / "dynamics.csv");
  CHECK(csv.find("nan") == std::string::npos);
  const auto lines = split_lines(csv);
  for (const char* column : {"lift_kinematic_mm", "lift_mm", "lift_loss_mm", "contact_pad_valve_force_N",
                             "contact_pad_valve_friction_W", "seat_force_N", "cam_torque_Nm",
                             "node_finger_deformation_deg", "node_valve_deformation_mm",
                             "spring_valve_spring_retainer_N", "spring_valve_spring_seat_N"})
    CHECK(has(lines[0], column));
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  REQUIRE(j["results"].size() == 2);
  REQUIRE(j["speed_map"].size() == 2);
  for (const auto& res : j["results"]) {
    // the valve opens within a few percent of the kinematic lift, seats once per revolution
    CHECK(res["max_lift_mm"].get<double>() == Approx(res["max_lift_kinematic_mm"].get<double>()).epsilon(0.05));
    CHECK(res["seating_velocity_m_per_s"].is_number());
    CHECK(res["springs"]["valve_spring"]["surge_amplitude_N"].get<double>() >= 0.0);
    CHECK(res["springs"]["valve_spring"]["segments"] == 5);
  }
}

TEST_CASE("camopt dynamics --contacts compliant integrates mode (b) and lists its events", "[dynamics][cli]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/bucket_tappet.toml").string(), "--rpm", "2000",
                             "--contacts", "compliant", "--step", "2", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto lines = split_lines(read_file(out / "dynamics.csv"));
  REQUIRE(lines.size() == 1 + 181);
  for (const char* column : {"contact_cam_tappet_force_N", "contact_cam_tappet_rigid_force_N",
                             "contact_cam_tappet_hertz_MPa", "node_tappet_deviation_mm"})
    CHECK(has(lines[0], column));
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  REQUIRE(j["results"].size() == 1);
  CHECK(j["results"][0]["events"].is_array());
  // 2000 rpm is well below this design's separation speed (3728 rpm): the contact stays closed
  CHECK(j["results"][0]["events"].empty());
  CHECK(j["results"][0]["connections"]["cam_tappet"]["min_force_N"].get<double>() > 0.0);
}
