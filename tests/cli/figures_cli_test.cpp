// --figures svg|png: each command writes its main plots as static images with its outputs,
// camopt report DIR --figures writes them for an existing folder, and the figures go with the
// run's output set (an earlier run's removed, none left by a failure).
#include <catch2/catch.hpp>
#include <cstdint>
#include <set>

#include "cli/cli_support.hpp"
#include "report/report_support.hpp"

namespace camopt::test {
namespace {

// the figure size (include/camopt/report/figures.hpp) [px]
constexpr std::uint32_t kWidth = 800, kHeight = 500;

// the commands that write a report, each a quick run; `out` the --out folder (a CSV for lift)
struct Job {
  std::string name;
  std::vector<std::string> args;
  bool lift_table = false;
};
std::vector<Job> jobs() {
  return {
      {"synthesize", {"synthesize", "designs/targets/rff_intake_lift.csv", "--design", "designs/roller_finger_follower.toml"}},
      {"kinematics", {"kinematics", "designs/roller_finger_follower.toml"}},
      {"optimize",
       {"optimize", "designs/roller_finger_follower.toml", "--constraints", "constraints/passenger_car_intake.toml",
        "--points", "720"}},
      {"dynamics", {"dynamics", "designs/bucket_tappet.toml", "--model", "rigid", "--rpm", "3000:6000:2"}},
      {"lift", {"lift", "--law", "cycloidal", "--lift", "9", "--duration", "120"}, true},
  };
}

// where a job's report is and what its figures are called: <plot id>.<ext> in the folder, or
// <stem>.<plot id>.<ext> beside a lift table
struct Written {
  fs::path dir, report;
  std::string prefix;
};
Written run_job(const TempDir& tmp, const Job& job, const std::vector<std::string>& extra) {
  const fs::path out = tmp / (job.lift_table ? job.name + ".csv" : job.name);
  std::vector<std::string> args = {"-q", "--threads", "2"};
  args.insert(args.end(), job.args.begin(), job.args.end());
  args.insert(args.end(), {"--out", out.string()});
  args.insert(args.end(), extra.begin(), extra.end());
  const RunResult r = run_camopt(args);
  INFO(r.command << "\n" << r.err);
  REQUIRE(r.exit_code == cli_ok);
  if (job.lift_table) return {tmp.path(), tmp / (job.name + ".report.html"), job.name + "."};
  return {out, out / "report.html", ""};
}

// the ids of the plots the page marks main, as file names with the prefix and extension
std::set<std::string> main_plot_files(const fs::path& report, const std::string& prefix, const std::string& ext) {
  std::set<std::string> names;
  const nlohmann::json data = page_data(read_file(report));
  for (const auto& p : data["plots"])
    if (p["main"].get<bool>()) names.insert(prefix + p["id"].get<std::string>() + ext);
  return names;
}

// the names of the files in dir that start with the prefix and end with the extension
std::set<std::string> files_named(const fs::path& dir, const std::string& prefix, const std::string& ext) {
  std::set<std::string> names;
  for (const fs::path& f : glob_files(dir, ext))
    if (f.filename().string().rfind(prefix, 0) == 0) names.insert(f.filename().string());
  return names;
}

// a PNG's signature and its IHDR chunk's width and height (big-endian, bytes 16..23)
void check_png(const fs::path& file) {
  INFO(file);
  const std::string bytes = read_file(file);
  REQUIRE(bytes.size() > 24);
  CHECK(bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  CHECK(bytes.compare(12, 4, "IHDR") == 0);
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  CHECK(be32(16) == kWidth);
  CHECK(be32(20) == kHeight);
}

void check_svg(const fs::path& file) {
  INFO(file);
  const std::string text = read_file(file);
  CHECK((text.rfind("<?xml", 0) == 0 || text.rfind("<svg", 0) == 0));
  CHECK(text.find("</svg>") != std::string::npos);
}

TEST_CASE("cli figures: --figures png writes each command's main plots as 800 x 500 PNG files", "[cli][report]") {
  TempDir tmp;
  for (const Job& job : jobs()) {
    INFO(job.name);
    const Written w = run_job(tmp, job, {"--figures", "png"});
    const std::set<std::string> expected = main_plot_files(w.report, w.prefix, ".png");
    CHECK_FALSE(expected.empty());
    CHECK(files_named(w.dir, w.prefix, ".png") == expected);
    CHECK(files_named(w.dir, w.prefix, ".svg").empty());
    for (const std::string& name : expected) check_png(w.dir / name);
  }
}

TEST_CASE("cli figures: --figures svg writes each command's main plots as SVG files", "[cli][report]") {
  TempDir tmp;
  for (const Job& job : jobs()) {
    INFO(job.name);
    const Written w = run_job(tmp, job, {"--figures", "svg"});
    const std::set<std::string> expected = main_plot_files(w.report, w.prefix, ".svg");
    CHECK_FALSE(expected.empty());
    CHECK(files_named(w.dir, w.prefix, ".svg") == expected);
    CHECK(files_named(w.dir, w.prefix, ".png").empty());
    for (const std::string& name : expected) check_svg(w.dir / name);
  }
}

TEST_CASE("cli figures: --figures with --no-report writes the figures alone", "[cli][report]") {
  TempDir tmp;
  const Job kin = jobs()[1];
  const Written w = run_job(tmp, kin, {"--no-report", "--figures", "svg"});
  CHECK_FALSE(fs::exists(w.report));
  // the ids of the same data's page, rebuilt
  REQUIRE(run_camopt({"report", w.dir.string()}).exit_code == cli_ok);
  CHECK(files_named(w.dir, "", ".svg") == main_plot_files(w.report, "", ".svg"));
}

TEST_CASE("cli figures: a bad --figures value exits 3 naming the option and writes nothing", "[cli][report]") {
  TempDir tmp;
  for (const Job& job : jobs()) {
    INFO(job.name);
    const fs::path out = tmp / (job.lift_table ? job.name + ".csv" : job.name);
    std::vector<std::string> args = job.args;
    args.insert(args.end(), {"--out", out.string(), "--figures", "jpeg"});
    const RunResult r = run_camopt(args);
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find("--figures") != std::string::npos);
    CHECK(r.err.find("jpeg") != std::string::npos);
  }
  CHECK(files_under(tmp.path()).empty());
  const RunResult report = run_camopt({"report", tmp.path().string(), "--figures", "gif"});
  CHECK(report.exit_code == cli_input_error);
  CHECK(report.err.find("--figures") != std::string::npos);
  CHECK(files_under(tmp.path()).empty());
}

TEST_CASE("cli figures: camopt report DIR --figures svg writes the figures of an existing folder", "[cli][report]") {
  TempDir tmp;
  const Written w = run_job(tmp, jobs()[0], {"--no-report"});
  CHECK(files_named(w.dir, "", ".svg").empty());
  const RunResult r = run_camopt({"report", w.dir.string(), "--figures", "svg"});
  INFO(r.err);
  REQUIRE(r.exit_code == cli_ok);
  const std::set<std::string> expected = main_plot_files(w.report, "", ".svg");
  CHECK_FALSE(expected.empty());
  CHECK(files_named(w.dir, "", ".svg") == expected);
  for (const std::string& name : expected) check_svg(w.dir / name);
  // stdout: the report's path, then each figure's
  const std::vector<std::string> lines = split_lines(r.out);
  REQUIRE(lines.size() == 1 + expected.size());
  CHECK(lines[0] == w.report.string());
  for (std::size_t i = 1; i < lines.size(); ++i) CHECK(expected.count(fs::path(lines[i]).filename().string()) == 1);
}

TEST_CASE("cli figures: a run removes an earlier run's figures and keeps other images", "[cli][report]") {
  TempDir tmp;
  const Job kin = jobs()[1];
  const Written w = run_job(tmp, kin, {"--figures", "png"});
  const std::set<std::string> pngs = main_plot_files(w.report, "", ".png");
  REQUIRE(files_named(w.dir, "", ".png") == pngs);
  write_text(w.dir / "sketch.png", "not camopt's");
  // the next run into the folder writes no figures: the earlier ones are gone with its set
  run_job(tmp, kin, {});
  CHECK(files_named(w.dir, "", ".png") == std::set<std::string>{"sketch.png"});
  // a run of another command into the folder removes the figures of the run the folder holds
  run_job(tmp, kin, {"--figures", "svg"});
  REQUIRE_FALSE(files_named(w.dir, "", ".svg").empty());
  const RunResult r = run_camopt({"-q", "dynamics", "designs/bucket_tappet.toml", "--model", "rigid", "--rpm", "6000",
                                  "--out", w.dir.string()});
  REQUIRE(r.exit_code == cli_ok);
  CHECK(files_named(w.dir, "", ".svg").empty());
  CHECK(fs::exists(w.dir / "sketch.png"));
}

TEST_CASE("cli figures: a figure that cannot be written leaves neither the report nor any figure", "[cli][report]") {
  TempDir tmp;
  const fs::path out = tmp / "kin";
  fs::create_directories(out / "svaj-lift.png");  // a directory where a figure goes
  const RunResult r = run_camopt({"-q", "kinematics", "designs/roller_finger_follower.toml", "--out", out.string(),
                                  "--figures", "png"});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("outputs are written, but not its report and figures") != std::string::npos);
  CHECK(r.err.find("svaj-lift.png") != std::string::npos);
  CHECK(fs::exists(out / "kinematics.csv"));
  CHECK_FALSE(fs::exists(out / "report.html"));
  CHECK(glob_files(out, ".png").empty());
  CHECK(glob_files(out, ".tmp").empty());
}

}  // namespace
}  // namespace camopt::test
