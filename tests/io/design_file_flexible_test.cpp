#include "camopt/io/design_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/io/design_rewrite.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using camopt::InputError;
using Catch::Contains;
namespace io = camopt::io;

using camopt::test::TempDir;

#include "design_file_test_support.hpp"

using namespace camopt::design_file_test;

// ---- flexible-model keys: contact laws, valve seats, component, link and spring damping

namespace {

// kBase plus a contact between the cam and the valve; `extra` is added to the contact
std::string with_contact(const std::string& extra) {
  return kBase + R"([[connection]]
name = "cam_valve"
type = "contact"
a = { node = "cam", shape = "circle", center_mm = [0, 5], radius_mm = 20 }
b = { node = "valve", shape = "line", point_mm = [0, 40], normal = [0, -1] }
)" + extra;
}

const std::string kFlexible = kBase + R"(seat = { diameter_mm = 33, angle_deg = 30, width_mm = 1.2, crown_radius_mm = 4, material = "insert", restitution = 0.6 }
axial_stiffness_N_per_mm = 60000
damping_N_s_per_m = 150
[[node]]
name = "rocker"
type = "rotational"
pivot_mm = [40, 30]
torsional_stiffness_Nm_per_rad = 4000
damping_Nm_s_per_rad = 0.02
[[node]]
name = "plunger"
type = "translational"
origin_mm = [60, 0]
[node.seat]
law = "linear"
stiffness_N_per_mm = 2e5
damping_N_s_per_m = 300
[[material]]
name = "steel"
youngs_modulus_GPa = 210
poisson_ratio = 0.3
[[material]]
name = "insert"
youngs_modulus_GPa = 180
poisson_ratio = 0.28
[[connection]]
name = "cam_valve"
type = "contact"
a = { node = "cam", shape = "circle", center_mm = [0, 5], radius_mm = 20 }
b = { node = "valve", shape = "line", point_mm = [0, 40], normal = [0, -1] }
materials = ["steel", "steel"]
damping_law = "hunt_crossley"
restitution = 0.7
[[connection]]
name = "pad"
type = "contact"
a = { node = "rocker", shape = "circle", center_mm = [60, 28], radius_mm = 8 }
b = { node = "plunger", shape = "line", point_mm = [60, 20], normal = [0, 1] }
law = "linear"
stiffness_N_per_mm = 50000
damping_N_s_per_m = 80
[[connection]]
name = "tip"
type = "contact"
a = { node = "rocker", shape = "circle", center_mm = [40, 50], radius_mm = 8 }
b = { node = "valve", shape = "line", point_mm = [40, 40], normal = [0, 1] }
law = "hertz"
damping_law = "linear"
damping_N_s_per_m = 40
[[connection]]
name = "push"
type = "link"
a = { node = "cam", point_mm = [0, 10] }
b = { node = "rocker", point_mm = [40, 10] }
stiffness_N_per_mm = 30000
damping_ratio = 0.03
[[connection]]
name = "gears"
type = "gear"
nodes = ["cam", "rocker"]
ratio = -1
stiffness_Nm_per_rad = 2500
damping_ratio = 0.02
[[connection]]
name = "rack"
type = "rack_pinion"
nodes = ["rocker", "plunger"]
pitch_radius_mm = 12
stiffness_N_per_mm = 8000
[[spring]]
name = "valve_spring"
type = "compression"
node = "valve"
rate_N_per_mm = 30
mass_kg = 0.03
surge_masses = 500
damping_N_s_per_m = 12
coil_damping_ratio = 0.02
[[spring]]
name = "plunger_spring"
type = "compression"
node = "plunger"
rate_N_per_mm = 10
mass_kg = 0.01
surge_masses = 3
coil_damping_N_s_per_m = 5
)";

// the message for `text` starts at the position of `snippet` and names `message` after it
void check_error(const std::string& text, const std::string& snippet, const std::string& message) {
  INFO(text);
  CHECK_THAT(error_of(text), Contains(at(text, snippet) + ": " + message));
}

}  // namespace

