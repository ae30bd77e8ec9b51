#pragma once
#include "temp_dir.hpp"
// helpers for the CLI tests: run the built camopt executable, fresh temporary directories,
// file reading. Header-only; the tests compare exit codes, messages and written files.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <catch2/catch.hpp>

namespace camopt::test {

namespace fs = std::filesystem;

// exit codes of camopt (src/cli/cli_common.hpp)
enum CliExit : int {
  cli_ok = 0,
  cli_internal_error = 1,
  cli_usage_error = 2,
  cli_input_error = 3,
  cli_numerical_failure = 4,
  cli_verification_failed = 5,
};

// wall-clock limit of one camopt run [s]; a hang fails the test with exit 124
constexpr int kRunTimeoutSeconds = 600;

inline fs::path source_dir() { return fs::path(CAMOPT_SOURCE_DIR); }
inline fs::path camopt_binary() { return fs::path(CAMOPT_BINARY); }

// one argument for /bin/sh, single-quoted
inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

inline std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

using camopt::test::TempDir;

// the warnings a test expects camopt to print: while an ExpectWarnings is alive, a
// "warning:" line on camopt's stderr must contain one of its texts; any other warning fails
// the test that ran camopt (a warning nobody looked at is a defect or a missing check)
inline std::vector<std::string>& expected_warnings() {
  static std::vector<std::string> texts;
  return texts;
}
struct ExpectWarnings {
  explicit ExpectWarnings(std::initializer_list<std::string> texts) : size_(expected_warnings().size()) {
    expected_warnings().insert(expected_warnings().end(), texts.begin(), texts.end());
  }
  ~ExpectWarnings() { expected_warnings().resize(size_); }
  ExpectWarnings(const ExpectWarnings&) = delete;
  ExpectWarnings& operator=(const ExpectWarnings&) = delete;

 private:
  std::size_t size_;
};

// every "warning:" line of stderr is one the running test expects
inline void check_no_unexpected_warning(const std::string& command, const std::string& err) {
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("warning:") == std::string::npos) continue;
    const auto& ok = expected_warnings();
    const bool expected = std::any_of(ok.begin(), ok.end(), [&](const std::string& t) { return line.find(t) != std::string::npos; });
    INFO("command: " << command);
    INFO("unexpected warning: " << line);
    CHECK(expected);
  }
}

struct RunResult {
  int exit_code = -1;  // WEXITSTATUS, or 128 + signal when killed
  std::string out;     // stdout
  std::string err;     // stderr
  std::string command;

  std::string all() const { return out + err; }
};

// run camopt with `args`, capturing stdout and stderr separately; no Catch2 assertion, so it
// may run on any thread (run_camopt checks the warnings as well)
inline RunResult run_camopt_unchecked(const std::vector<std::string>& args) {
  TempDir scratch;
  const fs::path err_file = scratch / "stderr.txt";
  RunResult r;
  r.command = shell_quote(camopt_binary().string());
  for (const auto& a : args) r.command += " " + shell_quote(a);
  const std::string full = "timeout " + std::to_string(kRunTimeoutSeconds) + " " + r.command + " 2>" +
                           shell_quote(err_file.string()) + " </dev/null";
  FILE* pipe = ::popen(full.c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed for: " + full);
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = ::pclose(pipe);
  if (status == -1)
    r.exit_code = -1;
  else if (WIFEXITED(status))
    r.exit_code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status))
    r.exit_code = 128 + WTERMSIG(status);
  r.err = read_file(err_file);
  return r;
}

// run camopt with `args` on the test's thread: a warning the test does not expect fails it
inline RunResult run_camopt(const std::vector<std::string>& args) {
  RunResult r = run_camopt_unchecked(args);
  check_no_unexpected_warning(r.command, r.err);
  return r;
}

inline RunResult run_camopt(std::initializer_list<std::string> args) {
  return run_camopt(std::vector<std::string>(args));
}

// regular files anywhere under `dir` (none when it does not exist)
inline std::vector<fs::path> files_under(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return files;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  return files;
}

// files in `dir` (not recursive) whose name ends in `extension`, sorted
inline std::vector<fs::path> glob_files(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && e.path().extension() == extension) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  return lines;
}

}  // namespace camopt::test
