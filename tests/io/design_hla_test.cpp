// the design file's [[hla]] tables (docs/hla.md, "Keys"): every key read (a full table round
// trip), the supply table from a CSV file, and every bad input as file:line:column: key: value:
// rule, including the element's rules that join keys (compile_hla, checked while reading)
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/io/design_file.hpp"
#include "io/design_file_test_support.hpp"
#include "temp_dir.hpp"

using camopt::InputError;
using Catch::Contains;
namespace io = camopt::io;

namespace {

// the smallest valid design of the design-file tests, with the node the HLA supports
const std::string kBase = camopt::design_file_test::kBase + R"([[node]]
name = "finger"
type = "rotational"
pivot_mm = [-35, 20]
)";

// every key, each with a value distinct from its default
const std::string kFull = R"([[hla]]
name = "hla_a"
node = "finger"
axis = [0.0, 2.0]
plunger_diameter_mm = 8.5
plunger_mass_kg = 0.0074
travel_min_mm = -3.9
travel_max_mm = 0.9
return_spring_rate_N_per_mm = 4.7
return_spring_preload_N = 11.5
chamber_volume_mm3 = 320.0
bulk_modulus_MPa = 1600.0
bulk_modulus_pressure_slope = 6.5
air_volume_fraction = 0.01
air_polytropic_index = 1.2
atmospheric_pressure_MPa = 0.1
cavitation_pressure_MPa = -0.09
oil_density_kg_per_m3 = 860.0
oil_viscosity_40C_mm2_per_s = 60.5
oil_viscosity_100C_mm2_per_s = 10.25
oil_temperature_C = 85.0
leak_clearance_mm = 0.0031
leak_eccentricity_ratio = 0.25
leak_length_mm = 5.4
orifice_diameter_mm = 0.05
orifice_discharge_coefficient = 0.65
orifice_transition_pressure_MPa = 0.0002
ball_diameter_mm = 3.2
ball_mass_kg = 0.00013
seat_diameter_mm = 1.9
ball_travel_mm = 0.35
cage_height_mm = 3.3
ball_spring_rate_N_per_mm = 0.03
ball_spring_preload_N = 0.04
ball_damping_N_s_per_m = 0.5
valve_discharge_coefficient = 0.62
ball_restitution = 0.3
supply_pressure_MPa = 0.25
)";

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

// kFull with the line of `key` replaced by `line` (or removed when empty)
std::string with(const std::string& key, const std::string& line) {
  std::string table = kFull;
  const std::size_t pos = table.find("\n" + key + " = ");
  REQUIRE(pos != std::string::npos);
  const std::size_t end = table.find('\n', pos + 1);
  table.replace(pos + 1, end - pos, line.empty() ? "" : line + "\n");
  return kBase + table;
}

}  // namespace