TEST_CASE("flexible-model keys are read with their values", "[io][design][flexible]") {
  const camopt::DesignSpec spec = io::parse_design(kFlexible, "case.toml", ".");
  REQUIRE(spec.nodes.size() == 4);

  // the output valve: seat table, axial damper
  const camopt::NodeSpec& valve = spec.nodes[1];
  CHECK(*valve.damping_N_s_per_m == 150.0);
  CHECK_FALSE(valve.damping_ratio);
  const camopt::SeatSpec& seat = valve.seat;
  CHECK(seat.enabled);
  CHECK(seat.given);
  CHECK(seat.diameter_mm == 33.0);
  CHECK(seat.angle_deg == 30.0);
  CHECK(seat.width_mm == 1.2);
  CHECK(seat.crown_radius_mm == 4.0);
  CHECK(seat.material == "insert");
  CHECK(seat.law.law == camopt::ContactLaw::hertz);
  CHECK(seat.law.damping_law == camopt::ContactDampingLaw::hunt_crossley);
  CHECK(*seat.law.restitution == 0.6);
  CHECK_FALSE(seat.law.damping_N_s_per_m);
  CHECK_FALSE(seat.law.stiffness_N_per_mm);
  CHECK(seat.where.str() == at(kFlexible, "{ diameter_mm = 33") + ": node[1].seat");

  const camopt::NodeSpec& rocker = spec.nodes[2];
  CHECK(*rocker.damping_Nm_s_per_rad == 0.02);
  CHECK_FALSE(rocker.damping_N_s_per_m);
  CHECK_FALSE(rocker.seat.given);

  // a seat written as a [node.seat] table, with the linear law
  const camopt::SeatSpec& plunger_seat = spec.nodes[3].seat;
  CHECK(plunger_seat.given);
  CHECK(plunger_seat.enabled);
  CHECK(plunger_seat.law.law == camopt::ContactLaw::linear);
  CHECK(*plunger_seat.law.stiffness_N_per_mm == 2e5);
  CHECK(*plunger_seat.law.damping_N_s_per_m == 300.0);
  CHECK(plunger_seat.diameter_mm == 29.0);  // the other values keep their defaults
  CHECK(plunger_seat.material.empty());
  CHECK(plunger_seat.where.key_path == "node[3].seat");
  CHECK(plunger_seat.where.line == line_of(kFlexible, "[node.seat]"));

  REQUIRE(spec.connections.size() == 6);
  const camopt::ContactLawSpec& hertz = spec.connections[0].contact_law;
  CHECK(hertz.law == camopt::ContactLaw::hertz);
  CHECK(hertz.damping_law == camopt::ContactDampingLaw::hunt_crossley);
  CHECK(*hertz.restitution == 0.7);
  CHECK_FALSE(hertz.damping_N_s_per_m);
  const camopt::ContactLawSpec& linear = spec.connections[1].contact_law;
  CHECK(linear.law == camopt::ContactLaw::linear);
  CHECK(*linear.stiffness_N_per_mm == 50000.0);
  CHECK(*linear.damping_N_s_per_m == 80.0);
  CHECK_FALSE(linear.restitution);
  const camopt::ContactLawSpec& hertz_linear = spec.connections[2].contact_law;
  CHECK(hertz_linear.law == camopt::ContactLaw::hertz);
  CHECK(hertz_linear.damping_law == camopt::ContactDampingLaw::linear);
  CHECK(*hertz_linear.damping_N_s_per_m == 40.0);
  // the contact's stiffness key is its law's, not a link compliance
  CHECK_FALSE(spec.connections[1].stiffness_N_per_mm);

  CHECK(*spec.connections[3].stiffness_N_per_mm == 30000.0);
  CHECK(*spec.connections[3].damping_ratio == 0.03);
  CHECK_FALSE(spec.connections[3].stiffness_Nm_per_rad);
  CHECK(*spec.connections[4].stiffness_Nm_per_rad == 2500.0);
  CHECK(*spec.connections[4].damping_ratio == 0.02);
  CHECK_FALSE(spec.connections[4].stiffness_N_per_mm);
  CHECK(*spec.connections[5].stiffness_N_per_mm == 8000.0);
  CHECK_FALSE(spec.connections[5].damping_ratio);

  REQUIRE(spec.springs.size() == 2);
  CHECK(spec.springs[0].surge_masses == camopt::kMaxSurgeMasses);
  CHECK(*spec.springs[0].damping_N_s_per_m == 12.0);
  CHECK(*spec.springs[0].coil_damping_ratio == 0.02);
  CHECK_FALSE(spec.springs[0].coil_damping_N_s_per_m);
  CHECK(*spec.springs[1].coil_damping_N_s_per_m == 5.0);
  CHECK_FALSE(spec.springs[1].coil_damping_ratio);
  CHECK_FALSE(spec.springs[1].damping_N_s_per_m);
}

