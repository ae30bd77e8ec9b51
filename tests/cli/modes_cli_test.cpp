// camopt dynamics --model modes: bad input exits 3 naming the option and the value and
// writes nothing; --rpm stays required by the time-domain models only.
#include <catch2/catch.hpp>
#include <algorithm>
#include <string>

#include "cli/cli_support.hpp"

using namespace camopt::test;

namespace {
bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
const std::string kDesign = (source_dir() / "designs/cvvl_swing_cam.toml").string();
}  // namespace

TEST_CASE("dynamics --model modes: a cam angle that is not a number is an input error naming --cam-deg",
          "[cli][dynamics][modes]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  for (const std::string& angles : {std::string("abc"), std::string("30,abc")}) {
    const auto r = run_camopt({"dynamics", kDesign, "--model", "modes", "--cam-deg", angles, "--out", out.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(has(r.err, "--cam-deg"));
    CHECK(has(r.err, "'abc'"));
    CHECK(files_under(out).empty());
  }
}

TEST_CASE("dynamics --model modes: a control position out of range is an input error naming --control",
          "[cli][dynamics][modes]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  // the CVVL's control shaft runs from 0 to 16 deg
  const auto r = run_camopt({"dynamics", kDesign, "--model", "modes", "--control", "99", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(has(r.err, "--control: value 99 is outside control 'shaft' range [0, 16]"));
  CHECK(files_under(out).empty());
}

TEST_CASE("dynamics: --rpm is required by the rigid and flexible models, not by modes", "[cli][dynamics][modes]") {
  TempDir tmp;
  for (const char* model : {"rigid", "flexible"}) {
    const fs::path out = tmp / model;
    const auto r = run_camopt({"dynamics", kDesign, "--model", model, "--out", out.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_usage_error);
    CHECK(has(r.err, "--rpm is required"));
    CHECK(files_under(out).empty());
  }
  const fs::path out = tmp / "modes";
  const auto r = run_camopt({"dynamics", kDesign, "--model", "modes", "--control", "0,16", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  // two control positions x (driver start, peak lift), a row per mode, as many modes as
  // coordinates (the shape columns after the first four)
  const auto lines = split_lines(read_file(out / "modes.csv"));
  REQUIRE(lines.size() > 1);
  CHECK(lines[0].rfind("control_deg,cam_deg,mode,frequency_Hz,", 0) == 0);
  const auto columns = static_cast<std::size_t>(std::count(lines[0].begin(), lines[0].end(), ',') + 1);
  CHECK(lines.size() - 1 == 2 * 2 * (columns - 4));
}
