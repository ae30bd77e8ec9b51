// the camopt executable (main.cpp): --version, --help of every subcommand with the units of
// its numeric options, and usage errors (exit 2)
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

// ---- version and help ---------------------------------------------------------------------

TEST_CASE("camopt --version prints the version", "[cli]") {
  const auto r = run_camopt({"--version"});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_ok);
  CHECK(contains(r.out, CAMOPT_VERSION));
}

TEST_CASE("camopt --help lists every subcommand", "[cli]") {
  const auto r = run_camopt({"--help"});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_ok);
  const auto entries = help_entries(r.out);
  for (const auto& sub : kSubcommands) {
    INFO("subcommand " << sub);
    CHECK(find_option(entries, sub) != nullptr);
  }
  // global numeric options carry units too
  const HelpEntry* threads = find_option(entries, "--threads");
  REQUIRE(threads != nullptr);
  CHECK(has_bracketed_unit(threads->text, "count"));
}

TEST_CASE("every subcommand's --help gives the units of its numeric options", "[cli]") {
  // options whose unit we know; checked when the subcommand has the option
  struct Expected {
    const char* subcommand;
    const char* option;
    const char* unit;
  };
  const std::vector<Expected> expected = {
      {"kinematics", "--step", "deg"},  {"kinematics", "--rpm", "rpm"}, {"kinematics", "--control", ""},
      {"kinematics", "--duration-at", "mm"},
      {"synthesize", "--control", "deg"}, {"synthesize", "--points", "count"},
      {"lift", "--lift", "mm"},           {"lift", "--duration", "deg"},
      {"dynamics", "--rpm", "rpm"},
  };
  for (const auto& sub : kSubcommands) {
    const auto r = run_camopt({sub, "--help"});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_ok);
    const auto entries = help_entries(r.out);
    // any option typed as a number names its unit in brackets
    for (const auto& e : entries) {
      if (!is_numeric_type(e.type)) continue;
      INFO("numeric option: " << e.text);
      CHECK(has_bracketed_unit(e.text));
    }
    for (const auto& x : expected) {
      if (sub != x.subcommand) continue;
      const HelpEntry* e = find_option(entries, x.option);
      if (!e) {
        WARN(sub << " has no option " << x.option << " (yet); not checked");
        continue;
      }
      INFO("option entry: " << e->text << "\nexpected unit: [" << x.unit << "...]");
      CHECK(has_bracketed_unit(e->text, x.unit));
    }
  }
}

// ---- usage errors (exit 2) -----------------------------------------------------------------

TEST_CASE("usage errors exit 2", "[cli]") {
  TempDir tmp;
  const std::string design = cli_data("eccentric_flat.toml").string();
  const std::string out = (tmp / "out").string();
  const std::vector<std::vector<std::string>> cases = {
      {},                                            // no subcommand
      {"--no-such-option"},                          // unknown global option
      {"validate", design, "--no-such-option"},      // unknown subcommand option
      {"frobnicate"},                                // unknown subcommand
      {"validate"},                                  // missing required positional
      {"lift", "--out", out + "/lift.csv"},          // missing required --law
      {"dynamics", design, "--out", out},            // missing required --rpm
      {"optimize", design, "--out", out},            // missing required --constraints
  };
  for (const auto& args : cases) {
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_usage_error);
    CHECK_FALSE(r.err.empty());
  }
  // a bad option value is an input error (README "Exit codes"), naming the option
  const std::vector<std::vector<std::string>> values = {
      {"--threads", "-1", "validate", design},                                  // value out of range
      {"dynamics", design, "--rpm", "3000", "--out", out, "--model", "stiff"},  // not one of the choices
  };
  for (const auto& args : values) {
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK((r.err.find("--threads") != std::string::npos || r.err.find("--model") != std::string::npos));
  }
  CHECK(no_output(tmp / "out"));
}