TEST_CASE("flexible-model keys keep their defaults when absent", "[io][design][flexible]") {
  const std::string text = with_contact(R"([[connection]]
name = "push"
type = "link"
a = { node = "cam", point_mm = [0, 10] }
b = { node = "valve", point_mm = [0, 40] }
[[connection]]
name = "gears"
type = "variable_gear"
nodes = ["cam", "valve"]
ratio_table = { input_deg = [0, 10, 20], ratio = [1, 2, 1] }
[[spring]]
name = "valve_spring"
type = "compression"
node = "valve"
rate_N_per_mm = 30
)");
  const camopt::DesignSpec spec = io::parse_design(text, "case.toml", ".");
  for (const camopt::NodeSpec& node : spec.nodes) {
    INFO(node.name);
    CHECK_FALSE(node.damping_N_s_per_m);
    CHECK_FALSE(node.damping_Nm_s_per_rad);
    CHECK(node.seat.enabled);
    CHECK_FALSE(node.seat.given);
    CHECK(node.seat.diameter_mm == 29.0);
    CHECK(node.seat.angle_deg == 45.0);
    CHECK(node.seat.width_mm == 1.5);
    CHECK(node.seat.crown_radius_mm == 5.0);
    CHECK(node.seat.material.empty());
    CHECK(node.seat.law.law == camopt::ContactLaw::hertz);
    CHECK(node.seat.law.damping_law == camopt::ContactDampingLaw::hunt_crossley);
    CHECK_FALSE(node.seat.law.restitution);
  }
  REQUIRE(spec.connections.size() == 3);
  const camopt::ContactLawSpec& law = spec.connections[0].contact_law;
  CHECK(law.law == camopt::ContactLaw::hertz);
  CHECK(law.damping_law == camopt::ContactDampingLaw::hunt_crossley);
  CHECK_FALSE(law.stiffness_N_per_mm);
  CHECK_FALSE(law.damping_N_s_per_m);
  CHECK_FALSE(law.restitution);
  for (const camopt::ConnectionSpec& c : spec.connections) {
    INFO(c.name);
    CHECK_FALSE(c.stiffness_N_per_mm);
    CHECK_FALSE(c.stiffness_Nm_per_rad);
    CHECK_FALSE(c.damping_ratio);
  }
  const camopt::SpringSpec& spring = spec.springs.at(0);
  CHECK(spring.surge_masses == 0);
  CHECK_FALSE(spring.damping_N_s_per_m);
  CHECK_FALSE(spring.coil_damping_ratio);
  CHECK_FALSE(spring.coil_damping_N_s_per_m);

  // seat = false on the output node: no seat (a mechanism that is not a valvetrain)
  const std::string no_seat = kBase + "seat = false\n";
  const camopt::DesignSpec open = io::parse_design(no_seat, "case.toml", ".");
  CHECK_FALSE(open.nodes[1].seat.enabled);
  CHECK_FALSE(open.nodes[1].seat.given);
  CHECK(open.nodes[1].seat.where.str() == at(no_seat, "false") + ": node[1].seat");
  // seat = {}: a seat of default values, written in the design
  const camopt::DesignSpec empty = io::parse_design(kBase + "seat = {}\n", "case.toml", ".");
  CHECK(empty.nodes[1].seat.enabled);
  CHECK(empty.nodes[1].seat.given);
  CHECK(empty.nodes[1].seat.diameter_mm == 29.0);
}

