// camopt lift: one cycle of a unit-labelled lift table and its summary, every law, bad options
#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/units.hpp"
#include "cli/cli_support.hpp"
#include "cli/command_test_support.hpp"
#include "support/compare.hpp"

#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define CAMOPT_TEST_HAVE_JSON 1
#endif

using namespace camopt::test;
using namespace camopt::test::commands;

// ---- lift ----------------------------------------------------------------------------------

namespace {

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

// a lift table written by camopt lift: header, then finite numbers only
Table read_table(const fs::path& file) {
  Table t;
  for (const auto& line : split_lines(read_file(file))) {
    if (line.empty() || line[0] == '#') continue;
    const auto cells = split_csv_row(line);
    if (t.header.empty()) {
      t.header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) {
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      if (c.empty() || !end || *end != '\0' || !std::isfinite(v)) FAIL_CHECK("cell '" << c << "' is not a finite number");
      row.push_back(v);
    }
    if (row.size() != t.header.size()) FAIL_CHECK("row of " << row.size() << " cells under " << t.header.size());
    t.rows.push_back(row);
  }
  return t;
}

double column_max(const Table& t, std::size_t c) {
  double m = -1e300;
  for (const auto& r : t.rows) m = std::max(m, r[c]);
  return m;
}

}  // namespace