TEST_CASE("design [[hla]]: every key is read", "[io][design][hla]") {
  const std::string text = kBase + kFull;
  const camopt::DesignSpec d = io::parse_design(text, "case.toml", ".");
  REQUIRE(d.hlas.size() == 1);
  const camopt::HlaSpec& h = d.hlas[0];
  CHECK(h.name == "hla_a");
  CHECK(h.node == "finger");
  CHECK(h.axis[0] == 0.0);
  CHECK(h.axis[1] == 2.0);
  CHECK(h.plunger_diameter_mm == 8.5);
  CHECK(h.plunger_mass_kg == 0.0074);
  CHECK(h.travel_min_mm == -3.9);
  CHECK(h.travel_max_mm == 0.9);
  CHECK(h.return_spring_rate_N_per_mm == 4.7);
  CHECK(h.return_spring_preload_N == 11.5);
  CHECK(h.chamber_volume_mm3 == 320.0);
  CHECK(h.bulk_modulus_MPa == 1600.0);
  CHECK(h.bulk_modulus_pressure_slope == 6.5);
  CHECK(h.air_volume_fraction == 0.01);
  CHECK(h.air_polytropic_index == 1.2);
  CHECK(h.atmospheric_pressure_MPa == 0.1);
  CHECK(h.cavitation_pressure_MPa == -0.09);
  CHECK(h.oil_density_kg_per_m3 == 860.0);
  CHECK(h.oil_viscosity_40C_mm2_per_s == 60.5);
  CHECK(h.oil_viscosity_100C_mm2_per_s == 10.25);
  CHECK(h.oil_temperature_C == 85.0);
  CHECK(h.leak_clearance_mm == 0.0031);
  CHECK(h.leak_eccentricity_ratio == 0.25);
  CHECK(h.leak_length_mm == 5.4);
  REQUIRE(h.orifice_diameter_mm);
  CHECK(*h.orifice_diameter_mm == 0.05);
  CHECK(h.orifice_discharge_coefficient == 0.65);
  CHECK(h.orifice_transition_pressure_MPa == 0.0002);
  CHECK(h.ball_diameter_mm == 3.2);
  REQUIRE(h.ball_mass_kg);
  CHECK(*h.ball_mass_kg == 0.00013);
  CHECK(h.seat_diameter_mm == 1.9);
  CHECK(h.ball_travel_mm == 0.35);
  REQUIRE(h.cage_height_mm);
  CHECK(*h.cage_height_mm == 3.3);
  CHECK(h.ball_spring_rate_N_per_mm == 0.03);
  CHECK(h.ball_spring_preload_N == 0.04);
  CHECK(h.ball_damping_N_s_per_m == 0.5);
  CHECK(h.valve_discharge_coefficient == 0.62);
  CHECK(h.ball_restitution == 0.3);
  REQUIRE(h.supply_pressure_MPa);
  CHECK(*h.supply_pressure_MPa == 0.25);
  CHECK(h.supply_crank_deg.empty());
  // the table and each key know where they were written
  CHECK(h.where.str() == at(text, "[[hla]]") + ": hla[0]");
  CHECK(h.at("leak_clearance_mm").str() == at(text, "0.0031") + ": hla[0].leak_clearance_mm");
  CHECK(h.at("supply_table").str() == at(text, "[[hla]]") + ": hla[0].supply_table");  // not written
  CHECK(h.key_where.size() == 37);  // every key written: all but supply_table
}

TEST_CASE("design [[hla]]: defaults of the optional keys", "[io][design][hla]") {
  std::string table = "[[hla]]\n";
  for (const char* line : {"name = \"h\"", "node = \"finger\"", "plunger_diameter_mm = 8.6", "plunger_mass_kg = 0.0075",
                           "travel_min_mm = -4", "travel_max_mm = 1", "return_spring_rate_N_per_mm = 4.8",
                           "return_spring_preload_N = 12", "chamber_volume_mm3 = 330",
                           "oil_viscosity_40C_mm2_per_s = 61", "oil_viscosity_100C_mm2_per_s = 10.5",
                           "oil_temperature_C = 90", "leak_clearance_mm = 0.003", "leak_length_mm = 5.5",
                           "ball_diameter_mm = 3", "seat_diameter_mm = 1.925", "ball_travel_mm = 0.4",
                           "ball_spring_rate_N_per_mm = 0.025", "ball_spring_preload_N = 0.0375",
                           "supply_pressure_MPa = 0.3"})
    table += std::string(line) + "\n";
  const camopt::HlaSpec h = io::parse_design(kBase + table, "case.toml", ".").hlas.at(0);
  const camopt::HlaSpec defaults;
  CHECK(h.axis == defaults.axis);
  CHECK(h.bulk_modulus_MPa == 1500.0);
  CHECK(h.air_volume_fraction == 0.0);
  CHECK(h.air_polytropic_index == 1.0);
  CHECK(h.atmospheric_pressure_MPa == 0.101325);
  CHECK(h.cavitation_pressure_MPa == -0.095);
  CHECK(h.oil_density_kg_per_m3 == 850.0);
  CHECK(h.leak_eccentricity_ratio == 0.0);
  CHECK_FALSE(h.orifice_diameter_mm);
  CHECK_FALSE(h.ball_mass_kg);
  CHECK_FALSE(h.cage_height_mm);
  CHECK(h.valve_discharge_coefficient == 0.6);
  CHECK(h.ball_restitution == 0.0);
}

TEST_CASE("design [[hla]]: the supply pressure from a crank-angle table", "[io][design][hla]") {
  camopt::test::TempDir tmp;
  tmp.write("supply.csv", "crank_deg,pressure_MPa\n0,0.3\n360,0.25\n540,0.35\n");
  std::string table = kFull;
  table.replace(table.find("supply_pressure_MPa = 0.25"), 26, "supply_table = \"supply.csv\"");
  tmp.write("design.toml", kBase + table);
  const camopt::DesignSpec d = io::load_design(tmp.file("design.toml"));
  const camopt::HlaSpec& h = d.hlas.at(0);
  CHECK_FALSE(h.supply_pressure_MPa);
  CHECK(h.supply_crank_deg == std::vector<double>{0.0, 360.0, 540.0});
  CHECK(h.supply_table_MPa == std::vector<double>{0.3, 0.25, 0.35});
  CHECK(h.supply_source_file == tmp.file("supply.csv"));
  // a cam-angle table is refused: the gallery follows the crank
  tmp.write("cam.csv", "cam_deg,pressure_MPa\n0,0.3\n180,0.25\n");
  table.replace(table.find("supply.csv"), 10, "cam.csv");
  tmp.write("design.toml", kBase + table);
  try {
    (void)io::load_design(tmp.file("design.toml"));
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), Contains("hla[0].supply_table") && Contains("is a cam angle"));
  }
}