TEST_CASE("design error: contact law keys", "[io][design][flexible]") {
  check_error(with_contact("law = \"spring\"\n"), "\"spring\"",
              "connection[0].law: value \"spring\" must be one of: hertz, linear");
  check_error(with_contact("law = \"linear\"\ndamping_N_s_per_m = 50\n"), "\"linear\"",
              "connection[0].law: value \"linear\" needs 'stiffness_N_per_mm'");
  check_error(with_contact("law = \"linear\"\nstiffness_N_per_mm = 0\n"), "0\n",
              "connection[0].stiffness_N_per_mm: value 0 must be > 0");
  check_error(with_contact("stiffness_N_per_mm = 300\n"), "300",
              "connection[0].stiffness_N_per_mm: value 300 is not allowed with law = \"hertz\"");
  check_error(with_contact("law = \"hertz\"\nstiffness_N_per_mm = 300\n"), "300",
              "connection[0].stiffness_N_per_mm: value 300 is not allowed with law = \"hertz\"");
  check_error(with_contact("damping_N_s_per_m = -0.5\n"), "-0.5",
              "connection[0].damping_N_s_per_m: value -0.5 must be >= 0");
  check_error(with_contact("damping_law = \"viscous\"\n"), "\"viscous\"",
              "connection[0].damping_law: value \"viscous\" must be one of: hunt_crossley, linear");
  check_error(with_contact("law = \"linear\"\nstiffness_N_per_mm = 3e4\ndamping_law = \"hunt_crossley\"\n"),
              "\"hunt_crossley\"",
              "connection[0].damping_law: value \"hunt_crossley\" is not allowed with law = \"linear\"");
  check_error(with_contact("restitution = 0\n"), "0\n", "connection[0].restitution: value 0 must be in (0, 1]");
  check_error(with_contact("restitution = 1.5\n"), "1.5",
              "connection[0].restitution: value 1.5 must be in (0, 1]");
  check_error(with_contact("law = \"linear\"\nstiffness_N_per_mm = 3e4\nrestitution = 0.8\n"), "0.8",
              "connection[0].restitution: value 0.8 is not allowed with law = \"linear\"");
  check_error(with_contact("damping_law = \"linear\"\nrestitution = 0.8\n"), "0.8",
              "connection[0].restitution: value 0.8 is not allowed with damping_law = \"linear\"");
  check_error(with_contact("damping_N_s_per_m = 50\nrestitution = 0.8\n"), "0.8",
              "connection[0].restitution: value 0.8 is not allowed together with damping_N_s_per_m");
  check_error(with_contact("damping_ratio = 0.1\n"), "damping_ratio",
              "connection[0]: key 'damping_ratio' is not allowed for type = \"contact\"");
}

