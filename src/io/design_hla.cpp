// [[hla]] tables -> HlaSpec (docs/hla.md, "Keys"). The parser reads types and the file's
// references; the element's rules (ranges and the rules that join keys) are compile_hla's,
// checked here once so that `camopt validate` reports them with the key's file:line:column.
#include "design_hla.hpp"

#include <filesystem>
#include <system_error>

#include "camopt/dynamics/hla.hpp"
#include "camopt/io/csv.hpp"

namespace camopt::io {

namespace {

using namespace toml_detail;

const Keys kHlaKeys = {
    "name", "node", "axis",
    // plunger and body
    "plunger_diameter_mm", "plunger_mass_kg", "travel_min_mm", "travel_max_mm", "return_spring_rate_N_per_mm",
    "return_spring_preload_N", "series_body_mass_kg",
    // chamber and oil
    "chamber_volume_mm3", "bulk_modulus_MPa", "bulk_modulus_pressure_slope", "air_volume_fraction",
    "air_polytropic_index", "atmospheric_pressure_MPa", "cavitation_pressure_MPa", "oil_density_kg_per_m3",
    "oil_viscosity_40C_mm2_per_s", "oil_viscosity_100C_mm2_per_s", "oil_temperature_C",
    // leak-down
    "leak_clearance_mm", "leak_eccentricity_ratio", "leak_length_mm", "orifice_diameter_mm",
    "orifice_discharge_coefficient", "orifice_transition_pressure_MPa",
    // check valve
    "ball_diameter_mm", "ball_mass_kg", "seat_diameter_mm", "ball_travel_mm", "cage_height_mm",
    "ball_spring_rate_N_per_mm", "ball_spring_preload_N", "ball_damping_N_s_per_m", "valve_discharge_coefficient",
    "ball_restitution",
    // supply
    "supply_pressure_MPa", "supply_table"};

// supply_table = "file.csv": crank_deg (or crank_angle_deg), pressure_MPa; resolved like the
// gas-force table, relative to the design file
void read_supply_table(const Table& t, HlaSpec& h) {
  const std::string name = t.string("supply_table");
  const fs::path path = t.context().resolve(name);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    t.fail("supply_table", "file " + quote(name) + " not found (resolved to " + quote(path.string()) + ")");
  try {
    const AngleTable table = read_angle_table(read_csv(path.string()), {"pressure_MPa"});
    if (table.basis != AngleBasis::crank)
      throw InputError(table.file + ": column '" + table.angle_column +
                       "' is a cam angle; the supply pressure is tabulated against crank angle (crank_deg)");
    h.supply_crank_deg = table.angle_deg;
    h.supply_table_MPa = table.value;
    h.supply_source_file = path.string();
  } catch (const InputError& e) {
    throw InputError(t.where("supply_table"), e.what());
  }
}

// the placement: in series on a translational node (series_body_mass_kg, a part of the node's
// mass), or under the pivot of any other node (no series_body_mass_kg)
void check_placement(const Table& t, const HlaSpec& h, const NodeSpec& node) {
  const bool translational = node.kind == NodeKind::translational;
  if (!translational && h.series_body_mass_kg)
    t.fail("series_body_mass_kg", "value " + format_value(*h.series_body_mass_kg) + ": node " + quote(node.name) +
                                      " is " + to_string(node.kind) +
                                      "; an HLA is in series only on a translational node (under a pivot it carries "
                                      "the whole node: remove the key)");
  if (!translational) return;
  if (!h.series_body_mass_kg)
    t.fail("missing required key 'series_body_mass_kg': an HLA on translational node " + quote(node.name) +
           " is in series, and the key gives the mass of the part on the contacts' side [kg]");
  const double whole = node.mass_kg.value_or(0.0);
  if (!(*h.series_body_mass_kg < whole))
    t.fail("series_body_mass_kg", "value " + format_value(*h.series_body_mass_kg) + " must be < node " +
                                      quote(node.name) + "'s mass_kg (" + format_value(whole) +
                                      "): the contact side is a part of the node, the valve side keeps the rest");
}

HlaSpec parse_hla(const Table& t) {
  t.allow(kHlaKeys);
  HlaSpec h;
  h.name = t.identifier("name");
  h.node = t.string("node");
  if (t.has("axis")) h.axis = t.direction("axis");
  // required numbers, then the optional ones with their defaults (the rules are compile_hla's)
  const auto required = [&](std::string_view key, double& value) { value = t.number(key); };
  const auto optional = [&](std::string_view key, double& value) { value = t.number_or(key, value); };
  required("plunger_diameter_mm", h.plunger_diameter_mm);
  required("plunger_mass_kg", h.plunger_mass_kg);
  required("travel_min_mm", h.travel_min_mm);
  required("travel_max_mm", h.travel_max_mm);
  required("return_spring_rate_N_per_mm", h.return_spring_rate_N_per_mm);
  required("return_spring_preload_N", h.return_spring_preload_N);
  h.series_body_mass_kg = t.optional_number("series_body_mass_kg");
  required("chamber_volume_mm3", h.chamber_volume_mm3);
  optional("bulk_modulus_MPa", h.bulk_modulus_MPa);
  optional("bulk_modulus_pressure_slope", h.bulk_modulus_pressure_slope);
  optional("air_volume_fraction", h.air_volume_fraction);
  optional("air_polytropic_index", h.air_polytropic_index);
  optional("atmospheric_pressure_MPa", h.atmospheric_pressure_MPa);
  optional("cavitation_pressure_MPa", h.cavitation_pressure_MPa);
  optional("oil_density_kg_per_m3", h.oil_density_kg_per_m3);
  required("oil_viscosity_40C_mm2_per_s", h.oil_viscosity_40C_mm2_per_s);
  required("oil_viscosity_100C_mm2_per_s", h.oil_viscosity_100C_mm2_per_s);
  required("oil_temperature_C", h.oil_temperature_C);
  required("leak_clearance_mm", h.leak_clearance_mm);
  optional("leak_eccentricity_ratio", h.leak_eccentricity_ratio);
  required("leak_length_mm", h.leak_length_mm);
  h.orifice_diameter_mm = t.optional_number("orifice_diameter_mm");
  optional("orifice_discharge_coefficient", h.orifice_discharge_coefficient);
  optional("orifice_transition_pressure_MPa", h.orifice_transition_pressure_MPa);
  required("ball_diameter_mm", h.ball_diameter_mm);
  h.ball_mass_kg = t.optional_number("ball_mass_kg");
  required("seat_diameter_mm", h.seat_diameter_mm);
  required("ball_travel_mm", h.ball_travel_mm);
  h.cage_height_mm = t.optional_number("cage_height_mm");
  required("ball_spring_rate_N_per_mm", h.ball_spring_rate_N_per_mm);
  required("ball_spring_preload_N", h.ball_spring_preload_N);
  optional("ball_damping_N_s_per_m", h.ball_damping_N_s_per_m);
  optional("valve_discharge_coefficient", h.valve_discharge_coefficient);
  optional("ball_restitution", h.ball_restitution);
  // supply: exactly one of the constant and the table
  if (t.has("supply_pressure_MPa") && t.has("supply_table"))
    t.fail("supply_table", "give either supply_pressure_MPa or supply_table, not both");
  if (!t.has("supply_pressure_MPa") && !t.has("supply_table"))
    t.fail("missing required key 'supply_pressure_MPa' (or a 'supply_table')");
  h.supply_pressure_MPa = t.optional_number("supply_pressure_MPa");
  if (t.has("supply_table")) read_supply_table(t, h);
  h.where = t.where();
  for (const std::string_view key : kHlaKeys)
    if (t.has(key)) h.key_where.emplace_back(std::string(key), t.where(key));
  return h;
}

}  // namespace

void parse_hlas(const Table& root, DesignSpec& spec) {
  for (const Table& t : root.array_of_tables("hla")) {
    HlaSpec h = parse_hla(t);
    for (const HlaSpec& other : spec.hlas)
      if (other.name == h.name)
        t.fail("name", "duplicate name " + quote(h.name) + " (already used by " + other.where.key_path + " at line " +
                           std::to_string(other.where.line) + ")");
    // the supported node exists (the nodes are read before)
    const NodeSpec* node = nullptr;
    std::string names;
    for (const NodeSpec& n : spec.nodes) {
      if (n.name == h.node) node = &n;
      names += (names.empty() ? "" : ", ") + n.name;
    }
    if (!node)
      t.fail("node", "unknown node " + quote(h.node) + " (the node the HLA supports; defined: " +
                         (names.empty() ? "none" : names) + ")");
    check_placement(t, h, *node);
    (void)dynamics::compile_hla(h);  // the element's rules, at their keys
    spec.hlas.push_back(std::move(h));
  }
}

}  // namespace camopt::io
