// the design file's optional [oil] table (docs/design-format.md, "[oil]"): values, the
// optional composite roughness, and every bad input as file:line:column: key: value: rule.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/io/design_file.hpp"

using camopt::InputError;
using Catch::Contains;
namespace io = camopt::io;

namespace {

// the smallest valid design; each case appends an [oil] table
const std::string kBase = R"(schema = 1
[design]
name = "base"
output_node = "valve"
[driver]
node = "cam"
[[node]]
name = "cam"
type = "rotational"
pivot_mm = [0, 0]
[[node]]
name = "valve"
type = "translational"
origin_mm = [0, 40]
)";

// "case.toml:LINE:COL" of the first occurrence of `snippet` in `text`
std::string at(const std::string& text, const std::string& snippet) {
  const std::size_t pos = text.find(snippet);
  REQUIRE(pos != std::string::npos);
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n');
  const std::size_t line_start = text.rfind('\n', pos - 1);
  return "case.toml:" + std::to_string(line) + ":" + std::to_string(pos - line_start);
}

std::string error_of(const std::string& text) {
  try {
    (void)io::parse_design(text, "case.toml", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("expected an InputError for:\n" << text);
  return {};
}

}  // namespace

TEST_CASE("design [oil]: viscosity, pressure-viscosity and composite roughness", "[io][design][oil]") {
  const std::string text = kBase + "[oil]\nviscosity_mPa_s = 9.1\npressure_viscosity_per_GPa = 16\n"
                                   "composite_roughness_um = 0.25\n";
  const camopt::DesignSpec d = io::parse_design(text, "case.toml", ".");
  REQUIRE(d.oil);
  CHECK(d.oil->viscosity_mPa_s == 9.1);
  CHECK(d.oil->pressure_viscosity_per_GPa == 16.0);  // an integer is a number
  REQUIRE(d.oil->composite_roughness_um);
  CHECK(*d.oil->composite_roughness_um == 0.25);
  CHECK(d.oil->where == at(text, "[oil]") + ": oil");
}

TEST_CASE("design [oil]: optional, and lambda's roughness optional within it", "[io][design][oil]") {
  CHECK_FALSE(io::parse_design(kBase, "case.toml", ".").oil);
  const camopt::DesignSpec d =
      io::parse_design(kBase + "[oil]\nviscosity_mPa_s = 10\npressure_viscosity_per_GPa = 18\n", "case.toml", ".");
  REQUIRE(d.oil);
  CHECK_FALSE(d.oil->composite_roughness_um);
  // an inline table at the top level is the same table
  const std::string inline_oil = "schema = 1\noil = { viscosity_mPa_s = 10, pressure_viscosity_per_GPa = 18 }\n" +
                                 kBase.substr(kBase.find('\n') + 1);
  const camopt::DesignSpec e = io::parse_design(inline_oil, "case.toml", ".");
  REQUIRE(e.oil);
  CHECK(e.oil->viscosity_mPa_s == 10.0);
}

TEST_CASE("design [oil]: bad input names the file, line, column, key, value and rule", "[io][design][oil]") {
  const std::string good = "viscosity_mPa_s = 9.1\npressure_viscosity_per_GPa = 16\n";
  auto oil = [&](const std::string& body) { return kBase + "[oil]\n" + body; };
  // an unknown key (a typo), with the allowed ones
  std::string text = oil(good + "composite_roughnes_um = 0.2\n");
  CHECK_THAT(error_of(text), Contains(at(text, "composite_roughnes_um") +
                                      ": oil: unknown key 'composite_roughnes_um' (allowed: viscosity_mPa_s, "
                                      "pressure_viscosity_per_GPa, composite_roughness_um)"));
  // a missing required key, reported at the table
  text = oil("viscosity_mPa_s = 9.1\n");
  CHECK_THAT(error_of(text), Contains(at(text, "[oil]") + ": oil: missing required key 'pressure_viscosity_per_GPa'"));
  text = oil("pressure_viscosity_per_GPa = 16\n");
  CHECK_THAT(error_of(text), Contains(at(text, "[oil]") + ": oil: missing required key 'viscosity_mPa_s'"));
  // ranges: every value > 0
  text = oil("viscosity_mPa_s = -9.1\npressure_viscosity_per_GPa = 16\n");
  CHECK_THAT(error_of(text), Contains(at(text, "-9.1") + ": oil.viscosity_mPa_s: value -9.1 must be > 0"));
  text = oil("viscosity_mPa_s = 9.1\npressure_viscosity_per_GPa = 0\n");
  CHECK_THAT(error_of(text), Contains(at(text, "0\n") + ": oil.pressure_viscosity_per_GPa: value 0 must be > 0"));
  text = oil(good + "composite_roughness_um = 0.0\n");
  CHECK_THAT(error_of(text), Contains(at(text, "0.0") + ": oil.composite_roughness_um: value 0 must be > 0"));
  // types
  text = oil("viscosity_mPa_s = \"thin\"\npressure_viscosity_per_GPa = 16\n");
  CHECK_THAT(error_of(text),
             Contains(at(text, "\"thin\"") + ": oil.viscosity_mPa_s: expected a number, got string \"thin\""));
  text = oil("viscosity_mPa_s = nan\npressure_viscosity_per_GPa = 16\n");
  CHECK_THAT(error_of(text), Contains(": oil.viscosity_mPa_s: value nan must be finite"));
  text = kBase + "[[oil]]\n" + good;
  CHECK_THAT(error_of(text), Contains(": oil: expected a table, got array of 1 elements"));
}