TEST_CASE("design error: valve seat", "[io][design][flexible]") {
  const auto node = [](const std::string& type, const std::string& extra) {
    return kBase + "[[node]]\nname = \"other\"\ntype = \"" + type + "\"\n" + extra;
  };
  check_error(node("rotational", "pivot_mm = [1, 1]\nseat = { diameter_mm = 30 }\n"), "{ diameter_mm = 30 }",
              "node[2].seat: table is not allowed: a valve seat needs a translational node (node \"other\" is "
              "rotational)");
  check_error(node("floating", "seat = false\n"), "false",
              "node[2].seat: boolean false is not allowed: a valve seat needs a translational node (node \"other\" "
              "is floating)");
  check_error(node("translational", "origin_mm = [5, 5]\nseat = false\n"), "false",
              "node[2].seat: boolean false is allowed only on the output node (design.output_node = \"valve\")");
  check_error(kBase + "seat = true\n", "true", "node[1].seat: boolean true: give a seat table");
  check_error(kBase + "seat = 3\n", "3\n", "node[1].seat: expected false or a seat table, got integer 3");

  const auto seat = [](const std::string& keys) { return kBase + "seat = { " + keys + " }\n"; };
  check_error(seat("diameter_mm = 0"), "0 }", "node[1].seat.diameter_mm: value 0 must be > 0");
  check_error(seat("angle_deg = 90"), "90", "node[1].seat.angle_deg: value 90 must be in (0, 90)");
  check_error(seat("angle_deg = 0"), "0 }", "node[1].seat.angle_deg: value 0 must be in (0, 90)");
  check_error(seat("width_mm = -1.5"), "-1.5", "node[1].seat.width_mm: value -1.5 must be > 0");
  check_error(seat("crown_radius_mm = 0"), "0 }", "node[1].seat.crown_radius_mm: value 0 must be > 0");
  check_error(seat("material = \"brass\""), "\"brass\"",
              "node[1].seat.material: unknown material \"brass\" (none defined)");
  check_error(seat("diamter_mm = 30"), "diamter_mm", "node[1].seat: unknown key 'diamter_mm'");
  check_error(seat("law = \"linear\""), "\"linear\"",
              "node[1].seat.law: value \"linear\" needs 'stiffness_N_per_mm'");
  check_error(seat("law = \"linear\", stiffness_N_per_mm = 1e5, crown_radius_mm = 4"), "crown_radius_mm",
              "node[1].seat: key 'crown_radius_mm' is not allowed for law = \"linear\"");
  check_error(seat("stiffness_N_per_mm = 2000"), "2000",
              "node[1].seat.stiffness_N_per_mm: value 2000 is not allowed with law = \"hertz\"");
  check_error(seat("restitution = 0.8, damping_N_s_per_m = 200"), "0.8",
              "node[1].seat.restitution: value 0.8 is not allowed together with damping_N_s_per_m");
  check_error(seat("damping_law = \"linear\", restitution = 0.8"), "0.8",
              "node[1].seat.restitution: value 0.8 is not allowed with damping_law = \"linear\"");
  check_error(seat("restitution = 1.01"), "1.01", "node[1].seat.restitution: value 1.01 must be in (0, 1]");
}

TEST_CASE("design error: component damping", "[io][design][flexible]") {
  check_error(kBase + "axial_stiffness_N_per_mm = 6e4\ndamping_ratio = 0.05\ndamping_N_s_per_m = 100\n", "100",
              "node[1].damping_N_s_per_m: value 100 is not allowed together with damping_ratio");
  check_error(kBase + "damping_N_s_per_m = 100\n", "100",
              "node[1].damping_N_s_per_m: value 100 needs 'axial_stiffness_N_per_mm'");
  check_error(kBase + "axial_stiffness_N_per_mm = 6e4\ndamping_N_s_per_m = -3\n", "-3",
              "node[1].damping_N_s_per_m: value -3 must be >= 0");
  const std::string rocker = kBase + "[[node]]\nname = \"rocker\"\ntype = \"rotational\"\npivot_mm = [1, 1]\n";
  check_error(rocker + "damping_Nm_s_per_rad = 0.5\n", "0.5",
              "node[2].damping_Nm_s_per_rad: value 0.5 needs 'torsional_stiffness_Nm_per_rad'");
  check_error(rocker + "torsional_stiffness_Nm_per_rad = 4000\ndamping_ratio = 0.1\ndamping_Nm_s_per_rad = 0.5\n",
              "0.5", "node[2].damping_Nm_s_per_rad: value 0.5 is not allowed together with damping_ratio");
  check_error(rocker + "torsional_stiffness_Nm_per_rad = 4000\ndamping_Nm_s_per_rad = -0.5\n", "-0.5",
              "node[2].damping_Nm_s_per_rad: value -0.5 must be >= 0");
  check_error(rocker + "damping_N_s_per_m = 100\n", "damping_N_s_per_m",
              "node[2]: key 'damping_N_s_per_m' is not allowed for type = \"rotational\"");
  check_error(kBase + "axial_stiffness_N_per_mm = 6e4\ndamping_Nm_s_per_rad = 1\n", "damping_Nm_s_per_rad",
              "node[1]: key 'damping_Nm_s_per_rad' is not allowed for type = \"translational\"");
}