TEST_CASE("lift writes one cycle of a unit-labelled lift table and a summary", "[cli][lift]") {
  TempDir tmp;
  const fs::path out = tmp / "lift.csv";
  const auto r = run_camopt({"lift", "--law", "polynomial-345", "--close-law", "modified-sine", "--lift", "9.5",
                             "--open", "72", "--close", "64", "--dwell", "6", "--ramp-height", "0.25", "--ramp-length",
                             "22", "--close-ramp-height", "0.18", "--close-ramp-length", "18", "--peak-at", "110",
                             "--step", "0.5", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  REQUIRE(fs::is_regular_file(out));
  for (const auto& f : files_under(tmp.path())) CHECK_FALSE(contains(f.filename().string(), ".tmp"));

  const Table t = read_table(out);
  CHECK(t.header == std::vector<std::string>{"cam_deg", "lift_mm", "vel_mm_per_deg", "acc_mm_per_deg2",
                                             "jerk_mm_per_deg3"});
  for (const auto& column : t.header) CHECK(has_unit_suffix(column));
  // one full cycle, 0 .. 360 - step, without repeating 360
  REQUIRE(t.rows.size() == 720);
  CHECK(t.rows.front()[0] == 0.0);
  CHECK_ABS(t.rows.back()[0], 359.5, tol::kOutputAngleAbs);
  // max lift at --peak-at, the base circle at zero, no negative lift
  CHECK_REL(column_max(t, 1), 9.5, tol::kLawLiftRel);
  CHECK_ABS(t.rows[220][0], 110.0, tol::kOutputAngleAbs);
  CHECK_REL(t.rows[220][1], 9.5, tol::kLawLiftRel);
  CHECK(t.rows[0][1] == 0.0);
  for (const auto& row : t.rows) CHECK(row[1] >= -1e-12);
  // the opening ramp: constant velocity Hr / (Lr (1 - b/2)) with the default blend 0.5
  // (event from 110 - 3 - 72 = 35 cam deg; constant part from 46 to 57 cam deg)
  CHECK_ABS(t.rows[100][0], 50.0, tol::kOutputAngleAbs);
  CHECK_REL(t.rows[100][2], 0.25 / (22.0 * 0.75), tol::kRampVelocityRel);
  CHECK(t.rows[100][3] == 0.0);

  // summary on stderr: max lift, durations at 1 mm and 0.1 mm, acceleration extremes
  CHECK(contains(r.err, "max lift 9.5 mm"));
  CHECK(contains(r.err, "at 0.1 mm"));
  CHECK(contains(r.err, "at 1 mm"));
  CHECK(contains(r.err, "acceleration max"));
  CHECK(r.out.empty());

  // --quiet silences the summary
  const auto q = run_camopt({"--quiet", "lift", "--law", "cycloidal", "--out", (tmp / "q.csv").string()});
  INFO(q.command << "\n" << q.all());
  CHECK(q.exit_code == cli_ok);
  CHECK(q.err.empty());
}

TEST_CASE("lift --basis crank writes crank degrees and derivatives per crank degree", "[cli][lift]") {
  TempDir tmp;
  const std::vector<std::string> common = {"lift", "--law", "modified-trapezoid", "--lift", "8", "--duration", "140",
                                           "--step", "1"};
  auto args_cam = common, args_crank = common;
  args_cam.insert(args_cam.end(), {"--out", (tmp / "cam.csv").string()});
  args_crank.insert(args_crank.end(), {"--basis", "crank", "--out", (tmp / "crank.csv").string()});
  const auto rc = run_camopt(args_cam), rk = run_camopt(args_crank);
  INFO(rc.all() << rk.all());
  REQUIRE(rc.exit_code == cli_ok);
  REQUIRE(rk.exit_code == cli_ok);
  const Table cam = read_table(tmp / "cam.csv"), crank = read_table(tmp / "crank.csv");
  REQUIRE(crank.header.size() == 5);
  CHECK(crank.header[0] == "crank_deg");
  REQUIRE(crank.rows.size() == 360);
  REQUIRE(cam.rows.size() == 360);
  CHECK_ABS(crank.rows.back()[0], 718.0, tol::kOutputAngleAbs);
  for (std::size_t i = 0; i < cam.rows.size(); i += 7) {
    CHECK_ABS(crank.rows[i][0], 2.0 * cam.rows[i][0], tol::kOutputAngleAbs);
    CHECK_NEAR(crank.rows[i][1], cam.rows[i][1], tol::kCrankBasisAbs, tol::kCrankBasisRel);
    CHECK_NEAR(crank.rows[i][2], cam.rows[i][2] / 2.0, tol::kCrankBasisAbs, tol::kCrankBasisRel);
    CHECK_NEAR(crank.rows[i][3], cam.rows[i][3] / 4.0, tol::kCrankBasisAbs, tol::kCrankBasisRel);
    CHECK_NEAR(crank.rows[i][4], cam.rows[i][4] / 8.0, tol::kCrankBasisAbs, tol::kCrankBasisRel);
  }
}

TEST_CASE("lift runs every law, symmetric and asymmetric", "[cli][lift]") {
  const std::vector<std::vector<std::string>> cases = {
      {"--law", "polynomial-345"},
      {"--law", "polynomial-4567", "--ramp-height", "0.3", "--ramp-length", "20"},
      {"--law", "cycloidal", "--open", "70", "--close", "55", "--dwell", "8"},
      {"--law", "modified-trapezoid", "--close-law", "cycloidal", "--peak-at", "20"},
      {"--law", "modified-sine", "--ramp-height", "0.2", "--ramp-length", "15", "--ramp-blend", "1"},
      {"--law", "polydyne", "--polydyne-rpm", "6500", "--polydyne-fn", "900", "--ramp-height", "0.25",
       "--ramp-length", "20"},
      {"--law", "bspline", "--acc-bspline", "0,1.5,3,2,0.2,-1,-1.2,-1,-0.6,-0.2,0", "--bspline-degree", "4"},
      {"--law", "cycloidal", "--close-law", "bspline", "--acc-bspline", "0,2,1,-0.5,-1,-0.5,0"},
  };
  for (const auto& extra : cases) {
    TempDir tmp;
    const fs::path out = tmp / "lift.csv";
    std::vector<std::string> args = {"lift"};
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"--lift", "10.5", "--step", "0.5", "--out", out.string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    REQUIRE(r.exit_code == cli_ok);
    const Table t = read_table(out);
    CHECK(t.rows.size() == 720);
    CHECK_REL(column_max(t, 1), 10.5, tol::kLawLiftAnyRel);
  }
}

TEST_CASE("lift rejects bad options with exit 3, names the option and writes no file", "[cli][lift]") {
  struct Case {
    std::vector<std::string> args;
    std::string expect;  // on stderr
  };
  const std::vector<Case> cases = {
      {{"--law", "cycloidal", "--lift", "-2"}, "--lift"},
      {{"--law", "cycloidal", "--lift", "0"}, "--lift"},
      {{"--law", "parabolic"}, "unknown law 'parabolic'"},
      {{"--law", "cycloidal", "--close-law", "harmonic"}, "--close-law"},
      {{"--law", "cycloidal", "--duration", "400"}, "360"},
      {{"--law", "cycloidal", "--open", "200", "--close", "170"}, "--open + --dwell + --close"},
      {{"--law", "cycloidal", "--open", "60"}, "--close"},
      {{"--law", "cycloidal", "--duration", "120", "--open", "60", "--close", "60"}, "--duration"},
      {{"--law", "cycloidal", "--duration", "120", "--ramp-height", "0.3", "--ramp-length", "70"}, "--ramp-length"},
      {{"--law", "cycloidal", "--ramp-height", "12", "--ramp-length", "10"}, "--ramp-height"},
      {{"--law", "cycloidal", "--ramp-height", "0.3"}, "--ramp-length"},
      {{"--law", "cycloidal", "--ramp-height", "0.3", "--ramp-length", "10", "--close-ramp-length", "0"},
       "--close-ramp-length"},
      {{"--law", "cycloidal", "--dwell", "-1"}, "--dwell"},
      {{"--law", "cycloidal", "--peak-at", "360"}, "--peak-at"},
      {{"--law", "cycloidal", "--step", "0.7"}, "--step"},
      {{"--law", "cycloidal", "--step", "0"}, "--step"},
      {{"--law", "cycloidal", "--basis", "flywheel"}, "--basis"},
      {{"--law", "cycloidal", "--ramp-blend", "0"}, "--ramp-blend"},
      {{"--law", "bspline"}, "--acc-bspline"},
      {{"--law", "bspline", "--acc-bspline", "0,-1,1,0"}, "--acc-bspline"},
      {{"--law", "bspline", "--acc-bspline", "0,1,-1,0", "--bspline-degree", "7"}, "--bspline-degree"},
      {{"--law", "cycloidal", "--acc-bspline", "0,1,-1,0"}, "--acc-bspline"},
      {{"--law", "polydyne"}, "--polydyne-rpm"},
      {{"--law", "polydyne", "--polydyne-rpm", "6000"}, "--polydyne-fn"},
      {{"--law", "polydyne", "--polydyne-rpm", "9000", "--polydyne-fn", "150"}, "monotonic"},
      {{"--law", "cycloidal", "--polydyne-rpm", "6000"}, "--polydyne-rpm"},
      {{"--law", "polynomial-4567", "--ramp-height", "3", "--ramp-length", "6"}, "monotonic"},
  };
  for (const auto& c : cases) {
    TempDir tmp;
    const fs::path out = tmp / "lift.csv";
    std::vector<std::string> args = {"lift"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"--out", out.string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all() << "\nexpected on stderr: " << c.expect);
    CHECK(r.exit_code == cli_input_error);
    CHECK(contains(r.err, c.expect));
    CHECK(files_under(tmp.path()).empty());
  }
  // an output directory that does not exist
  TempDir tmp;
  const fs::path out = tmp / "missing" / "lift.csv";
  const auto r = run_camopt({"lift", "--law", "cycloidal", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(contains(r.err, out.parent_path().string()));
  CHECK(files_under(tmp.path()).empty());
}

TEST_CASE("lift --help names the unit of every numeric option", "[cli][lift]") {
  const auto r = run_camopt({"lift", "--help"});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto entries = help_entries(r.out);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"--lift", "mm"},          {"--duration", "deg"},      {"--open", "deg"},        {"--close", "deg"},
      {"--dwell", "deg"},        {"--ramp-height", "mm"},    {"--ramp-length", "deg"}, {"--close-ramp-height", "mm"},
      {"--close-ramp-length", "deg"}, {"--peak-at", "deg"}, {"--step", "deg"},       {"--polydyne-rpm", "rpm"},
      {"--polydyne-fn", "Hz"},   {"--ramp-blend", "fraction"}};
  for (const auto& [option, unit] : expected) {
    const HelpEntry* e = find_option(entries, option);
    INFO("option " << option);
    REQUIRE(e != nullptr);
    CHECK(has_bracketed_unit(e->text, unit));
  }
}
