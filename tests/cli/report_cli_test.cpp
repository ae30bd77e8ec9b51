// the report each run writes after its outputs, --no-report, and camopt report DIR.
#include <catch2/catch.hpp>

#include "cli/cli_support.hpp"

namespace camopt::test {
namespace {

bool file_exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

TEST_CASE("cli report: a run writes report.html and camopt report rebuilds it byte for byte", "[cli][report]") {
  // the run makes its page from the table it holds in memory, camopt report from the file:
  // the same bytes (empty cells of open contacts in the rigid run, several speeds and
  // control positions, the flexible and compliant models)
  TempDir tmp;
  const std::vector<std::vector<std::string>> runs = {
      {"kinematics", "designs/roller_finger_follower.toml", "--outputs", "all", "--rpm", "6000"},
      {"kinematics", "designs/cvvl_swing_cam.toml", "--control", "0:16:3", "--step", "1"},
      {"dynamics", "designs/roller_finger_follower.toml", "--model", "rigid", "--rpm", "3000:12000:3"},
      {"dynamics", "designs/cvvl_swing_cam.toml", "--model", "rigid", "--rpm", "3000:6000:2", "--control", "0:16:2"},
      {"dynamics", "designs/roller_finger_follower.toml", "--model", "flexible", "--rpm", "6000"},
      {"dynamics", "designs/roller_finger_follower.toml", "--model", "rigid", "--contacts", "compliant", "--rpm", "3000"},
  };
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string out = tmp.file("run" + std::to_string(i));
    std::vector<std::string> args = {"-q"};
    args.insert(args.end(), runs[i].begin(), runs[i].end());
    args.insert(args.end(), {"--out", out});
    const RunResult run = run_camopt(args);
    INFO(run.command << "\n" << run.err);
    REQUIRE(run.exit_code == cli_ok);
    const std::string first = read_file(fs::path(out) / "report.html");
    REQUIRE(first.size() > 50000);  // uPlot inlined
    CHECK(first.find("\"command\":\"" + runs[i][0]) != std::string::npos);
    fs::remove(fs::path(out) / "report.html");
    const RunResult again = run_camopt({"report", out});
    REQUIRE(again.exit_code == cli_ok);
    CHECK(again.out == (fs::path(out) / "report.html").string() + "\n");
    CHECK(read_file(fs::path(out) / "report.html") == first);
  }
}

TEST_CASE("cli report: every folder command writes its report, --no-report none", "[cli][report]") {
  TempDir tmp;
  const std::vector<std::vector<std::string>> runs = {
      {"synthesize", "designs/targets/rff_intake_lift.csv", "--design", "designs/roller_finger_follower.toml"},
      {"dynamics", "designs/bucket_tappet.toml", "--model", "rigid", "--rpm", "6000"},
      {"dynamics", "designs/bucket_tappet.toml", "--model", "flexible", "--rpm", "6000"},
      {"dynamics", "designs/bucket_tappet.toml", "--model", "modes"},
  };
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string out = tmp.file("run" + std::to_string(i));
    std::vector<std::string> args = {"-q"};
    args.insert(args.end(), runs[i].begin(), runs[i].end());
    args.insert(args.end(), {"--out", out});
    const RunResult r = run_camopt(args);
    INFO(r.command << "\n" << r.err);
    REQUIRE(r.exit_code == cli_ok);
    CHECK(file_exists(fs::path(out) / "report.html"));
    // the same run with --no-report: the earlier report is gone with the earlier set
    args.push_back("--no-report");
    const RunResult quiet = run_camopt(args);
    REQUIRE(quiet.exit_code == cli_ok);
    CHECK_FALSE(file_exists(fs::path(out) / "report.html"));
  }
}

TEST_CASE("cli report: lift writes <stem>.report.html beside its CSV", "[cli][report]") {
  TempDir tmp;
  const std::string csv = tmp.file("intake.csv");
  REQUIRE(run_camopt({"-q", "lift", "--law", "cycloidal", "--out", csv}).exit_code == cli_ok);
  const std::string page = read_file(tmp / "intake.report.html");
  CHECK(page.find("\"command\":\"lift\"") != std::string::npos);
  fs::remove(tmp / "intake.report.html");
  REQUIRE(run_camopt({"-q", "lift", "--law", "cycloidal", "--out", csv, "--no-report"}).exit_code == cli_ok);
  CHECK_FALSE(file_exists(tmp / "intake.report.html"));
  const RunResult r = run_camopt({"report", csv});
  REQUIRE(r.exit_code == cli_ok);
  CHECK(read_file(tmp / "intake.report.html") == page);
}

TEST_CASE("cli report: a folder without results or with a bad CSV exits 3 naming it and writes nothing",
          "[cli][report]") {
  TempDir tmp;
  const RunResult empty = run_camopt({"report", tmp.file("empty")});
  CHECK(empty.exit_code == cli_input_error);
  CHECK(empty.err.find("empty") != std::string::npos);
  fs::create_directories(tmp / "none");
  const RunResult none = run_camopt({"report", tmp.file("none")});
  CHECK(none.exit_code == cli_input_error);
  CHECK(none.err.find("no camopt result") != std::string::npos);
  CHECK(files_under(tmp / "none").empty());
  // a kinematics folder whose CSV was damaged: named with its line, the old report kept
  const std::string out = tmp.file("kin");
  REQUIRE(run_camopt({"-q", "kinematics", "designs/bucket_tappet.toml", "--out", out}).exit_code == cli_ok);
  const std::string before = read_file(fs::path(out) / "report.html");
  std::string csv = read_file(fs::path(out) / "kinematics.csv");
  csv.insert(csv.find('\n', csv.find('\n') + 1) + 1, "0,1,x,2,3,4\n");  // a bad line 3
  write_text(fs::path(out) / "kinematics.csv", csv);
  const RunResult bad = run_camopt({"report", out});
  CHECK(bad.exit_code == cli_input_error);
  CHECK(bad.err.find("kinematics.csv:3") != std::string::npos);
  CHECK(read_file(fs::path(out) / "report.html") == before);
  CHECK(glob_files(out, ".tmp").empty());
  CHECK(files_under(out).size() == 3);
}

TEST_CASE("cli report: the 17-position CVVL report with every output is under 5 MB", "[cli][report]") {
  TempDir tmp;
  const std::string out = tmp.file("cvvl");
  const RunResult r = run_camopt({"-q", "--threads", "2", "kinematics", "designs/cvvl_swing_cam.toml", "--outputs", "all",
                                  "--control", "0:16:17", "--step", "0.5", "--out", out});
  REQUIRE(r.exit_code == cli_ok);
  const auto size = fs::file_size(fs::path(out) / "report.html");
  INFO("report.html: " << size << " bytes");
  CHECK(size < 5u * 1024u * 1024u);
  const std::string page = read_file(fs::path(out) / "report.html");
  CHECK(page.find("\"control 16 deg\"") != std::string::npos);
}

TEST_CASE("cli report: validate writes no report and says so in its help", "[cli][report]") {
  const RunResult help = run_camopt({"validate", "--help"});
  CHECK(help.exit_code == cli_ok);
  CHECK(help.out.find("no report") != std::string::npos);
  const RunResult report_help = run_camopt({"report", "--help"});
  CHECK(report_help.exit_code == cli_ok);
  CHECK(report_help.out.find("fetches nothing") != std::string::npos);
}

}  // namespace
}  // namespace camopt::test
