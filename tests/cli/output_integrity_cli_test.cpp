// what a run leaves in its output folder: one whole set of files or the previous set
// untouched, never a mix, never a temporary file, never a replaced link, device or fifo;
// a design.toml that can be moved with its folder.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "cli_support.hpp"

extern char** environ;

using namespace camopt::test;

namespace {

const std::string kRff = (source_dir() / "designs/roller_finger_follower.toml").string();
const std::string kTarget = (source_dir() / "designs/targets/rff_intake_lift.csv").string();

// entries of a folder whose name marks an output not yet renamed into place
std::vector<std::string> temp_files_in(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) names.push_back(e.path().filename());
  return names;
}

// every entry of a folder, sorted
std::vector<std::string> entries_of(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

// data rows of a CSV file (lines after the header)
std::size_t data_rows(const fs::path& csv) {
  const auto lines = split_lines(read_file(csv));
  return lines.empty() ? 0 : lines.size() - 1;
}

// the inode facts that tell whether a special file is still the one it was
struct Identity {
  bool exists = false;
  mode_t mode = 0;
  dev_t rdev = 0;
  ino_t inode = 0;
  bool operator==(const Identity&) const = default;
};
Identity identity_of(const fs::path& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) return {};
  return {true, info.st_mode, info.st_rdev, info.st_ino};
}

// start camopt with `args`, its output discarded, SIGINT and SIGTERM at their default action
pid_t spawn_camopt(const std::vector<std::string>& args) {
  std::vector<std::string> argv_text = {camopt_binary().string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &files, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) throw std::runtime_error("posix_spawn failed for " + argv_text[0]);
  return pid;
}

// the wait status of a spawned run
int wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waitpid failed");
  return status;
}

// significant digits of a decimal number's text: no sign, point, exponent, or leading and
// trailing zeros ("0.040" has 1, "17.600000000000001" has 17)
std::size_t significant_digits(std::string_view number) {
  number = number.substr(0, number.find_first_of("eE"));
  std::string digits;
  for (const char c : number)
    if (std::isdigit(static_cast<unsigned char>(c))) digits += c;
  const auto first = digits.find_first_not_of('0');
  if (first == std::string::npos) return 0;
  return digits.find_last_not_of('0') - first + 1;
}

}  // namespace

// ---- one set, checked before the first rename ---------------------------------------------