TEST_CASE("design [[hla]]: bad input names the file, line, column, key, value and rule", "[io][design][hla]") {
  // each case replaces the line of `key` by `line`; the error is at the value of the line's first
  // key (at the key itself for an unknown key)
  struct Case {
    std::string key, line, expect;
    bool at_key = false;
  };
  const std::vector<Case> cases = {
      // the rules named by the element: negative clearance, a ball travel larger than its cage, a
      // chamber that cannot hold the preload
      {"leak_clearance_mm", "leak_clearance_mm = -0.003", "hla[0].leak_clearance_mm: value -0.003 must be > 0"},
      {"ball_travel_mm", "ball_travel_mm = 0.8",
       "hla[0].ball_travel_mm: value 0.8 must be <= cage_height_mm - seated ball top (3.3 - 2.887439319 = "
       "0.412560681 mm): the ball's travel is larger than its cage"},
      {"return_spring_preload_N", "return_spring_preload_N = 22",
       "hla[0].return_spring_preload_N: value 22: the chamber cannot hold the preload at the supply pressure"},
      {"leak_eccentricity_ratio", "leak_eccentricity_ratio = 1", "hla[0].leak_eccentricity_ratio: value 1 must be in [0, 1)"},
      {"plunger_mass_kg", "plunger_mass_kg = 0", "hla[0].plunger_mass_kg: value 0 must be > 0"},
      {"leak_length_mm", "leak_length_mm = -5", "hla[0].leak_length_mm: value -5 must be > 0"},
      {"travel_min_mm", "travel_min_mm = 0.5", "hla[0].travel_min_mm: value 0.5 must be <= 0 (the travel limits must contain"},
      {"seat_diameter_mm", "seat_diameter_mm = 3.5", "hla[0].seat_diameter_mm: value 3.5 must be < ball_diameter_mm (3.2)"},
      {"oil_viscosity_40C_mm2_per_s", "oil_viscosity_40C_mm2_per_s = 9",
       "hla[0].oil_viscosity_40C_mm2_per_s: value 9 must be > oil_viscosity_100C_mm2_per_s (10.25)"},
      {"cavitation_pressure_MPa", "cavitation_pressure_MPa = -0.2",
       "hla[0].cavitation_pressure_MPa: value -0.2 must be > -atmospheric_pressure_MPa (-0.1)"},
      // types, unknown keys and nodes, and the supply given twice
      {"plunger_diameter_mm", "plunger_diameter_mm = \"big\"",
       "hla[0].plunger_diameter_mm: expected a number, got string \"big\""},
      {"node", "node = \"rocker\"", "hla[0].node: unknown node \"rocker\""},
      {"ball_restitution", "ball_restitutio = 0.3", "hla[0]: unknown key 'ball_restitutio'", true},
      {"supply_pressure_MPa", "supply_table = \"s.csv\"\nsupply_pressure_MPa = 0.3",
       "hla[0].supply_table: give either supply_pressure_MPa or supply_table, not both"},
  };
  for (const Case& c : cases) {
    const std::string text = with(c.key, c.line);
    const std::size_t line_at = text.find(c.line);
    REQUIRE(line_at != std::string::npos);
    const std::size_t value_at = line_at + (c.at_key ? 0 : c.line.find(" = ") + 3);
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(value_at), '\n');
    const std::string where =
        "case.toml:" + std::to_string(line) + ":" + std::to_string(value_at - text.rfind('\n', value_at - 1));
    INFO(c.line);
    CHECK_THAT(error_of(text), Contains(where + ": " + c.expect));
  }
  // a missing required key is reported at the table
  const std::string text = with("leak_length_mm", "");
  CHECK_THAT(error_of(text), Contains(at(text, "[[hla]]") + ": hla[0]: missing required key 'leak_length_mm'"));
}
