// camopt kinematics: usage and input errors, the unit-labelled CSV and JSON summary of a
// bundled design; and a four-bar near its change point with a floating coupler
// (tests/data/kinematics/floating_coupler_four_bar.toml; the closed-form check over a
// revolution is tests/kinematics/branch_test.cpp): whatever outputs are asked for, the run
// stays on the drawing's branch (the rocker is back at its drawing angle after a revolution)
// with the same lift bits, and it is reported near toggle in summary.json and on stderr.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>
#define CAMOPT_TEST_HAVE_JSON 1
#include <string>
#include <vector>

#include "camopt/io/csv.hpp"
#include "cli/cli_support.hpp"
#include "cli/command_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt::test;
using namespace camopt::test::commands;

namespace {

const std::string kDesign = (source_dir() / "tests/data/kinematics/floating_coupler_four_bar.toml").string();

}  // namespace

TEST_CASE("kinematics: a near-change-point four-bar stays on its branch and is flagged near toggle",
          "[cli][kinematics][branch]") {
  const ExpectWarnings flagged{"near a singular configuration"};  // the flag this test is about
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
    CHECK_ABS(lift.back(), 0.0, tol::kRevolutionClosureAbs);
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
  CHECK_ABS(position["min_toggle_margin"].get<double>(), 0.5592, tol::kPrintedAngleSineAbs);
  CHECK(r.err.find("near a singular configuration") == std::string::npos);
}

// ---- kinematics ----------------------------------------------------------------------------

TEST_CASE("kinematics without --out is a usage error", "[cli][kinematics]") {
  const auto r = run_camopt({"kinematics", cli_data("eccentric_flat.toml").string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_usage_error);
}

TEST_CASE("kinematics names a design file that does not exist and writes nothing", "[cli][kinematics]") {
  TempDir tmp;
  const std::string missing = (tmp / "no_such_design.toml").string();
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"kinematics", missing, "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(contains(r.err, missing));
  CHECK(no_output(out));
}

TEST_CASE("kinematics rejects a bad design with exit 3 and writes nothing", "[cli][kinematics]") {
  const auto designs = glob_files(source_dir() / "tests" / "data" / "bad_designs", ".toml");
  REQUIRE_FALSE(designs.empty());
  for (const auto& d : designs) {
    TempDir tmp;
    const fs::path out = tmp / "out";
    const auto r = run_camopt({"kinematics", d.string(), "--out", out.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(no_output(out));
  }
}

TEST_CASE("kinematics of a four-bar that cannot close fails with exit 4 and writes nothing",
          "[cli][kinematics]") {
  const ExpectWarnings open_drawing{"four_bar_cannot_close.toml: warning:"};  // its drawing does not close either
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"kinematics", cli_data("four_bar_cannot_close.toml").string(), "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_numerical_failure);
  // the message names the connection and the driver angle where it failed
  CHECK(contains(r.err, "short_coupler"));
  CHECK(contains(r.err, "deg"));
  CHECK(no_output(out));
}

namespace {

// the files of a successful kinematics run: unit-labelled CSV with finite cells, JSON summary
void check_kinematics_outputs(const fs::path& out) {
  REQUIRE(fs::is_regular_file(out / "kinematics.csv"));
  REQUIRE(fs::is_regular_file(out / "summary.json"));
  // no temp file of the atomic writes is left behind
  for (const auto& f : files_under(out)) {
    INFO("output file " << f.string());
    CHECK_FALSE(contains(f.filename().string(), ".tmp"));
  }

  // kinematics.csv: every column has a unit, every cell is finite
  std::vector<std::string> header;
  std::size_t rows = 0;
  const auto lines = split_lines(read_file(out / "kinematics.csv"));
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.empty() || line[0] == '#') continue;
    const auto cells = split_csv_row(line);
    if (header.empty()) {
      header = cells;
      for (const auto& column : header) {
        INFO("kinematics.csv column '" << column << "' has no unit suffix");
        CHECK(has_unit_suffix(column));
      }
      continue;
    }
    ++rows;
    INFO("kinematics.csv line " << i + 1 << ": " << line);
    REQUIRE(cells.size() == header.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string cell = lower(cells[c]);
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      const bool number = !cell.empty() && end && *end == '\0';
      const bool bad = cell.empty() || contains(cell, "nan") || contains(cell, "inf") || (number && !std::isfinite(v));
      if (bad)
        FAIL_CHECK("column " << header[c] << ": cell '" << cells[c] << "' is empty or not finite");
    }
  }
  CHECK_FALSE(header.empty());
  CHECK(rows > 1);

  // summary.json parses
  const std::string text = read_file(out / "summary.json");
  INFO("summary.json: " << text.substr(0, 2000));
#ifdef CAMOPT_TEST_HAVE_JSON
  nlohmann::json summary;
  REQUIRE_NOTHROW(summary = nlohmann::json::parse(text));
  CHECK(summary.is_object());
  CHECK_FALSE(summary.empty());
#else
  const auto first = text.find_first_not_of(" \t\r\n");
  REQUIRE(first != std::string::npos);
  CHECK(text[first] == '{');
#endif
}

}  // namespace

TEST_CASE("kinematics of a bundled design writes a unit-labelled CSV and a JSON summary",
          "[cli][kinematics]") {
  const fs::path design = bundled_design("eccentric_flat_follower.toml");
  INFO("design " << design.string());
  REQUIRE(fs::exists(design));
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"kinematics", design.string(), "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  check_kinematics_outputs(out);
}

TEST_CASE("kinematics with every output at an engine speed labels every column with its unit",
          "[cli][kinematics]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  const auto r = run_camopt({"kinematics", cli_data("eccentric_flat.toml").string(), "--out", out.string(),
                             "--outputs", "all", "--rpm", "3000", "--step", "2"});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  check_kinematics_outputs(out);
}