TEST_CASE("a directory at one output path is an input error naming it, before any output is renamed",
          "[cli][outputs]") {
  struct Case {
    std::vector<std::string> args;
    std::string blocked;                // made a directory before the run
    std::vector<std::string> expected;  // the outputs that must not appear
  };
  const std::vector<Case> cases = {
      {{"kinematics", kRff}, "summary.json", {"kinematics.csv"}},
      {{"dynamics", kRff, "--model", "rigid", "--rpm", "3000"}, "summary.json", {"dynamics.csv"}},
      {{"dynamics", kRff, "--model", "modes"}, "summary.json", {"modes.csv"}},
      {{"synthesize", kTarget, "--design", kRff}, "report.json", {"profile.csv", "design.toml", "profile.dxf"}},
      // a name the run does not write this time is checked too: the run would remove it
      {{"dynamics", kRff, "--model", "rigid", "--rpm", "3000"}, "modes.csv", {"dynamics.csv", "summary.json"}},
  };
  for (const auto& c : cases) {
    TempDir tmp;
    const fs::path out = tmp / "o";
    fs::create_directories(out / c.blocked);
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--out", out.string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find("cannot write '" + (out / c.blocked).string() + "': it is a directory") != std::string::npos);
    for (const auto& name : c.expected) CHECK_FALSE(fs::exists(out / name));
    CHECK(temp_files_in(out).empty());
    CHECK(fs::is_directory(out / c.blocked));
  }
  // the single file of lift
  TempDir tmp;
  fs::create_directories(tmp / "lift.csv");
  const auto r = run_camopt({"lift", "--law", "polynomial-345", "--out", (tmp / "lift.csv").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("lift.csv': it is a directory") != std::string::npos);
  CHECK(entries_of(tmp.path()) == std::vector<std::string>{"lift.csv"});
}

// ---- the folder lock ----------------------------------------------------------------------

TEST_CASE("two runs into one folder at once each commit a whole set: the folder never holds a mix",
          "[cli][outputs]") {
  // the two runs differ in step, 7201 or 7501 rows, and the summary says which; their run
  // times are close, so that their commits meet (without the lock, 1 to 3 trials in 20 here
  // left one run's CSV beside the other's summary; the io test of the lock is deterministic)
  TempDir tmp;
  const fs::path out = tmp / "o";
  for (int trial = 0; trial < 16; ++trial) {
    RunResult a, b;
    std::thread first([&] { a = run_camopt_unchecked({"kinematics", kRff, "--step", "0.05", "--out", out.string()}); });
    std::thread second([&] { b = run_camopt_unchecked({"kinematics", kRff, "--step", "0.048", "--out", out.string()}); });
    first.join();
    second.join();
    check_no_unexpected_warning(a.command, a.err);
    check_no_unexpected_warning(b.command, b.err);
    INFO("trial " << trial << "\n" << a.all() << b.all());
    REQUIRE(a.exit_code == cli_ok);
    REQUIRE(b.exit_code == cli_ok);
    const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
    const std::size_t points = summary["points_per_position"].get<std::size_t>();
    CHECK((points == 7201 || points == 7501));
    CHECK(data_rows(out / "kinematics.csv") == points);
    CHECK(entries_of(out) == std::vector<std::string>{"kinematics.csv", "report.html", "summary.json"});
  }
}

// ---- signals ------------------------------------------------------------------------------

TEST_CASE("a run stopped by SIGTERM or SIGINT while it writes leaves no temporary file", "[cli][outputs]") {
  // 90001 points: a CSV of about 9 MB and its report, so the writes take a while (tenths of
  // a second in a Release build, seconds under the sanitizers) while the polling below sees
  // a temporary file within 0.2 ms
  const std::vector<std::string> args = {"kinematics", kRff, "--step", "0.004"};
  TempDir tmp;

  SECTION("the signal sent as soon as a temporary file appears") {
    for (const int signal_number : {SIGTERM, SIGINT}) {
      const fs::path out = tmp / ("o" + std::to_string(signal_number));
      std::vector<std::string> run = args;
      run.insert(run.end(), {"--out", out.string()});
      const pid_t pid = spawn_camopt(run);
      bool seen = false;
      int status = 0;
      for (;;) {
        if (!temp_files_in(out).empty()) {
          seen = true;
          ::kill(pid, signal_number);
          status = wait_for(pid);
          break;
        }
        if (::waitpid(pid, &status, WNOHANG) == pid) break;  // finished first: nothing to check
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      INFO("signal " << signal_number);
      REQUIRE(seen);
      CHECK(WIFSIGNALED(status));
      CHECK(WTERMSIG(status) == signal_number);
      CHECK(temp_files_in(out).empty());
      CHECK_FALSE(fs::exists(out / "kinematics.csv"));  // the set was not committed
    }
  }

  SECTION("the signal sent after a range of delays") {
    // the time of a whole run, then signals spread over it
    const fs::path timed = tmp / "timed";
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> run = args;
    run.insert(run.end(), {"--out", timed.string()});
    const int timed_status = wait_for(spawn_camopt(run));
    REQUIRE(WIFEXITED(timed_status));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int k = 1; k <= 8; ++k) {
      const fs::path out = tmp / ("d" + std::to_string(k));
      run = args;
      run.insert(run.end(), {"--out", out.string()});
      const pid_t pid = spawn_camopt(run);
      std::this_thread::sleep_for(std::chrono::duration<double>(seconds * k / 9.0));
      ::kill(pid, k % 2 ? SIGTERM : SIGINT);
      wait_for(pid);
      INFO("signal after " << seconds * k / 9.0 << " s of a " << seconds << " s run");
      CHECK(temp_files_in(out).empty());
      // either the whole set or none of it
      CHECK(fs::exists(out / "kinematics.csv") == fs::exists(out / "summary.json"));
    }
  }
}

TEST_CASE("SIGINT during one long flexible run ends it by the signal, with nothing written", "[cli][outputs]") {
  // one run (one speed, one control position) of many revolutions from rest at a tight
  // tolerance: seconds of integration, the signal sent well inside it
  TempDir tmp;
  const fs::path out = tmp / "o";
  const std::string cvvl = (source_dir() / "designs/cvvl_swing_cam.toml").string();
  const pid_t pid = spawn_camopt({"dynamics", cvvl, "--model", "flexible", "--rpm", "6000", "--revolutions", "12",
                                  "--start", "rest", "--rtol", "1e-8", "--atol", "1e-9", "--out", out.string()});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  int status = 0;
  REQUIRE(::waitpid(pid, &status, WNOHANG) == 0);  // still integrating
  ::kill(pid, SIGINT);
  status = wait_for(pid);
  CHECK(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGINT);
  CHECK_FALSE(fs::exists(out / "dynamics.csv"));
  CHECK_FALSE(fs::exists(out / "summary.json"));
  CHECK(temp_files_in(out).empty());
}

// ---- a previous run's files ---------------------------------------------------------------

TEST_CASE("a run removes the files of its set that it did not write, and nothing else", "[cli][outputs]") {
  TempDir tmp;
  const fs::path out = tmp / "o";
  fs::create_directories(out);
  write_text(out / "notes.txt", "mine\n");
  auto r = run_camopt({"dynamics", kRff, "--model", "rigid", "--rpm", "3000", "--out", out.string()});
  REQUIRE(r.exit_code == cli_ok);
  CHECK(entries_of(out) == std::vector<std::string>{"dynamics.csv", "notes.txt", "report.html", "summary.json"});
  // a modes run: its summary beside the rigid run's dynamics.csv would be a mix
  r = run_camopt({"dynamics", kRff, "--model", "modes", "--out", out.string()});
  INFO(r.all());
  REQUIRE(r.exit_code == cli_ok);
  CHECK(entries_of(out) == std::vector<std::string>{"modes.csv", "notes.txt", "report.html", "summary.json"});
  CHECK(read_file(out / "notes.txt") == "mine\n");
}

TEST_CASE("a failing re-run leaves the previous set as it was, a different one replaces it whole",
          "[cli][outputs]") {
  TempDir tmp;
  const fs::path out = tmp / "o";
  auto r = run_camopt({"synthesize", kTarget, "--design", kRff, "--out", out.string()});
  REQUIRE(r.exit_code == cli_ok);
  const std::vector<std::string> set = {"design.toml", "grinding.csv", "profile.csv", "profile.dxf", "report.html",
                                        "report.json"};
  REQUIRE(entries_of(out) == set);
  std::map<std::string, std::string> before;
  for (const auto& name : set) before[name] = read_file(out / name);

  // failing runs (bad input, numerical failure): the previous set, byte for byte
  write_text(tmp / "bad.csv", "cam_deg,lift_mm\n0,0\n10,1\n20,3\n30,5\n40,6\n50,6.5\n");
  r = run_camopt({"synthesize", (tmp / "bad.csv").string(), "--design", kRff, "--out", out.string()});
  CHECK(r.exit_code == cli_input_error);
  r = run_camopt({"synthesize", kTarget, "--design", kRff, "--max-round-trip-error", "1e-15", "--out",
                  out.string()});
  CHECK(r.exit_code == cli_numerical_failure);
  CHECK(entries_of(out) == set);
  for (const auto& name : set) CHECK(read_file(out / name) == before[name]);

  // an infeasible optimisation commits its report alone: the synthesized profile, its
  // drawing and grinding table would read as the optimiser's
  std::string constraints = read_file(source_dir() / "constraints/passenger_car_intake.toml");
  const auto at = constraints.find("\nmax_lift_mm");
  REQUIRE(at != std::string::npos);
  constraints.insert(at + 1, "min_max_lift_mm = 8.9\n");
  constraints = std::regex_replace(constraints, std::regex("\nmax_lift_mm *=[^\n]*"), "\nmax_lift_mm = 9.0");
  constraints = std::regex_replace(constraints, std::regex("\ngrid_step_deg *=[^\n]*"), "\ngrid_step_deg = 2.0");
  write_text(tmp / "set.toml", constraints);
  r = run_camopt({"optimize", kRff, "--constraints", (tmp / "set.toml").string(), "--solver", "ipopt", "--out",
                  out.string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_numerical_failure);
  CHECK(entries_of(out) == std::vector<std::string>{"report.html", "report.json"});
  CHECK(read_file(out / "report.json").find("conflicting_constraints") != std::string::npos);
}

// ---- links, devices and fifos -------------------------------------------------------------

TEST_CASE("an output that is a symbolic link, a fifo or a device is refused and left as it was", "[cli][outputs]") {
  TempDir tmp;
  const std::vector<std::string> lift = {"lift", "--law", "polynomial-345", "--out"};
  const auto run_lift = [&](const fs::path& out) {
    std::vector<std::string> args = lift;
    args.push_back(out.string());
    return run_camopt(args);
  };

  // a symbolic link as the output file: the file it names keeps its content
  write_text(tmp / "real.csv", "keep\n");
  fs::create_symlink(tmp / "real.csv", tmp / "link.csv");
  auto r = run_lift(tmp / "link.csv");
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("link.csv': it is a symbolic link") != std::string::npos);
  CHECK(fs::is_symlink(tmp / "link.csv"));
  CHECK(read_file(tmp / "real.csv") == "keep\n");

  // a fifo as the output file: refused without opening it (opening would block)
  REQUIRE(::mkfifo((tmp / "pipe.csv").c_str(), 0600) == 0);
  r = run_lift(tmp / "pipe.csv");
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("pipe.csv': it is a named pipe (fifo)") != std::string::npos);
  CHECK(fs::is_fifo(tmp / "pipe.csv"));

  // a symbolic link as the output folder, and as one file in it
  fs::create_directories(tmp / "real_dir");
  fs::create_directory_symlink(tmp / "real_dir", tmp / "link_dir");
  r = run_camopt({"kinematics", kRff, "--out", (tmp / "link_dir").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("output directory '" + (tmp / "link_dir").string() + "' is a symbolic link") != std::string::npos);
  CHECK(fs::is_empty(tmp / "real_dir"));
  fs::create_directories(tmp / "o");
  fs::create_symlink(tmp / "real.csv", tmp / "o/kinematics.csv");
  REQUIRE(::mkfifo((tmp / "o/summary.json").c_str(), 0600) == 0);
  r = run_camopt({"kinematics", kRff, "--out", (tmp / "o").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("kinematics.csv': it is a symbolic link") != std::string::npos);
  CHECK(fs::is_symlink(tmp / "o/kinematics.csv"));
  CHECK(fs::is_fifo(tmp / "o/summary.json"));
  CHECK(read_file(tmp / "real.csv") == "keep\n");
  CHECK(temp_files_in(tmp / "o").empty());

  // a character device: first a copy of /dev/null made in the temp folder, so that a
  // wrong program destroys only the copy; the real /dev/null only once the copy survives
  if (::mknod((tmp / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    WARN("mknod is not permitted here: the device cases are skipped");
    return;
  }
  const Identity copy = identity_of(tmp / "null");
  r = run_lift(tmp / "null");
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("null': it is a character device") != std::string::npos);
  REQUIRE(identity_of(tmp / "null") == copy);
  CHECK(entries_of(tmp.path()) == std::vector<std::string>{"link.csv", "link_dir", "null", "o", "pipe.csv",
                                                            "real.csv", "real_dir"});

  const Identity dev_null = identity_of("/dev/null");
  REQUIRE(S_ISCHR(dev_null.mode));
  r = run_lift("/dev/null");
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("cannot write '/dev/null': it is a character device") != std::string::npos);
  REQUIRE(identity_of("/dev/null") == dev_null);
  r = run_camopt({"kinematics", kRff, "--out", "/dev/null"});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("output directory '/dev/null' is a character device") != std::string::npos);
  CHECK(identity_of("/dev/null") == dev_null);
}

// ---- design.toml ---------------------------------------------------------------------------

TEST_CASE("synthesize's design.toml keeps the input's comments and numbers and moves with its folder",
          "[cli][outputs][synthesize]") {
  TempDir tmp;
  fs::create_directories(tmp / "a");
  const fs::path out = tmp / "a/out", moved = tmp / "b/moved";
  auto r = run_camopt({"synthesize", kTarget, "--design", kRff, "--out", out.string()});
  REQUIRE(r.exit_code == cli_ok);
  const std::string text = read_file(out / "design.toml");
  INFO(text);
  // the profile reads profile.csv beside the file; no absolute path in any key
  CHECK(text.find("file = \"profile.csv\"") != std::string::npos);
  CHECK(text.find("= \"/") == std::string::npos);
  // comments and numbers of the input, as written
  CHECK(text.find("# beam estimate: pad 17.6 mm beyond the roller") != std::string::npos);
  CHECK(text.find("inertia_kg_mm2 = 9        # about the cg") != std::string::npos);
  CHECK(text.find("origin_mm = [17.6, -30.5]") != std::string::npos);
  // no number longer than its shortest round-trip form
  const std::regex number(R"((^|[=\[, ])(-?[0-9]+\.[0-9]+([eE][-+]?[0-9]+)?)(?=[,\] \n]|$))");
  for (const std::string& line : split_lines(text)) {
    const std::string code = line.substr(0, line.find('#'));
    for (std::sregex_iterator it(code.begin(), code.end(), number), end; it != end; ++it) {
      const std::string token = (*it)[2];
      double value = 0;
      std::from_chars(token.data(), token.data() + token.size(), value);
      char shortest[32];
      const auto done = std::to_chars(shortest, shortest + sizeof shortest, value);
      INFO(line << ": " << token);
      CHECK(significant_digits(token) <= significant_digits(std::string_view(shortest, done.ptr - shortest)));
    }
  }

  // the folder moved elsewhere still runs
  fs::create_directories(moved.parent_path());
  fs::rename(out, moved);
  r = run_camopt({"kinematics", (moved / "design.toml").string(), "--out", (tmp / "k").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_ok);
}

TEST_CASE("synthesize --cam swing: design.toml names the other profiles relative to its folder",
          "[cli][outputs][synthesize]") {
  // the CVVL design (no lash) and its profiles copied to d/; the swing cam synthesized for its
  // own lift into a/out: the input lobe stays in d/profiles and is named relative to a/out,
  // so the folder moved to the same depth still runs
  TempDir tmp;
  fs::create_directories(tmp / "d/profiles");
  fs::create_directories(tmp / "a");
  for (const char* profile : {"cvvl_input_lobe.csv", "cvvl_swing_cam.csv"})
    fs::copy_file(source_dir() / "designs/profiles" / profile, tmp / "d/profiles" / profile);
  const std::string design_text = std::regex_replace(read_file(source_dir() / "designs/cvvl_swing_cam.toml"),
                                                     std::regex("lash_mm = 0\\.1"), "lash_mm = 0.0");
  const fs::path design = tmp / "d/cvvl.toml", out = tmp / "a/out", moved = tmp / "b/out";
  write_text(design, design_text);
  auto r = run_camopt({"kinematics", design.string(), "--control", "0", "--step", "0.5", "--outputs", "lift",
                       "--out", (tmp / "lift").string()});
  REQUIRE(r.exit_code == cli_ok);
  const auto lines = split_lines(read_file(tmp / "lift/kinematics.csv"));
  std::string target = "cam_deg,lift_mm\n";
  for (std::size_t i = 1; i + 1 < lines.size(); ++i) target += lines[i].substr(lines[i].find(',') + 1) + "\n";
  write_text(tmp / "target.csv", target);

  r = run_camopt({"synthesize", (tmp / "target.csv").string(), "--design", design.string(), "--cam", "swing",
                  "--control", "0", "--out", out.string()});
  INFO(r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string text = read_file(out / "design.toml");
  INFO(text);
  CHECK(text.find("file = \"../../d/profiles/cvvl_input_lobe.csv\"") != std::string::npos);
  CHECK(text.find("file = \"profile.csv\"") != std::string::npos);
  CHECK(text.find("file = \"profiles/cvvl_swing_cam.csv\"") == std::string::npos);
  fs::create_directories(moved.parent_path());
  fs::rename(out, moved);
  r = run_camopt({"kinematics", (moved / "design.toml").string(), "--control", "0", "--out", (tmp / "k").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_ok);
}
