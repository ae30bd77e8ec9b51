// the table formats of camopt kinematics and dynamics (docs/outputs.md, "Table formats"):
// the wide CSV is the long one re-indexed, exactly; the .npz holds the long CSV's values bit
// for bit and the report built from it is the CSV's; --outputs picks contacts and nodes by
// name; a wrong name, a wide table of a model without one, a damaged archive: exit 3, named.
#include <bit>
#include <catch2/catch.hpp>
#include <charconv>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "camopt/io/npz.hpp"
#include "cli/cli_support.hpp"

using namespace camopt::test;

namespace {

const std::string kCvvl = (source_dir() / "designs/cvvl_swing_cam.toml").string();

// a CSV as camopt writes it, read independently of camopt's readers: comma cells, an empty
// cell NaN; columns by name, in order
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
  const std::vector<double>& at(const std::string& name) const {
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) return values[c];
    FAIL("no column " << name);
    return values.front();
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char ch : line) {
    if (ch == ',') cells.emplace_back();
    else cells.back().push_back(ch);
  }
  return cells;
}

Table read_table(const fs::path& file) {
  Table t;
  const std::vector<std::string> lines = split_lines(read_file(file));
  REQUIRE(!lines.empty());
  t.names = split(lines[0]);
  t.values.resize(t.names.size());
  for (std::size_t l = 1; l < lines.size(); ++l) {
    if (lines[l].empty()) continue;
    const auto cells = split(lines[l]);
    REQUIRE(cells.size() == t.names.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      double v = std::numeric_limits<double>::quiet_NaN();
      if (!cells[c].empty()) REQUIRE(std::from_chars(cells[c].data(), cells[c].data() + cells[c].size(), v).ec == std::errc());
      t.values[c].push_back(v);
    }
  }
  return t;
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

std::string number_text(double v) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

// every value of the wide table at its place in the long one: the long rows of each key
// values, in angle order, column <quantity>@<key>=<value>...
void check_wide_is_long(const Table& wide, const Table& lng, const std::vector<std::string>& keys,
                        const std::vector<std::string>& angles) {
  // the long rows of each key combination, by its column suffix
  std::map<std::string, std::vector<std::size_t>> rows;
  for (std::size_t r = 0; r < lng.values[0].size(); ++r) {
    std::string suffix;
    for (const auto& k : keys) suffix += "@" + k + "=" + number_text(lng.at(k)[r]);
    rows[suffix].push_back(r);
  }
  std::size_t checked = 0;
  for (const auto& a : angles)
    for (const auto& [suffix, group] : rows)
      for (std::size_t i = 0; i < group.size(); ++i) REQUIRE(same_bits(wide.at(a)[i], lng.at(a)[group[i]]));
  for (std::size_t c = angles.size(); c < wide.names.size(); ++c) {
    const std::string& name = wide.names[c];
    const std::size_t at = name.find('@');
    REQUIRE(at != std::string::npos);
    const auto group = rows.find(name.substr(at));
    REQUIRE(group != rows.end());
    const auto& column = lng.at(name.substr(0, at));
    REQUIRE(group->second.size() == wide.values[c].size());
    for (std::size_t i = 0; i < group->second.size(); ++i) {
      INFO(name << " row " << i);
      REQUIRE(same_bits(wide.values[c][i], column[group->second[i]]));
      ++checked;
    }
  }
  // every long value but the keys and angles is somewhere in the wide table
  CHECK(checked == (lng.names.size() - keys.size() - angles.size()) * lng.values[0].size());
}

}  // namespace

TEST_CASE("formats: the wide kinematics and rigid dynamics tables are the long ones re-indexed, exactly",
          "[cli][formats]") {
  TempDir tmp;
  const std::vector<std::pair<std::vector<std::string>, std::vector<std::string>>> runs = {
      {{"kinematics", kCvvl, "--control", "0:16:3", "--outputs", "all", "--rpm", "6000", "--step", "1"}, {"control_deg"}},
      {{"dynamics", kCvvl, "--model", "rigid", "--rpm", "2000,6000", "--control", "0,8", "--step", "1"},
       {"rpm", "control_deg"}}};
  for (const auto& [args, keys] : runs) {
    INFO(args[0]);
    const std::string table = args[0] == "kinematics" ? "kinematics.csv" : "dynamics.csv";
    std::vector<Table> tables;
    for (const std::string format : {"long", "wide"}) {
      std::vector<std::string> a = args;
      for (const std::string& extra : {std::string("--format"), format, std::string("--out"), (tmp / format).string(),
                                       std::string("--no-report")})
        a.push_back(extra);
      const RunResult r = run_camopt(a);
      INFO(r.command << "\n" << r.all());
      REQUIRE(r.exit_code == cli_ok);
      tables.push_back(read_table(tmp / format / table));
    }
    const std::vector<std::string> angles =
        args[0] == "kinematics" ? std::vector<std::string>{"cam_deg"} : std::vector<std::string>{"cam_deg", "crank_deg"};
    check_wide_is_long(tables[1], tables[0], keys, angles);
    // the wide table: one row per angle, the long one a row per key values and angle
    CHECK(tables[0].values[0].size() == tables[1].values[0].size() * (args[0] == "kinematics" ? 3 : 4));
  }
}