TEST_CASE("design error: link and gear compliance", "[io][design][flexible]") {
  const std::string link = kBase + R"([[connection]]
name = "push"
type = "crank_slider"
a = { node = "cam", point_mm = [0, 10] }
b = { node = "valve", point_mm = [0, 40] }
)";
  check_error(link + "stiffness_N_per_mm = 0\n", "0\n", "connection[0].stiffness_N_per_mm: value 0 must be > 0");
  check_error(link + "damping_ratio = -0.1\n", "-0.1", "connection[0].damping_ratio: value -0.1 must be >= 0");
  check_error(link + "stiffness_Nm_per_rad = 100\n", "stiffness_Nm_per_rad",
              "connection[0]: key 'stiffness_Nm_per_rad' is not allowed for type = \"crank_slider\"");
  const std::string gear = kBase + "[[node]]\nname = \"rocker\"\ntype = \"rotational\"\npivot_mm = [1, 1]\n" +
                           "[[connection]]\nname = \"g\"\ntype = \"gear\"\nnodes = [\"cam\", \"rocker\"]\nratio = 2\n";
  check_error(gear + "stiffness_Nm_per_rad = -5\n", "-5", "connection[0].stiffness_Nm_per_rad: value -5 must be > 0");
  check_error(gear + "stiffness_N_per_mm = 100\n", "stiffness_N_per_mm",
              "connection[0]: key 'stiffness_N_per_mm' is not allowed for type = \"gear\"");
  check_error(gear + "restitution = 0.5\n", "restitution",
              "connection[0]: key 'restitution' is not allowed for type = \"gear\"");
  const std::string rack = kBase + "[[connection]]\nname = \"r\"\ntype = \"rack_pinion\"\nnodes = [\"cam\", "
                                   "\"valve\"]\npitch_radius_mm = 10\n";
  check_error(rack + "stiffness_N_per_mm = -1\n", "-1", "connection[0].stiffness_N_per_mm: value -1 must be > 0");
  check_error(rack + "damping_ratio = -1\n", "-1", "connection[0].damping_ratio: value -1 must be >= 0");
}

TEST_CASE("design error: spring damping and surge masses", "[io][design][flexible]") {
  const std::string spring =
      kBase + "[[spring]]\nname = \"s\"\ntype = \"compression\"\nnode = \"valve\"\nrate_N_per_mm = 30\n";
  check_error(spring + "damping_N_s_per_m = -2\n", "-2", "spring[0].damping_N_s_per_m: value -2 must be >= 0");
  check_error(spring + "coil_damping_ratio = 0.02\n", "0.02",
              "spring[0].coil_damping_ratio: value 0.02 needs 'surge_masses' > 0");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = 0\ncoil_damping_N_s_per_m = 4.5\n", "4.5",
              "spring[0].coil_damping_N_s_per_m: value 4.5 needs 'surge_masses' > 0");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = 4\ncoil_damping_ratio = 0.02\ncoil_damping_N_s_per_m = 4.5\n",
              "4.5", "spring[0].coil_damping_N_s_per_m: value 4.5 is not allowed together with coil_damping_ratio");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = 4\ncoil_damping_ratio = -0.01\n", "-0.01",
              "spring[0].coil_damping_ratio: value -0.01 must be >= 0");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = 4\ncoil_damping_N_s_per_m = -1\n", "-1",
              "spring[0].coil_damping_N_s_per_m: value -1 must be >= 0");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = 501\n", "501",
              "spring[0].surge_masses: value 501 must be <= 500 (every surge mass adds a "
              "coordinate to the flexible model");
  check_error(spring + "mass_kg = 0.03\nsurge_masses = -1\n", "-1", "spring[0].surge_masses: value -1 must be >= 0");
  const std::string torsion = kBase + "[[spring]]\nname = \"t\"\ntype = \"torsion\"\nnode = \"cam\"\n" +
                              "rate_Nmm_per_deg = 5\ndamping_N_s_per_m = 1\n";
  check_error(torsion, "damping_N_s_per_m",
              "spring[0]: key 'damping_N_s_per_m' is not allowed for type = \"torsion\"");
}

namespace {

void check_same_law(const camopt::ContactLawSpec& a, const camopt::ContactLawSpec& b) {
  CHECK(a.law == b.law);
  CHECK(a.damping_law == b.damping_law);
  CHECK(a.stiffness_N_per_mm == b.stiffness_N_per_mm);
  CHECK(a.damping_N_s_per_m == b.damping_N_s_per_m);
  CHECK(a.restitution == b.restitution);
}

}  // namespace

