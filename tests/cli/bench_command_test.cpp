// camopt bench end to end: the work-precision table's columns and rows, errors that equal an
// independent computation from two kinematics runs, tight runs tighter than the defaults, and
// bad input.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "camopt/io/csv.hpp"
#include "cli/cli_support.hpp"
#include "support/compare.hpp"
#include "support/tolerances.hpp"

using namespace camopt::test;

namespace {

// the cells of a CSV line ("" quotes a quote inside a quoted cell)
std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted && ch == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
    else if (ch == '"') quoted = !quoted;
    else if (ch == ',' && !quoted) cells.emplace_back();
    else cells.back() += ch;
  }
  return cells;
}

// bench.csv as rows of named cells, keyed "stage/run"
std::map<std::string, std::map<std::string, std::string>> bench_rows(const std::string& text,
                                                                     std::vector<std::string>& header) {
  const auto lines = split_lines(text);
  header = cells_of(lines.at(0));
  std::map<std::string, std::map<std::string, std::string>> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = cells_of(lines[i]);
    REQUIRE(cells.size() == header.size());
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < cells.size(); ++c) row[header[c]] = cells[c];
    rows[row["stage"] + "/" + row["run"]] = row;
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& key) {
  const std::string& text = row.at(key);
  INFO(key << " = '" << text << "'");
  REQUIRE_FALSE(text.empty());
  return std::stod(text);
}

// the lift column of `camopt kinematics --outputs lift` at a step
std::vector<double> kinematic_lift(const fs::path& design, const std::string& step, const fs::path& out) {
  const auto r = run_camopt({"kinematics", design.string(), "--outputs", "lift", "--step", step, "--out", out.string(),
                             "--no-report"});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const camopt::io::CsvTable t = camopt::io::read_csv((out / "kinematics.csv").string());
  const auto it = std::find(t.columns.begin(), t.columns.end(), "lift_mm");
  REQUIRE(it != t.columns.end());
  return t.values[static_cast<std::size_t>(it - t.columns.begin())];
}

}  // namespace

TEST_CASE("camopt bench: the work-precision table of a design, its errors against tighter runs",
          "[bench][cli]") {
  TempDir tmp;
  const fs::path design = source_dir() / "designs/eccentric_flat_follower.toml";
  const auto r = run_camopt({"bench", design.string(), "--repeat", "1", "--out", (tmp / "out").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  // the table on stdout names its columns with their units
  for (const char* column : {"stage", "time_ms", "ns_per_point", "lift_error_mm", "force_error_rel",
                             "separation_error_rpm"})
    CHECK(r.out.find(column) != std::string::npos);
  std::vector<std::string> header;
  const auto rows = bench_rows(read_file(tmp / "out" / "bench.csv"), header);
  CHECK(header == std::vector<std::string>{"stage", "run", "setting", "points", "time_ms", "ns_per_point",
                                           "lift_error_mm", "force_error_rel", "separation_error_rpm", "note"});
  REQUIRE(rows.size() == 10);
  for (const char* stage : {"kinematics lift", "kinematics all", "synthesis", "rigid", "flexible"}) {
    INFO(stage);
    const auto& def = rows.at(std::string(stage) + "/default");
    const auto& tight = rows.at(std::string(stage) + "/tight");
    CHECK(def.at("note").empty());
    CHECK(number(def, "time_ms") > 0.0);
    CHECK(number(def, "ns_per_point") == Approx(number(def, "time_ms") * 1e6 / number(def, "points")));
    // the tight run is tighter: more points, or the flexible model's tolerance 1e4 x smaller
    if (std::string(stage) == "flexible") {
      CHECK(def.at("setting") == "rtol 1e-06 atol 1e-07");
      CHECK(tight.at("setting") == "rtol 1e-10 atol 1e-12");
    } else {
      CHECK(number(tight, "points") > 2 * number(def, "points"));
    }
  }
  // the design's 1 deg step and 4x finer: the default table's lift between its points by
  // linear interpolation against the finer run, computed here from two kinematics runs
  const std::vector<double> coarse = kinematic_lift(design, "1", tmp / "k1"), fine = kinematic_lift(design, "0.25", tmp / "k4");
  REQUIRE(fine.size() == 4 * (coarse.size() - 1) + 1);
  double expected = 0.0;
  for (std::size_t j = 0; j < fine.size(); ++j) {
    const std::size_t i = j / 4;
    const double f = (j % 4) / 4.0;
    expected = std::max(expected, std::abs((j % 4 ? (1 - f) * coarse[i] + f * coarse[i + 1] : coarse[i]) - fine[j]));
  }
  // the eccentric's lift e (1 - cos theta): a chord misses at most e h^2 / 8 (h = 1 deg)
  CHECK(expected > 0.5 * 4 * std::pow(M_PI / 180, 2) / 8);
  CHECK(expected < 4 * std::pow(M_PI / 180, 2) / 8);
  for (const char* stage : {"kinematics lift/default", "kinematics all/default"})
    CHECK_REL(number(rows.at(stage), "lift_error_mm"), expected, tol::kBenchRecomputedRel);
  // the synthesis: both runs reproduce the eccentric's lift (their round trips)
  CHECK(number(rows.at("synthesis/default"), "lift_error_mm") < tol::kRoundTripAbs);
  CHECK(number(rows.at("synthesis/tight"), "lift_error_mm") < tol::kRoundTripAbs);
  // the rigid model: the grid misses the peak force between its points, not the separation
  // speed (refined between grid points); the flexible model's default tolerance against 1e-10
  const auto& rigid = rows.at("rigid/default");
  CHECK(number(rigid, "force_error_rel") >= 0.0);
  CHECK(number(rigid, "force_error_rel") < 1e-3);
  CHECK(number(rigid, "separation_error_rpm") < 1e-6 * 1e4);
  const auto& flexible = rows.at("flexible/default");
  CHECK(number(flexible, "lift_error_mm") > 0.0);
  CHECK(number(flexible, "lift_error_mm") < 1e-3);
}

TEST_CASE("camopt bench: a stage the design cannot run is a row that says why", "[bench][cli]") {
  TempDir tmp;
  // a four-bar has no cam to make again
  const auto r = run_camopt({"bench", (source_dir() / "designs/four_bar.toml").string(), "--repeat", "1", "--out",
                             (tmp / "out").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  std::vector<std::string> header;
  const auto rows = bench_rows(read_file(tmp / "out" / "bench.csv"), header);
  CHECK(rows.at("synthesis/default").at("note").rfind("skipped: ", 0) == 0);
  CHECK(rows.at("synthesis/default").at("time_ms").empty());
  CHECK(rows.at("kinematics lift/default").at("note").empty());
}

TEST_CASE("camopt bench: bad input exits 3 and writes nothing", "[bench][cli]") {
  TempDir tmp;
  write_text(tmp / "bad.toml", "schema = 1\n[design]\nname = \"x\"\n");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"bench", (tmp / "bad.toml").string(), "--out", (tmp / "out").string()},
        std::vector<std::string>{"bench", (tmp / "missing.toml").string(), "--out", (tmp / "out").string()},
        std::vector<std::string>{"bench", (source_dir() / "designs/cvvl_swing_cam.toml").string(), "--control",
                                 "0:16:2", "--out", (tmp / "out").string()}}) {
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK_FALSE(fs::exists(tmp / "out" / "bench.csv"));
  }
}
