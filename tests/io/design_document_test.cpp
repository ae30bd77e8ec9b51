// the design document: key paths read and set on a design's text, the parsed spec against
// a file edited by hand, and the message of every kind of bad override
#include "camopt/io/design_document.hpp"
#include "support/input_error.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"

namespace {

using namespace camopt;
using camopt::test::input_error_of;

const std::string kDesigns = std::string(CAMOPT_SOURCE_DIR) + "/designs";
const std::string kRff = kDesigns + "/roller_finger_follower.toml";


// `text` with its first `from` replaced by `to` (the file a user would edit by hand)
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

TEST_CASE("key paths read every kind of value of a design") {
  const io::DesignDocument doc = io::DesignDocument::load(kRff);
  CHECK(doc.get("design.name") == "\"roller_finger_follower\"");
  CHECK(doc.get("node.finger.mass_kg") == "0.040");
  CHECK(doc.get_number("node.finger.mass_kg") == 0.04);
  CHECK(doc.get("node.finger.pivot_mm") == "[-22, -28.5]");
  CHECK(doc.get_number("node.finger.pivot_mm[1]") == -28.5);
  CHECK(doc.get_number("connection.cam_roller.b.radius_mm") == 8.5);
  CHECK(doc.get("connection.cam_roller.b.roller") == "true");
  CHECK(doc.get_number("spring.valve_spring.rate_N_per_mm") == 35);
  CHECK(doc.get_number("oil.viscosity_mPa_s") == 9.1);
}

TEST_CASE("a set changes the value the spec reads and nothing else") {
  io::DesignDocument doc = io::DesignDocument::load(kRff);
  doc.set("node.finger.mass_kg", "0.05");
  doc.set("node.finger.pivot_mm[0]", "-21.5");
  doc.set("connection.cam_roller.b.radius_mm", "9");
  doc.set("spring.valve_spring.rate_N_per_mm", "40");
  doc.set("design.name", "\"study\"");
  doc.set("driver.step_deg", "0.5");  // absent from the file: added to [driver]
  CHECK(doc.get("node.finger.mass_kg") == "0.05");
  CHECK(doc.get("driver.step_deg") == "0.5");
  const DesignSpec s = doc.spec();
  CHECK(s.name == "study");
  CHECK(s.driver.step_deg == 0.5);
  CHECK(s.nodes[1].mass_kg == 0.05);
  CHECK(s.nodes[1].pivot_mm == Vec2{-21.5, -28.5});
  CHECK(s.connections[0].surface_b.radius_mm == 9);
  CHECK(s.springs[0].rate_N_per_mm == 40);
  // the same edits made by hand give the same spec, value for value
  std::string text = doc.text();
  const std::string original = io::DesignDocument::load(kRff).text();
  std::string by_hand = replaced(original, "mass_kg = 0.040", "mass_kg = 0.05");
  by_hand = replaced(by_hand, "pivot_mm = [-22, -28.5]", "pivot_mm = [-21.5, -28.5]");
  by_hand = replaced(by_hand, "radius_mm = 8.5", "radius_mm = 9");
  by_hand = replaced(by_hand, "rate_N_per_mm = 35", "rate_N_per_mm = 40");
  by_hand = replaced(by_hand, "name = \"roller_finger_follower\"", "name = \"study\"");
  by_hand = replaced(by_hand, "[driver]\n", "[driver]\nstep_deg = 0.5\n");
  CHECK(text == by_hand);
  // comments stay as written
  CHECK(text.find("# about the cg (pressed-steel finger ~ 45 mm long)") != std::string::npos);
}

TEST_CASE("a whole array and a bare word are set") {
  io::DesignDocument doc = io::DesignDocument::load(kRff);
  doc.set("node.finger.pivot_mm", "[-20, -29]");
  doc.set("design.name", "study_2");  // a bare word is a string
  const DesignSpec s = doc.spec();
  CHECK(s.nodes[1].pivot_mm == Vec2{-20, -29});
  CHECK(s.name == "study_2");
  // an inline table gets a key it did not have
  doc.set("connection.pad_valve.a.concave", "false");
  CHECK(doc.get("connection.pad_valve.a") ==
        "{ node = \"finger\", shape = \"circle\", center_mm = [17.6, -18.5], radius_mm = 12, concave = false }");
}

TEST_CASE("a bad override is an InputError naming it as given") {
  io::DesignDocument doc = io::DesignDocument::load(kRff);
  CHECK(input_error_of([&] { doc.set("node.fingr.mass_kg", "0.05"); }) ==
        "--set node.fingr.mass_kg=0.05: no [[node]] named \"fingr\" (cam, finger, valve)");
  CHECK(input_error_of([&] { doc.set("drivr.step_deg", "2"); }) ==
        "--set drivr.step_deg=2: no key 'drivr' in the file (keys: connection, design, driver, material, node, oil, "
        "profile, schema, spring)");
  CHECK(input_error_of([&] { doc.set("node.finger.pivot_mm[2]", "1"); }) ==
        "--set node.finger.pivot_mm[2]=1: index 2 is out of range (node.finger.pivot_mm has 2 elements)");
  CHECK(input_error_of([&] { doc.set("node.finger.mass_kg", "\"heavy\""); }) ==
        "--set node.finger.mass_kg=\"heavy\": node.finger.mass_kg is a number in the file (0.040), got string "
        "\"heavy\"");
  CHECK(input_error_of([&] { doc.set("node.finger.mass_kg", "1 2"); }) ==
        "--set node.finger.mass_kg=1 2: value \"1 2\" is not a TOML value (a number, a \"string\", true or false, or "
        "an array [a, b])");
  CHECK(input_error_of([&] { doc.set("node.finger", "1"); }) ==
        "--set node.finger=1: node.finger is a table; name a key inside it (e.g. node.finger.name)");
  CHECK(input_error_of([] { (void)io::parse_override("node.finger.mass_kg"); }) ==
        "--set node.finger.mass_kg: expected KEY=VALUE, a key path and a TOML value (e.g. --set "
        "connection.cam_roller.b.radius_mm=9)");
  // nothing was changed by the refused overrides
  CHECK(doc.overrides().empty());
  CHECK(doc.text() == io::DesignDocument::load(kRff).text());
}

TEST_CASE("a value that breaks a design rule is reported at its override") {
  io::DesignDocument doc = io::DesignDocument::load(kRff);
  doc.set(io::parse_override("connection.cam_roller.b.radius_mm=-1"));
  CHECK(input_error_of([&] { (void)doc.spec(); }) ==
        "--set connection.cam_roller.b.radius_mm=-1: connection[0].b.radius_mm: value -1 must be in [0.001, "
        "1e+06]");
  // an unknown key added by an override is refused at the override, with the allowed keys
  io::DesignDocument typo = io::DesignDocument::load(kRff);
  typo.set("node.finger.mass_kgg", "0.05");
  const std::string message = input_error_of([&] { (void)typo.spec(); });
  CHECK(message.rfind("--set node.finger.mass_kgg=0.05: node[1]: unknown key 'mass_kgg' (allowed: ", 0) == 0);
  // an untouched key keeps its file location
  io::DesignDocument other = io::DesignDocument::load(kRff);
  other.set("node.finger.mass_kg", "0.05");
  other.set("spring.valve_spring.solid_length_mm", "40");
  CHECK(input_error_of([&] { (void)other.spec(); }) ==
        "--set spring.valve_spring.solid_length_mm=40: spring[0].solid_length_mm: value 40 must be > 0 and < "
        "installed_length_mm (38.8)");
}

TEST_CASE("a constraint set takes overrides with its own option name") {
  const std::string path = std::string(CAMOPT_SOURCE_DIR) + "/constraints/cvvl_swing_cam.toml";
  const opt::OptimizationSpec base = io::load_constraints(path);
  const opt::OptimizationSpec changed =
      io::load_constraints(path, {io::parse_override("limits.max_pressure_angle_deg=28", "--set-constraint")});
  CHECK(base.limits.max_pressure_angle_deg == 30.0);
  CHECK(changed.limits.max_pressure_angle_deg == 28.0);
  CHECK(input_error_of([&] {
          (void)io::load_constraints(path, {io::parse_override("limits.max_pressure_angle_deg=-1", "--set-constraint")});
        }).rfind("--set-constraint limits.max_pressure_angle_deg=-1: limits.max_pressure_angle_deg: value -1 must be", 0) == 0);
}

}  // namespace