TEST_CASE("a design rewritten with a new profile file keeps the flexible-model keys", "[io][design][flexible]") {
  // camopt synthesize writes DIR/design.toml with design_with_profile_file
  const TempDir dir;
  const std::string original = kFlexible + R"([[profile]]
name = "lobe"
form = "circle"
disc_radius_mm = 20
)";
  const std::string design = dir.write("design.toml", original);
  const std::string table = dir.write("profile.csv", "angle_deg,radius_mm\n0,20\n60,21\n120,24\n180,25\n240,24\n300,21\n");
  const std::string rewritten = io::design_with_profile_file(design, "lobe", "profile.csv", dir.path().string());
  INFO(rewritten);
  const camopt::DesignSpec a = io::parse_design(original, "design.toml", dir.path().string());
  const camopt::DesignSpec b = io::parse_design(rewritten, "rewritten.toml", dir.path().string());

  REQUIRE(b.profiles.size() == 1);
  CHECK(b.profiles[0].form == camopt::ProfileForm::polar);
  CHECK(b.profiles[0].source_file == table);

  REQUIRE(a.nodes.size() == b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    INFO("node " << a.nodes[i].name);
    CHECK(a.nodes[i].damping_N_s_per_m == b.nodes[i].damping_N_s_per_m);
    CHECK(a.nodes[i].damping_Nm_s_per_rad == b.nodes[i].damping_Nm_s_per_rad);
    CHECK(a.nodes[i].damping_ratio == b.nodes[i].damping_ratio);
    const camopt::SeatSpec& sa = a.nodes[i].seat;
    const camopt::SeatSpec& sb = b.nodes[i].seat;
    CHECK(sa.enabled == sb.enabled);
    CHECK(sa.given == sb.given);
    CHECK(sa.diameter_mm == sb.diameter_mm);
    CHECK(sa.angle_deg == sb.angle_deg);
    CHECK(sa.width_mm == sb.width_mm);
    CHECK(sa.crown_radius_mm == sb.crown_radius_mm);
    CHECK(sa.material == sb.material);
    check_same_law(sa.law, sb.law);
  }
  CHECK(b.nodes[1].seat.given);
  CHECK(b.nodes[3].seat.law.law == camopt::ContactLaw::linear);

  REQUIRE(a.connections.size() == b.connections.size());
  for (std::size_t i = 0; i < a.connections.size(); ++i) {
    INFO("connection " << a.connections[i].name);
    check_same_law(a.connections[i].contact_law, b.connections[i].contact_law);
    CHECK(a.connections[i].stiffness_N_per_mm == b.connections[i].stiffness_N_per_mm);
    CHECK(a.connections[i].stiffness_Nm_per_rad == b.connections[i].stiffness_Nm_per_rad);
    CHECK(a.connections[i].damping_ratio == b.connections[i].damping_ratio);
  }
  CHECK(b.connections[1].contact_law.law == camopt::ContactLaw::linear);

  REQUIRE(a.springs.size() == b.springs.size());
  for (std::size_t i = 0; i < a.springs.size(); ++i) {
    INFO("spring " << a.springs[i].name);
    CHECK(a.springs[i].surge_masses == b.springs[i].surge_masses);
    CHECK(a.springs[i].damping_N_s_per_m == b.springs[i].damping_N_s_per_m);
    CHECK(a.springs[i].coil_damping_ratio == b.springs[i].coil_damping_ratio);
    CHECK(a.springs[i].coil_damping_N_s_per_m == b.springs[i].coil_damping_N_s_per_m);
  }

  // seat = false survives as well
  const std::string open = dir.write("open.toml", kBase + "seat = false\n[[profile]]\nname = \"lobe\"\nform = \"circle\"\n"
                                                  "disc_radius_mm = 20\n");
  const camopt::DesignSpec c =
      io::parse_design(io::design_with_profile_file(open, "lobe", "profile.csv", dir.path().string()), "open.toml",
                        dir.path().string());
  CHECK_FALSE(c.nodes[1].seat.enabled);
}
