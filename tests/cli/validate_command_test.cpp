// camopt validate: every bundled design accepted, every bad design rejected with its message
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

#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define CAMOPT_TEST_HAVE_JSON 1
#endif

using namespace camopt::test;
using namespace camopt::test::commands;

// ---- validate ------------------------------------------------------------------------------

TEST_CASE("validate accepts every bundled design", "[cli][validate]") {
  const auto designs = glob_files(source_dir() / "designs", ".toml");
  if (designs.empty()) {
    WARN("no designs/*.toml yet; nothing to validate");
    return;
  }
  for (const auto& d : designs) {
    const auto r = run_camopt({"validate", d.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_ok);
  }
}

TEST_CASE("validate rejects every bad design with its expected message", "[cli][validate]") {
  const auto designs = glob_files(source_dir() / "tests" / "data" / "bad_designs", ".toml");
  REQUIRE_FALSE(designs.empty());
  const std::string marker = "# expect: ";
  for (const auto& d : designs) {
    const auto lines = split_lines(read_file(d));
    INFO("bad design " << d.string());
    REQUIRE_FALSE(lines.empty());
    REQUIRE(lines[0].rfind(marker, 0) == 0);
    const std::string expected = lines[0].substr(marker.size());
    const auto r = run_camopt({"validate", d.string()});
    INFO(r.command << "\n" << r.all() << "\nexpected on stderr: " << expected);
    CHECK(r.exit_code == cli_input_error);
    CHECK(contains(r.err, expected));
  }
}

TEST_CASE("validate names a design file that does not exist", "[cli][validate]") {
  TempDir tmp;
  const std::string missing = (tmp / "no_such_design.toml").string();
  const auto r = run_camopt({"validate", missing});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(contains(r.err, missing));
}
