// what camopt prints: constraint-set errors located at their file:line:column (or named as a
// default the file does not state), user bytes escaped on the terminal, and progress lines
// that never run into the messages printed after them.
#include <catch2/catch.hpp>

#include <cctype>

#include "cli_support.hpp"

using namespace camopt::test;

namespace {

// `text` with the first line that starts with `key` replaced by `replacement` (the key must be there)
std::string replace_line(const std::string& text, const std::string& key, const std::string& replacement) {
  std::vector<std::string> lines = split_lines(text);
  std::string out;
  bool done = false;
  for (const auto& line : lines) {
    const bool hit = !done && line.rfind(key, 0) == 0;
    done = done || hit;
    out += (hit ? replacement : line) + "\n";
  }
  REQUIRE(done);
  return out;
}

// 1-based number of the first line of `text` that starts with `prefix`
int line_of(const std::string& text, const std::string& prefix) {
  const std::vector<std::string> lines = split_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind(prefix, 0) == 0) return static_cast<int>(i) + 1;
  FAIL("no line starts with " << prefix);
  return 0;
}

// every byte of `text` is printable ASCII, a newline, or part of well-formed UTF-8 text
bool terminal_safe(const std::string& text) {
  for (unsigned char c : text)
    if ((c < 0x20 && c != '\n') || c == 0x7f || c == 0xff || c == 0xfe) return false;
  return true;
}

}  // namespace

TEST_CASE("constraint-set errors found after parsing name the file, line and column of the key", "[cli][messages]") {
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  const std::string base = read_file(source_dir() / "constraints/passenger_car_intake.toml");
  struct Case {
    std::string text, key_line, key, expect;  // the key's line starts with key_line; key: its text there
  };
  const std::vector<Case> cases = {
      {replace_line(base, "min_duration_deg", "min_duration_deg = 170.0"), "min_duration_deg", "min_duration_deg",
       "limits.min_duration_deg = 170 cam deg: must be below event.duration_deg = 128 cam deg"},
      {replace_line(base, "max_lift_mm", "max_lift_mm = 9.0\nmin_max_lift_mm = 9.5"), "min_max_lift_mm",
       "min_max_lift_mm", "limits.min_max_lift_mm = 9.5 mm is above limits.max_lift_mm = 9 mm"},
      {replace_line(base, "opening_ramp", "opening_ramp = { height_mm = 0.2, length_deg = 90.0 }"), "opening_ramp",
       "length_deg", "event.opening_ramp.length_deg + event.closing_ramp.length_deg = 108 cam deg"},
      {replace_line(base, "rpm = 6500", "rpm = 6500\ncontrols = [8.0]"), "controls", "controls",
       "set.controls: 1 value(s) given, but the design"},
  };
  for (const auto& c : cases) {
    TempDir tmp;
    const std::string set = tmp.write("set.toml", c.text);
    const auto r = run_camopt({"optimize", rff, "--constraints", set, "--out", (tmp / "out").string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    const int line = line_of(c.text, c.key_line);
    const std::size_t column = split_lines(c.text)[static_cast<std::size_t>(line - 1)].find(c.key) + 1;
    const std::string where = set + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
    CHECK(r.err.find(where + c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(tmp / "out"));
  }
}

TEST_CASE("a constraint-set error about a key the file does not state says that it takes its default",
          "[cli][messages]") {
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  const std::string base = read_file(source_dir() / "constraints/passenger_car_intake.toml");
  TempDir tmp;
  // no engine speed, but speed-dependent limits
  const std::string set = tmp.write("set.toml", replace_line(base, "rpm = 6500", "# no rpm"));
  const auto r = run_camopt({"optimize", rff, "--constraints", set, "--out", (tmp / "out").string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find(set + ": set.rpm = 0: the speed-dependent limits") != std::string::npos);
  CHECK(r.err.find("(set.rpm is not in the file: it takes its default)") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("NUL, control and non-UTF-8 bytes of an input are escaped in the message, not printed raw",
          "[cli][messages]") {
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  TempDir tmp;
  static const char kBytes[] = "cam_deg,lift_mm\n0,0\n1,7\0\x01\x1b[2J\xff\xfe\n";
  const std::string target = tmp.write("target.csv", std::string(kBytes, sizeof kBytes - 1));
  const auto r = run_camopt({"synthesize", target, "--design", rff, "--out", (tmp / "out").string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find(":3: column 'lift_mm' value '7\\x00\\x01\\x1b[2J\\xff\\xfe' is not a number") != std::string::npos);
  CHECK(terminal_safe(r.err));
  CHECK_FALSE(fs::exists(tmp / "out"));

  // a TOML string with escaped control characters, quoted back in a message
  const std::string design = read_file(rff);
  const std::string bad = tmp.write("bad.toml", replace_line(design, "form = \"polar\"", "form = \"polar\\u0000\\u001b[31m\""));
  const auto v = run_camopt({"validate", bad});
  INFO(v.command << "\n" << v.all());
  CHECK(v.exit_code == cli_input_error);
  CHECK(v.err.find("\\x00\\x1b[31m") != std::string::npos);
  CHECK(terminal_safe(v.err));
}

TEST_CASE("a progress line drawn in place is cleared before the next message and says when outputs are written",
          "[cli][messages]") {
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  TempDir tmp;
  // --progress always: the line a terminal would show, written to the captured stderr
  const auto r = run_camopt({"--progress", "always", "kinematics", rff, "--step", "0.25", "--out", (tmp / "out").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string& screen = r.err;
  const std::string bar_end = "100%, writing the outputs ...";
  const std::size_t bar = screen.find(bar_end);
  REQUIRE(bar != std::string::npos);
  // the next thing on the terminal clears the bar's line and then prints a message on it
  const std::string after = screen.substr(bar + bar_end.size());
  CHECK(after.rfind("\r\x1b[K", 0) == 0);
  CHECK(after.size() > 4);
  CHECK(std::isalpha(static_cast<unsigned char>(after[4])));
  CHECK(after.find("kinematics: 1 position(s)") != std::string::npos);

  // auto on a file and never: no line drawn in place
  for (const char* mode : {"auto", "never"}) {
    const auto q = run_camopt({"--progress", mode, "kinematics", rff, "--out", (tmp / mode).string()});
    INFO(q.command << "\n" << q.all());
    CHECK(q.exit_code == cli_ok);
    CHECK(q.err.find('\r') == std::string::npos);
    CHECK(q.err.find("kinematics: 1 position(s)") != std::string::npos);
  }
  const auto bad = run_camopt({"--progress", "sometimes", "kinematics", rff, "--out", (tmp / "bad").string()});
  CHECK(bad.exit_code == cli_input_error);
  CHECK(bad.err.find("--progress") != std::string::npos);
}
