// camopt dynamics --model rigid end to end: files written, columns with units, one row per
// (rpm, control, cam angle), the summary's fields, bad input and the flexible stub.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "camopt/core/units.hpp"
#include "cli/cli_support.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

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

namespace {
// the columns of a CSV by name
std::map<std::string, std::vector<double>> columns_of(const std::string& csv) {
  const auto lines = split_lines(csv);
  std::vector<std::string> names;
  std::stringstream head(lines[0]);
  for (std::string n; std::getline(head, n, ',');) names.push_back(n);
  std::map<std::string, std::vector<double>> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::stringstream row(lines[i]);
    std::size_t k = 0;
    for (std::string v; std::getline(row, v, ','); ++k) out[names[k]].push_back(std::stod(v));
  }
  return out;
}
}  // namespace

TEST_CASE("camopt dynamics --model flexible: valve motion, seat, surge and an rpm map", "[dynamics][cli]") {
  // two revolutions are too few for the CVVL's periodic steady state: the run says so
  const ExpectWarnings two_revolutions{"no periodic steady state"};
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
  // the CSV's rows of one speed (one reported revolution each)
  const auto c = columns_of(csv);
  for (const auto& res : j["results"]) {
    const double rpm = res["rpm"].get<double>();
    INFO(rpm << " rpm");
    // the valve opens within a few percent of the kinematic lift
    CHECK_REL(res["max_lift_mm"].get<double>(), res["max_lift_kinematic_mm"].get<double>(), tol::kLiftLossShareRel);
    // and seats once per revolution: the valve comes back from its lift to the seat once. Its
    // seat is compliant and damped, so it may bounce off it by micrometres (this design closes
    // without a ramp: 1.6 um at 2000 rpm, 14 um at 6000): a seating is the valve landing on
    // its seat (seat force > 0 in the CSV) after it was open by more than kOpen since it last
    // sat there, counted around the revolution from a seated point
    constexpr double kOpen = 0.1;  // [mm], above any bounce
    CHECK(res["bounce_height_mm"].get<double>() < kOpen);
    std::vector<double> lift, seat;
    for (std::size_t i = 0; i < c.at("rpm").size(); ++i)
      if (c.at("rpm")[i] == rpm) lift.push_back(c.at("lift_mm")[i]), seat.push_back(c.at("seat_force_N")[i]);
    REQUIRE(seat.size() == 361);
    lift.pop_back(), seat.pop_back();  // 360 deg is 0 deg again
    const std::size_t n = seat.size();
    std::size_t first = 0;
    while (first < n && !(seat[first] > 0.0)) ++first;
    REQUIRE(first < n);
    int seatings = 0;
    bool opened = false;
    for (std::size_t k = 1; k <= n; ++k) {
      const std::size_t i = (first + k) % n;
      if (lift[i] > kOpen) opened = true;
      if (seat[i] > 0.0 && opened) ++seatings, opened = false;
    }
    CHECK(seatings == 1);
    // the events (CVODE's root finding) agree: the seat opens as often as it closes, and
    // every closing after the first is a bounce
    int seat_opens = 0, seat_closes = 0;
    for (const auto& e : res["events"])
      if (e["what"] == "valve seat") ++(e["event"] == "opens" ? seat_opens : seat_closes);
    CHECK(seat_closes >= 1);
    CHECK(seat_opens == seat_closes);
    CHECK(res["bounce_count"] == seat_closes - 1);
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

TEST_CASE("camopt dynamics --model flexible: valve velocity and acceleration are the lift's derivatives, every "
          "default is in the summary", "[dynamics][cli]") {
  const ExpectWarnings two_revolutions{"no periodic steady state"};  // two revolutions only
  TempDir tmp;
  const fs::path out = tmp / "out";
  // the eccentric's path is smooth (a tabulated lobe's acceleration can change by 300 m/s^2
  // within 0.5 deg, finer than the flexible model's 0.25 deg path table)
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/eccentric_flat_follower.toml").string(), "--model",
                             "flexible", "--rpm", "3000", "--step", "0.02", "--revolutions", "2", "--out",
                             out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  auto c = columns_of(read_file(out / "dynamics.csv"));
  for (const char* name : {"vel_m_per_s", "acc_m_per_s2", "spring_return_spring_static_N", "seat_force_N"})
    REQUIRE(c.count(name) == 1);
  // central differences of the lift (0.02 deg at 1500 cam rpm: 2.2 us) against the columns,
  // away from the seat (its impacts make the force jump)
  const double dt = 0.02 * camopt::rad_per_deg / (1500 * 2 * camopt::pi / 60);
  const auto& lift = c["lift_mm"];
  Series vel("central difference of lift_mm [m/s] against vel_m_per_s", "row"),
      acc("central difference of vel_m_per_s [m/s^2] against acc_m_per_s2", "row");
  double peak_v = 0;
  for (std::size_t i = 1; i + 1 < lift.size(); ++i) {
    if (c["seat_force_N"][i] > 0 || c["lift_kinematic_mm"][i] < 0.5) continue;
    const double v = (lift[i + 1] - lift[i - 1]) / (2 * dt) * 1e-3;
    const double a = (c["vel_m_per_s"][i + 1] - c["vel_m_per_s"][i - 1]) / (2 * dt);
    vel.add(static_cast<double>(i), v, c["vel_m_per_s"][i]);
    acc.add(static_cast<double>(i), a, c["acc_m_per_s2"][i]);
    peak_v = std::max(peak_v, std::abs(c["vel_m_per_s"][i]));
  }
  INFO("peak velocity " << peak_v << " m/s");
  CHECK(peak_v > 0.5);
  CHECK_SERIES(vel.compare({.rel = tol::kCsvVelocityFdRel}));
  CHECK_SERIES(acc.compare({.rel = tol::kCsvAccelerationFdRel}));
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  const auto& res = j["results"][0];
  CHECK(res["seats"]["follower"]["seating_velocity_m_per_s"].is_number());
  CHECK(res["seats"]["follower"]["max_force_N"].get<double>() > 0.0);
  CHECK(res.contains("gap_linearisation_error_mm"));
  CHECK(res.contains("periodic_steady_state"));
  bool seat_default = false;
  for (const auto& p : j["model_parameters"])
    if (p["key"] == "node.follower.seat.diameter") seat_default = p["value"] == "29" && p["from_design"] == false;
  CHECK(seat_default);
}

TEST_CASE("camopt dynamics --model flexible: a seat the valve cannot reach is an input error naming the node",
          "[dynamics][cli]") {
  TempDir tmp;
  std::string text = read_file(source_dir() / "designs/eccentric_flat_follower.toml");
  // the follower held 0.5 mm below its drawing: it never comes down to its seat there
  text = std::regex_replace(text, std::regex("(\\[\\[node\\]\\]\\nname = \"follower\")"), "$1\nrest_mm = -0.5");
  const fs::path design = tmp / "unreachable_seat.toml";
  write_text(design, text);
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", design.string(), "--model", "flexible", "--rpm", "3000", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(has(r.err, "unreachable_seat.toml:"));
  CHECK(has(r.err, "node 'follower': seat: the valve never reaches its seat"));
  CHECK((!fs::exists(out) || fs::is_empty(out)));
}

TEST_CASE("camopt dynamics --model rigid: per node the inertia, spring, damping and gas forces", "[dynamics][cli]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/eccentric_flat_follower.toml").string(), "--model",
                             "rigid", "--rpm", "3000", "--step", "1", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  auto c = columns_of(read_file(out / "dynamics.csv"));
  for (const char* name : {"node_follower_inertia_N", "node_follower_spring_N", "node_follower_damping_N",
                           "node_follower_gas_N", "spring_return_spring_load_N", "contact_disc_face_force_N"})
    REQUIRE(c.count(name) == 1);
  // the spring's force on the node is minus its load; no damper, no gas in this design; the
  // inertia force is -m a with a from central differences of the lift (1 deg at 1500 cam rpm:
  // truncation (1 deg)^2 / 12 = 2.5e-5 of a harmonic) and m the follower's mass plus a third of
  // the spring's (0.10 + 0.01 / 3 kg, the design)
  const double kFollowerMass = 0.10 + 0.01 / 3;
  const double dt = 1.0 * camopt::rad_per_deg / (1500 * 2 * camopt::pi / 60);
  const auto& lift = c["lift_mm"];
  Series inertia("-m a, a the central difference of lift_mm [N], against node_follower_inertia_N", "row");
  double peak = 0;
  for (std::size_t i = 1; i + 1 < lift.size(); ++i) {
    CHECK(c["node_follower_spring_N"][i] == -c["spring_return_spring_load_N"][i]);
    CHECK(c["node_follower_damping_N"][i] == 0.0);
    const double a = (lift[i + 1] - 2 * lift[i] + lift[i - 1]) / (dt * dt) * 1e-3;
    inertia.add(static_cast<double>(i), -kFollowerMass * a, c["node_follower_inertia_N"][i]);
    peak = std::max(peak, std::abs(c["node_follower_inertia_N"][i]));
  }
  INFO("peak inertia force " << peak << " N");
  CHECK(peak > 1.0);
  CHECK_SERIES(inertia.compare({.rel = tol::kCsvInertiaFdRel}));
}

TEST_CASE("cli dynamics: the flexible model with an HLA writes its pressure, flows and plunger, the others hold it rigid",
          "[cli][dynamics][hla]") {
  TempDir tmp;
  const std::string design = std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam_hla.toml";
  const std::string out = tmp.file("flex");
  const RunResult r = run_camopt({"-q", "dynamics", design, "--model", "flexible", "--rpm", "3000,9000", "--out", out});
  INFO(r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string csv = read_file(fs::path(out) / "dynamics.csv");
  for (const char* column : {"hla_finger_plunger_mm", "hla_finger_force_N", "hla_finger_pressure_MPa",
                             "hla_finger_leak_mm3_per_s", "hla_finger_refill_mm3_per_s", "hla_finger_ball_lift_mm"})
    CHECK(csv.substr(0, csv.find('\n')).find(column) != std::string::npos);
  const auto summary = nlohmann::json::parse(read_file(fs::path(out) / "summary.json"));
  REQUIRE(summary["results"].size() == 2);
  for (const auto& res : summary["results"]) {
    const auto& h = res["hla"][0];
    CHECK(h["node"] == "finger");
    // the chamber carries the valve train's load: MPa, not the gallery's 0.3
    CHECK(h["max_pressure_MPa"].get<double>() > 5.0);
    CHECK(h["ball_opens"].get<bool>());
  }
  // the speed map: at 9000 rpm the finger leaves the swing cam and the plunger moves by tenths of
  // a millimetre over the revolution, at 3000 rpm by less than a micrometre
  const auto& map = summary["speed_map"];
  CHECK(std::abs(map[1]["hla_finger_drift_mm"].get<double>()) > 0.01);
  CHECK(std::abs(map[0]["hla_finger_drift_mm"].get<double>()) < 1e-3);
  // kinematics holds the pivot and says so
  const RunResult k = run_camopt({"kinematics", design, "--out", tmp.file("kin")});
  REQUIRE(k.exit_code == cli_ok);
  CHECK(k.err.find("hla 'finger_hla' under node 'finger' is held rigid") != std::string::npos);
  CHECK(nlohmann::json::parse(read_file(fs::path(tmp.file("kin")) / "summary.json"))["hla_held_rigid"][0] == "finger_hla");
}
