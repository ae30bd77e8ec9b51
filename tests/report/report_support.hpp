#pragma once
// shared by the report tests: result folders made once per test run by the camopt binary, an
// independent CSV reader and base64 float32 decoder, lookups into a ReportData.
#include <cstdint>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/report/report.hpp"
#include "cli/cli_support.hpp"

namespace camopt::test {

// the result folders of the bundled jobs, each run once (on first use) into one temp dir
inline fs::path result_folder(const std::string& name) {
  static TempDir root;
  static std::map<std::string, fs::path> made;
  if (const auto it = made.find(name); it != made.end()) return it->second;
  const std::string out = root.file(name);
  const std::map<std::string, std::vector<std::string>> jobs = {
      {"kin_default", {"kinematics", "designs/roller_finger_follower.toml", "--out", out}},
      {"kin_all", {"kinematics", "designs/roller_finger_follower.toml", "--outputs", "all", "--rpm", "6000", "--out", out}},
      {"kin_cvvl17",
       {"kinematics", "designs/cvvl_swing_cam.toml", "--outputs", "all", "--control", "0:16:17", "--step", "0.5", "--out", out}},
      {"synthesize",
       {"synthesize", "designs/targets/rff_intake_lift.csv", "--design", "designs/roller_finger_follower.toml", "--out", out}},
      {"optimize",
       {"optimize", "designs/roller_finger_follower.toml", "--constraints", "constraints/passenger_car_intake.toml",
        "--points", "720", "--out", out}},
      {"rigid", {"dynamics", "designs/cvvl_swing_cam.toml", "--model", "rigid", "--rpm", "1000:7000:4", "--out", out}},
      {"rigid_map",
       {"dynamics", "designs/cvvl_swing_cam.toml", "--model", "rigid", "--rpm", "3000:6000:3", "--control", "0:16:3",
        "--out", out}},
      {"flexible", {"dynamics", "designs/roller_finger_follower.toml", "--model", "flexible", "--rpm", "6000", "--out", out}},
      {"flexible_hla",
       {"dynamics", "designs/cvvl_swing_cam_hla.toml", "--model", "flexible", "--rpm", "3000,6000", "--out", out}},
      {"modes", {"dynamics", "designs/roller_finger_follower.toml", "--model", "modes", "--out", out}},
      {"lift", {"lift", "--law", "cycloidal", "--lift", "9", "--duration", "120", "--step", "0.5", "--out", out + ".csv"}},
  };
  const auto job = jobs.find(name);
  REQUIRE(job != jobs.end());
  std::vector<std::string> args = {"-q", "--threads", "2"};
  args.insert(args.end(), job->second.begin(), job->second.end());
  const RunResult r = run_camopt(args);
  INFO(r.command << "\n" << r.err);
  REQUIRE(r.exit_code == cli_ok);
  made[name] = name == "lift" ? fs::path(out + ".csv") : fs::path(out);
  return made[name];
}

// a camopt CSV read independently of the report module: header names, columns of doubles
struct TestCsv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;
  const std::vector<double>& operator[](const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return columns[i];
    FAIL("no column " << name);
    return columns.front();
  }
};
inline TestCsv read_test_csv(const fs::path& path) {
  TestCsv t;
  std::istringstream in(read_file(path));
  std::string line, cell;
  std::getline(in, line);
  std::istringstream h(line);
  while (std::getline(h, cell, ',')) t.header.push_back(cell);
  t.columns.resize(t.header.size());
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (std::size_t c = 0; std::getline(row, cell, ','); ++c) t.columns[c].push_back(std::stod(cell));
  }
  return t;
}

// base64 of little-endian float32 decoded (written here, apart from the writer's encoder)
inline std::vector<float> decode_float32(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<unsigned char> bytes;
  unsigned bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<unsigned>(value(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<unsigned char>((bits >> count) & 0xFF));
    }
  }
  std::vector<float> out(bytes.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t u = bytes[4 * i] | (bytes[4 * i + 1] << 8) | (bytes[4 * i + 2] << 16) |
                            (static_cast<std::uint32_t>(bytes[4 * i + 3]) << 24);
    std::memcpy(&out[i], &u, 4);
  }
  return out;
}

inline const report::Plot& plot_of(const report::ReportData& d, const std::string& id) {
  for (const auto& p : d.plots)
    if (p.id == id) return p;
  FAIL("no plot " << id);
  return d.plots.front();
}
inline bool has_plot(const report::ReportData& d, const std::string& id) {
  for (const auto& p : d.plots)
    if (p.id == id) return true;
  return false;
}
inline const report::Table& table_of(const report::ReportData& d, const std::string& id) {
  for (const auto& t : d.tables)
    if (t.id == id) return t;
  FAIL("no table " << id);
  return d.tables.front();
}

// the data JSON of a report.html
inline nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"camopt-data\">";
  const std::size_t begin = html.find(open);
  REQUIRE(begin != std::string::npos);
  const std::size_t end = html.find("</script>", begin);
  return nlohmann::json::parse(html.substr(begin + open.size(), end - begin - open.size()));
}

}  // namespace camopt::test