TEST_CASE("formats: the .npz archive holds the long CSV's values bit for bit, and the report is the CSV's",
          "[cli][formats]") {
  TempDir tmp;
  const std::vector<std::string> run = {"kinematics", kCvvl, "--control", "0:16:3", "--outputs", "all", "--step", "1"};
  std::vector<std::string> csv_run = run, npz_run = run;
  for (const std::string& a : {std::string("--out"), (tmp / "csv").string()}) csv_run.push_back(a);
  for (const std::string& a : {std::string("--format"), std::string("npz"), std::string("--out"), (tmp / "npz").string()})
    npz_run.push_back(a);
  const RunResult a = run_camopt(csv_run), b = run_camopt(npz_run);
  REQUIRE(a.exit_code == cli_ok);
  REQUIRE(b.exit_code == cli_ok);
  CHECK(!fs::exists(tmp / "npz" / "kinematics.csv"));
  const Table csv = read_table(tmp / "csv" / "kinematics.csv");
  const camopt::io::Columns npz = camopt::io::read_npz((tmp / "npz" / "kinematics.npz").string());
  REQUIRE(npz.header == csv.names);
  for (std::size_t c = 0; c < csv.names.size(); ++c)
    for (std::size_t r = 0; r < csv.values[c].size(); ++r) {
      INFO(csv.names[c] << " row " << r);
      REQUIRE(same_bits(npz.values[c][r], csv.values[c][r]));
    }
  // the report from the archive: the same page as from the CSV, once both folders hold the
  // same summary (its run time is the run's) and the page names the same folder
  fs::copy_file(tmp / "csv" / "summary.json", tmp / "npz" / "summary.json", fs::copy_options::overwrite_existing);
  fs::rename(tmp / "csv", tmp / "run");
  REQUIRE(run_camopt({"report", (tmp / "run").string()}).exit_code == cli_ok);
  const std::string from_csv = read_file(tmp / "run" / "report.html");
  fs::rename(tmp / "run", tmp / "csv");
  fs::rename(tmp / "npz", tmp / "run");
  REQUIRE(run_camopt({"report", (tmp / "run").string()}).exit_code == cli_ok);
  CHECK(read_file(tmp / "run" / "report.html") == from_csv);

  // a damaged archive: exit 3, the file and the fault named
  const std::string bytes = read_file(tmp / "run" / "kinematics.npz");
  write_text(tmp / "run" / "kinematics.npz", bytes.substr(0, bytes.size() / 2));
  const RunResult bad = run_camopt({"report", (tmp / "run").string()});
  CHECK(bad.exit_code == cli_input_error);
  CHECK(bad.err.find((tmp / "run" / "kinematics.npz").string() + ": not a .npz archive as camopt writes it") !=
        std::string::npos);
  CHECK(bad.err.find("truncated") != std::string::npos);
}

TEST_CASE("formats: --outputs picks contacts and nodes by name, and a wrong name is an input error listing the names",
          "[cli][formats]") {
  TempDir tmp;
  const auto columns_of = [&](const std::string& outputs) {
    const fs::path out = tmp / outputs.substr(0, outputs.find(':'));
    const RunResult r = run_camopt({"kinematics", kCvvl, "--outputs", outputs, "--step", "2", "--out", out.string(),
                                    "--no-report"});
    INFO(r.all());
    REQUIRE(r.exit_code == cli_ok);
    return read_table(out / "kinematics.csv");
  };
  const Table all = columns_of("all");
  const Table some = columns_of("jerk,contact:swing_roller,node:finger");
  // the picked contact's and node's columns, with the lift; the same values as with all
  std::vector<std::string> expected = {"control_deg", "cam_deg", "lift_mm", "vel_mm_per_deg", "acc_mm_per_deg2",
                                       "jerk_mm_per_deg3"};
  for (const auto& name : all.names)
    if (name.rfind("finger_", 0) == 0 || name.rfind("swing_roller_", 0) == 0) expected.push_back(name);
  CHECK(some.names == expected);
  CHECK(expected.size() > 10);
  for (std::size_t c = 0; c < some.names.size(); ++c)
    for (std::size_t r = 0; r < some.values[c].size(); ++r) REQUIRE(same_bits(some.values[c][r], all.at(some.names[c])[r]));

  const RunResult bad = run_camopt({"kinematics", kCvvl, "--outputs", "lift,contact:cam", "--out", (tmp / "x").string()});
  CHECK(bad.exit_code == cli_input_error);
  CHECK(bad.err.find("--outputs: contact:cam: " + kCvvl + " has no contact 'cam' (contacts: cam_roller, swing_roller") !=
        std::string::npos);
  const RunResult bad_node = run_camopt({"kinematics", kCvvl, "--outputs", "node:cam", "--out", (tmp / "x").string()});
  CHECK(bad_node.exit_code == cli_input_error);
  CHECK(bad_node.err.find("has no node 'cam' (nodes: ") != std::string::npos);
  CHECK(!fs::exists(tmp / "x"));
}

TEST_CASE("formats: a wide table of a model without one angle grid is an input error", "[cli][formats]") {
  TempDir tmp;
  const RunResult r = run_camopt({"dynamics", (source_dir() / "designs/roller_finger_follower.toml").string(), "--model",
                                  "flexible", "--rpm", "6000", "--format", "wide", "--out", (tmp / "x").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("--format wide: value 'wide' is for --model rigid with rigid contacts") != std::string::npos);
}
