// collect() on result folders made by the camopt binary: plot ids, series counts, units from
// the CSV headers, display data against the CSV values; bad folders named.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "camopt/core/error.hpp"
#include "camopt/io/atomic_file.hpp"
#include "report/report_support.hpp"
#include "support/compare.hpp"

namespace camopt::test {
namespace {

using report::ReportData;

// every series of `plot` (one per group of `group_rows` rows) equals the csv column exactly
void check_series_are_columns(const report::Plot& plot, const TestCsv& csv, const std::string& x_column,
                              const std::string& y_column, std::size_t groups) {
  INFO("plot " << plot.id << ", column " << y_column);
  REQUIRE(plot.series.size() == groups);
  const std::size_t rows = csv[y_column].size() / groups;
  for (std::size_t g = 0; g < groups; ++g) {
    const report::Series& s = plot.series[g];
    const std::vector<double>& x = s.x.empty() ? plot.x_values : s.x;
    REQUIRE(s.y.size() == rows);
    REQUIRE(x.size() == rows);
    for (std::size_t i = 0; i < rows; ++i) {
      REQUIRE(s.y[i] == csv[y_column][g * rows + i]);
      REQUIRE(x[i] == csv[x_column][g * rows + i]);
    }
  }
}

TEST_CASE("report: collect of the 17-position CVVL sweep gives one series per control position") {
  const fs::path dir = result_folder("kin_cvvl17");
  const ReportData d = report::collect(dir);
  const TestCsv csv = read_test_csv(dir / "kinematics.csv");
  CHECK(d.command == "kinematics");
  REQUIRE(d.family.size() == 17);
  CHECK(d.family[4] == "control 4 deg");
  // the valve's SVAJ: the CSV columns, units as in their headers
  const std::pair<const char*, const char*> svaj[] = {{"svaj-lift", "lift_mm"},
                                                      {"svaj-velocity", "vel_mm_per_deg"},
                                                      {"svaj-acceleration", "acc_mm_per_deg2"},
                                                      {"svaj-jerk", "jerk_mm_per_deg3"}};
  const char* units[] = {"mm", "mm/deg", "mm/deg^2", "mm/deg^3"};
  for (std::size_t q = 0; q < 4; ++q) {
    const report::Plot& p = plot_of(d, svaj[q].first);
    CHECK(p.y.unit == units[q]);
    CHECK(p.x.unit == "deg");
    CHECK(p.link_group == "svaj");
    check_series_are_columns(p, csv, "cam_deg", svaj[q].second, 17);
    for (std::size_t g = 0; g < 17; ++g) CHECK(p.series[g].family_member == static_cast<int>(g));
  }
  // every node's and contact's plots, 17 series each
  const report::Plot& pa = plot_of(d, "contact-cam_roller-pressure-angle");
  CHECK(pa.y.unit == "deg");
  check_series_are_columns(pa, csv, "cam_deg", "cam_roller_pressure_angle_deg", 17);
  const report::Plot& finger = plot_of(d, "node-finger_angle-acceleration");
  CHECK(finger.y.unit == "deg/deg^2");
  check_series_are_columns(finger, csv, "cam_deg", "finger_angle_acc_deg_per_deg2", 17);
  // a contact quantity that is zero everywhere (the pad's roller speed) is not drawn
  CHECK_FALSE(has_plot(d, "contact-pad_valve-roller-speed"));
  // the summary's extremes, one row per position
  CHECK(table_of(d, "extremes").rows.size() == 17);
  CHECK(d.notes.empty());
}

TEST_CASE("report: the animation of the 17-position CVVL sweep moves the valve by the CSV lift at every frame") {
  const fs::path dir = result_folder("kin_cvvl17");
  const ReportData d = report::collect(dir);
  const TestCsv csv = read_test_csv(dir / "kinematics.csv");
  REQUIRE(d.scene.has_value());
  const report::Scene& sc = *d.scene;
  REQUIRE(sc.positions.size() == 17);
  CHECK(sc.output_body == "valve");
  // the section sits right after the valve's SVAJ
  REQUIRE(d.sections.size() > 1);
  CHECK(d.sections[1].id == "mechanism");
  // frames every 1 deg: every second row of the 0.5 deg table, 361 per position
  const std::size_t rows = csv["cam_deg"].size() / 17;
  REQUIRE(rows == 721);
  const auto valve = static_cast<std::size_t>(
      std::find(sc.bodies.begin(), sc.bodies.end(), sc.output_body) - sc.bodies.begin());
  REQUIRE(valve < sc.bodies.size());
  for (std::size_t k = 0; k < 17; ++k) {
    const report::ScenePosition& pos = sc.positions[k];
    CHECK(pos.control == csv["control_deg"][k * rows]);
    REQUIRE(pos.cam_deg.size() == 361);
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f) {
      const std::size_t row = k * rows + 2 * f;
      INFO("control " << pos.control << ", frame " << f);
      REQUIRE(pos.cam_deg[f] == csv["cam_deg"][row]);
      // the lift column bit for bit, and the valve's drawn translation (it slides along its
      // axis from its drawing position) of that length
      REQUIRE(pos.lift_mm[f] == csv["lift_mm"][row]);
      const double tx = pos.pose[valve][3 * f], ty = pos.pose[valve][3 * f + 1];
      REQUIRE(std::abs(std::hypot(tx, ty) - std::abs(csv["lift_mm"][row])) <= 1e-12);
    }
  }
}

TEST_CASE("report: collect of a default kinematics run says how to get the contact plots") {
  const ReportData d = report::collect(result_folder("kin_default"));
  CHECK(has_plot(d, "svaj-acceleration"));
  CHECK_FALSE(has_plot(d, "contact-cam_roller-pressure-angle"));
  bool told = false;
  for (const auto& n : d.notes) told = told || n.find("--outputs all") != std::string::npos;
  CHECK(told);
  CHECK(d.family.empty());
  CHECK(plot_of(d, "svaj-lift").series.size() == 1);
}

TEST_CASE("report: collect of kinematics with --rpm plots the contact speeds in SI units") {
  const fs::path dir = result_folder("kin_all");
  const ReportData d = report::collect(dir);
  const TestCsv csv = read_test_csv(dir / "kinematics.csv");
  const report::Plot& roller = plot_of(d, "contact-cam_roller-roller-speed");
  CHECK(roller.y.unit == "rpm");
  check_series_are_columns(roller, csv, "cam_deg", "cam_roller_roller_rpm", 1);
  CHECK(plot_of(d, "contact-cam_roller-entrainment").y.unit == "m/s");
}

TEST_CASE("report: the page's arrays are the CSV values in float32") {
  const fs::path dir = result_folder("kin_cvvl17");
  const TestCsv csv = read_test_csv(dir / "kinematics.csv");
  const nlohmann::json j = page_data(report::render_html(report::collect(dir)));
  const nlohmann::json* acc = nullptr;
  for (const auto& p : j["plots"])
    if (p["id"] == "svaj-acceleration") acc = &p;
  REQUIRE(acc);
  const std::vector<float> x = decode_float32((*acc)["x_values"].get<std::string>());
  const auto& series = (*acc)["series"];
  REQUIRE(series.size() == 17);
  const std::size_t rows = csv["cam_deg"].size() / 17;
  REQUIRE(x.size() == rows);
  for (std::size_t g = 0; g < 17; ++g) {
    const std::vector<float> y = decode_float32(series[g]["y"].get<std::string>());
    REQUIRE(y.size() == rows);
    CHECK(series[g]["family_member"] == static_cast<int>(g));
    for (std::size_t i = 0; i < rows; ++i) {
      REQUIRE(y[i] == static_cast<float>(csv["acc_mm_per_deg2"][g * rows + i]));
      REQUIRE(x[i] == static_cast<float>(csv["cam_deg"][i]));
    }
  }
}

TEST_CASE("report: collect of synthesize draws the profile to scale with its base circle") {
  const fs::path dir = result_folder("synthesize");
  const ReportData d = report::collect(dir);
  const TestCsv profile = read_test_csv(dir / "profile.csv");
  const nlohmann::json rj = nlohmann::json::parse(read_file(dir / "report.json"));
  CHECK(d.command == "synthesize");
  const report::Plot& p = plot_of(d, "profile");
  CHECK(p.kind == report::PlotKind::profile);
  CHECK(p.main);
  REQUIRE(p.series.size() == 2);
  CHECK(p.series[0].x == profile["x_mm"]);
  CHECK(p.series[0].y == profile["y_mm"]);
  CHECK(p.series[0].color == profile["radius_of_curvature_mm"]);
  CHECK(p.color.unit == "mm");
  // the base circle: dashed, every point at the base radius
  const double base = rj["profile"]["base_circle_radius_mm"].get<double>();
  CHECK(p.series[1].dashed);
  for (std::size_t i = 0; i < p.series[1].x.size(); ++i)
    REQUIRE_REL(std::hypot(p.series[1].x[i], p.series[1].y[i]), base, 1e-14);
  // the concave windows as bands where the radius of curvature is negative
  const report::Plot& rho = plot_of(d, "profile-curvature");
  REQUIRE(rj["checks"]["concave"] == true);
  REQUIRE_FALSE(rho.bands.empty());
  const auto& angle = profile["angle_deg"];
  const auto& r = profile["radius_of_curvature_mm"];
  for (std::size_t i = 0; i < angle.size(); ++i) {
    bool inside = false;
    for (const auto& b : rho.bands) inside = inside || (angle[i] >= b.from && angle[i] <= b.to);
    INFO("profile angle " << angle[i] << " radius " << r[i]);
    REQUIRE(inside == (r[i] < 0));
  }
  // the made cam in the kinematic solver: its largest pressure angle and its round-trip error
  // are those synthesize reports from its own check of the same cam on the same grid
  const report::Plot& pa = plot_of(d, "made-pressure-angle");
  REQUIRE(pa.series.size() == 1);
  double pa_max = 0;
  for (double v : pa.series[0].y) pa_max = std::max(pa_max, std::abs(v));
  CHECK_REL(pa_max, rj["checks"]["max_pressure_angle_deg"].get<double>(), 1e-12);
  const report::Plot& rt = plot_of(d, "made-round-trip");
  REQUIRE(rt.series.size() == 1);
  CHECK(rt.series[0].x.size() == 720);
  double rt_max = 0;
  for (double v : rt.series[0].y) rt_max = std::max(rt_max, std::abs(v));
  // (a difference of two 8 mm lifts: their round-off, a few 1e-15 mm, is the tolerance)
  CHECK_ABS(rt_max, rj["checks"]["round_trip_max_error_mm"].get<double>(), 1e-13);
}

TEST_CASE("report: collect of optimize puts the limits and active angles on the SVAJ plots") {
  const fs::path dir = result_folder("optimize");
  const ReportData d = report::collect(dir);
  const nlohmann::json rj = nlohmann::json::parse(read_file(dir / "report.json"));
  CHECK(d.command == "optimize");
  const report::Plot& acc = plot_of(d, "svaj-acceleration");
  bool found = false;
  for (const auto& l : acc.limits)
    found = found || (l.label == "acc_max" && l.y == rj["constraints"]["acc_max"]["limit"].get<double>());
  CHECK(found);
  // every active angle of jerk_max lies in a band of the jerk plot
  const report::Plot& jerk = plot_of(d, "svaj-jerk");
  for (const auto& a : rj["constraints"]["jerk_max"]["active_at_cam_deg"]) {
    const double deg = std::stod(a.get<std::string>());
    bool inside = false;
    for (const auto& b : jerk.bands) inside = inside || (deg > b.from && deg < b.to);
    CHECK(inside);
  }
  // the constraint table: one row per constraint, none failed at this optimum
  const report::Table& t = table_of(d, "constraints");
  CHECK(t.rows.size() == rj["constraints"].size());
  CHECK(t.failed_rows.empty());
  CHECK(has_plot(d, "profile"));
  // the convergence history: one series per ipopt working-set round, the rounds' iterations
  // adding up to the run's count, ending at the reported optimum, in the order of the run
  const report::Plot& conv = plot_of(d, "convergence-objective");
  REQUIRE(conv.series.size() == 2);
  int iterations = 0;
  std::map<std::string, int> last;
  for (const auto& row : rj["convergence"]) last[row["phase"].get<std::string>()] = row["iteration"].get<int>();
  for (const auto& [phase, n] : last) iterations += n;
  CHECK(iterations == rj["iterations"].get<int>());
  CHECK(conv.series.back().y.back() == rj["objective"]["value"].get<double>());
  const report::Plot& viol = plot_of(d, "convergence-violation");
  CHECK(viol.series.back().y.back() <= 1e-9);
  double time = 0;
  for (const auto& s : conv.series)
    for (double x : s.x) {
      REQUIRE(x >= time);
      time = x;
    }
}

TEST_CASE("report: collect of a rigid rpm sweep gives one series per speed and the speed map") {
  const fs::path dir = result_folder("rigid");
  const ReportData d = report::collect(dir);
  const TestCsv csv = read_test_csv(dir / "dynamics.csv");
  CHECK(d.command == "dynamics rigid");
  REQUIRE(d.family.size() == 4);
  CHECK(d.family[0] == "1000 rpm");
  const report::Plot& f = plot_of(d, "force-cam_roller");
  CHECK(f.y.unit == "N");
  check_series_are_columns(f, csv, "cam_deg", "contact_cam_roller_force_N", 4);
  CHECK(plot_of(d, "cam-torque").y.unit == "Nm");
  CHECK(plot_of(d, "hertz-cam_roller").y.unit == "MPa");
  CHECK(plot_of(d, "speed-map").kind == report::PlotKind::line);
}

TEST_CASE("report: collect of a rigid rpm x control sweep draws the speed map as a heatmap") {
  const fs::path dir = result_folder("rigid_map");
  const ReportData d = report::collect(dir);
  const nlohmann::json sj = nlohmann::json::parse(read_file(dir / "summary.json"));
  const report::Plot& map = plot_of(d, "speed-map");
  REQUIRE(map.kind == report::PlotKind::heatmap);
  REQUIRE(map.x_values.size() == 3);
  REQUIRE(map.y_values.size() == 3);
  REQUIRE(map.z.size() == 9);
  CHECK(d.family.size() == 9);
  // z: the smallest contact force of each result, at its (rpm, control) cell
  for (const auto& r : sj["results"]) {
    double smallest = 1e300;
    for (const auto& [name, c] : r["connections"].items()) smallest = std::min(smallest, c["min_force_N"].get<double>());
    const auto col = std::find(map.x_values.begin(), map.x_values.end(), r["rpm"].get<double>()) - map.x_values.begin();
    const auto row =
        std::find(map.y_values.begin(), map.y_values.end(), r["control_deg"].get<double>()) - map.y_values.begin();
    REQUIRE(col < 3);
    REQUIRE(row < 3);
    CHECK(map.z[static_cast<std::size_t>(row * 3 + col)] == smallest);
  }
}

TEST_CASE("report: collect of flexible dynamics draws the kinematic lift dashed under the dynamic one") {
  const fs::path dir = result_folder("flexible");
  const ReportData d = report::collect(dir);
  const TestCsv csv = read_test_csv(dir / "dynamics.csv");
  const report::Plot& lift = plot_of(d, "dynamic-lift");
  REQUIRE(lift.series.size() == 2);
  CHECK_FALSE(lift.series[0].dashed);
  CHECK(lift.series[1].dashed);
  CHECK(lift.series[0].y == csv["lift_mm"]);
  CHECK(lift.series[1].y == csv["lift_kinematic_mm"]);
  CHECK(has_plot(d, "force-cam_roller"));
}

TEST_CASE("report: collect of modes tabulates the natural frequencies") {
  const fs::path dir = result_folder("modes");
  const ReportData d = report::collect(dir);
  const nlohmann::json sj = nlohmann::json::parse(read_file(dir / "summary.json"));
  const report::Table& t = table_of(d, "frequencies");
  REQUIRE(t.rows.size() == sj["results"].size());
  // every frequency reads back to the summary's number (shortest round-trip text)
  for (std::size_t r = 0; r < t.rows.size(); ++r)
    for (std::size_t k = 0; k < sj["results"][r]["frequencies_Hz"].size(); ++k)
      CHECK(std::stod(t.rows[r][3 + k]) == sj["results"][r]["frequencies_Hz"][k].get<double>());
  CHECK(has_plot(d, "mode-shapes-1"));
}

TEST_CASE("report: collect of a lift table plots its four columns") {
  const fs::path csv_path = result_folder("lift");
  const ReportData d = report::collect(csv_path);
  const TestCsv csv = read_test_csv(csv_path);
  CHECK(d.command == "lift");
  check_series_are_columns(plot_of(d, "svaj-jerk"), csv, "cam_deg", "jerk_mm_per_deg3", 1);
  CHECK(report::report_path(csv_path) == csv_path.parent_path() / "lift.report.html");
}

TEST_CASE("report: collect names a missing folder, a folder without results and a bad CSV line") {
  TempDir tmp;
  CHECK_THROWS_WITH(report::collect(tmp / "absent"), Catch::Contains("absent") && Catch::Contains("no such folder"));
  CHECK_THROWS_WITH(report::collect(tmp.path()), Catch::Contains("no camopt result"));
  // a kinematics folder whose CSV has a bad cell on line 3
  const fs::path dir = tmp / "kin";
  fs::create_directories(dir);
  fs::copy_file(result_folder("kin_default") / "summary.json", dir / "summary.json");
  write_text(dir / "kinematics.csv", "control_deg,cam_deg,lift_mm\n0,0,0\n0,1,abc\n");
  CHECK_THROWS_AS(report::collect(dir), InputError);
  CHECK_THROWS_WITH(report::collect(dir), Catch::Contains("kinematics.csv:3") && Catch::Contains("'abc'"));
  write_text(dir / "kinematics.csv", "control_deg,cam_deg,lift_mm\n0,0,0\n0,1\n");
  CHECK_THROWS_WITH(report::collect(dir), Catch::Contains("kinematics.csv:3") && Catch::Contains("2 cells"));
  // a summary without its design key
  write_text(dir / "summary.json", "{\"positions\": []}");
  CHECK_THROWS_WITH(report::collect(dir), Catch::Contains("summary.json") && Catch::Contains("'design'"));
  write_text(dir / "summary.json", "{\"positions\": [");
  CHECK_THROWS_WITH(report::collect(dir), Catch::Contains("summary.json") && Catch::Contains("not a JSON object"));
}

TEST_CASE("report: a run's table in memory is taken while the folder holds the file it committed") {
  TempDir tmp;
  const fs::path dir = tmp / "kin";
  fs::create_directories(dir);
  for (const char* name : {"summary.json", "kinematics.csv"})
    fs::copy_file(result_folder("kin_default") / name, dir / name);
  const TestCsv csv = read_test_csv(dir / "kinematics.csv");
  // the table as the run holds it, told apart from the file: the lift doubled, and a negative
  // zero at the first row (the file's text of it is 0)
  io::Columns table{csv.header, csv.columns, {}};
  std::size_t lift = 0;
  while (table.header[lift] != "lift_mm") ++lift;
  for (double& v : table.values[lift]) v *= 2.0;
  table.values[lift][0] = -0.0;
  const auto id = io::file_id((dir / "kinematics.csv").string());
  REQUIRE(id.has_value());
  const report::WrittenTables written = {{"kinematics.csv", {table, *id}}};
  // the file the run committed: the table is taken, its -0 as 0
  const report::ReportData memory_data = report::collect(dir, written);
  const report::Series& in_memory = plot_of(memory_data, "svaj-lift").series.front();
  REQUIRE(in_memory.y.size() == csv["lift_mm"].size());
  CHECK_FALSE(std::signbit(in_memory.y[0]));
  CHECK(in_memory.y[0] == 0.0);
  for (std::size_t i = 1; i < in_memory.y.size(); ++i) REQUIRE(in_memory.y[i] == 2.0 * csv["lift_mm"][i]);
  // another run's file in its place (a rename: another inode): the file is read
  write_text(dir / "kinematics.tmp", read_file(dir / "kinematics.csv"));
  fs::rename(dir / "kinematics.tmp", dir / "kinematics.csv");
  const report::ReportData file_data = report::collect(dir, written);
  const report::Series& from_file = plot_of(file_data, "svaj-lift").series.front();
  REQUIRE(from_file.y.size() == csv["lift_mm"].size());
  for (std::size_t i = 0; i < from_file.y.size(); ++i) REQUIRE(from_file.y[i] == csv["lift_mm"][i]);
}

TEST_CASE("report: collect of flexible dynamics with an HLA plots its chamber and maps its drift") {
  const fs::path dir = result_folder("flexible_hla");
  const TestCsv csv = read_test_csv(dir / "dynamics.csv");
  const report::ReportData d = report::collect(dir);
  const report::Plot& pressure = plot_of(d, "hla-pressure-finger");
  CHECK(pressure.section == "hla");
  CHECK(pressure.y.unit == "MPa");
  REQUIRE(pressure.series.size() == 2);  // 3000 and 6000 rpm
  const std::size_t rows = csv["cam_deg"].size() / 2;
  for (std::size_t g = 0; g < 2; ++g) {
    REQUIRE(pressure.series[g].y.size() == rows);
    for (std::size_t i = 0; i < rows; ++i) REQUIRE(pressure.series[g].y[i] == csv["hla_finger_pressure_MPa"][g * rows + i]);
  }
  CHECK(plot_of(d, "hla-flow-finger").series.size() == 4);  // leak and refill per speed
  for (const char* id : {"hla-plunger-finger", "hla-force-finger", "hla-ball-finger"}) CHECK(plot_of(d, id).series.size() == 2);
  // the drift over engine speed: the summary's speed map
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"));
  const report::Plot& map = plot_of(d, "hla-drift-map-finger");
  REQUIRE(map.series.size() == 1);
  REQUIRE(map.series[0].y.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) CHECK(map.series[0].y[k] == summary["speed_map"][k]["hla_finger_drift_mm"].get<double>());
}

}  // namespace
}  // namespace camopt::test
