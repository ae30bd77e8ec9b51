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

TEST_CASE("a full design parses into DesignSpec with source references", "[io][design]") {
  const camopt::DesignSpec spec = io::parse_design(kGood, "case.toml", "/designs");
  CHECK(spec.name == "rocker_cvvl");
  CHECK(spec.file == "case.toml");
  CHECK(spec.directory == "/designs");
  CHECK(spec.output_node == "valve");

  // driver defaults
  CHECK(spec.driver.node == "cam");
  CHECK(spec.driver.start_deg == 0.0);
  CHECK(spec.driver.stop_deg == 360.0);
  CHECK(spec.driver.step_deg == 0.5);
  CHECK(spec.driver.crank_per_cam == 2.0);
  CHECK(spec.driver.where.line == line_of(kGood, "[driver]"));

  REQUIRE(spec.controls.size() == 1);
  CHECK(spec.controls[0].unit == "deg");
  CHECK(spec.controls[0].default_value == 4.0);

  REQUIRE(spec.nodes.size() == 3);
  const camopt::NodeSpec& rocker = spec.nodes[1];
  CHECK(rocker.kind == camopt::NodeKind::rotational);
  CHECK(rocker.pivot_mm == camopt::Vec2{40.0, 30.0});
  CHECK(rocker.where.key_path == "node[1]");
  CHECK(rocker.where.line == line_of(kGood, "name = \"rocker\"") - 1);  // the [[node]] header
  REQUIRE(rocker.pivot_motion);
  CHECK(rocker.pivot_motion->gain == 1.5);
  CHECK(rocker.pivot_motion->where.str() == at(kGood, "{ control = \"shaft\"") + ": node[1].pivot_motion");
  CHECK(spec.nodes[2].kind == camopt::NodeKind::translational);
  CHECK(spec.nodes[2].direction == camopt::Vec2{0.0, -1.0});
  CHECK(*spec.nodes[2].mass_kg == 0.05);
  CHECK_FALSE(spec.nodes[0].mass_kg);

  REQUIRE(spec.profiles.size() == 1);
  CHECK(spec.profiles[0].form == camopt::ProfileForm::base_plus_lift);
  CHECK(spec.profiles[0].base_radius_mm == 18.0);
  CHECK(spec.profiles[0].lift_mm == std::vector<double>{0, 2, 6, 8, 6, 2});
  CHECK(spec.profiles[0].source_file.empty());

  REQUIRE(spec.connections.size() == 2);
  const camopt::ConnectionSpec& roller = spec.connections[0];
  CHECK(roller.kind == camopt::ConnectionKind::contact);
  CHECK(roller.surface_a.shape == camopt::SurfaceShape::profile);
  CHECK(roller.surface_a.orientation_deg == 90.0);
  CHECK(roller.surface_b.roller);
  CHECK(roller.surface_b.radius_mm == 10.0);
  CHECK(roller.surface_b.origin_mm == camopt::Vec2{0.0, 30.0});
  CHECK(roller.material_b == "steel");
  CHECK(roller.surface_b.where.str() == at(kGood, "{ node = \"rocker\", shape = \"circle\"") + ": connection[0].b");
  CHECK(spec.connections[1].surface_b.shape == camopt::SurfaceShape::line);
  CHECK(spec.connections[1].lash_mm == 0.1);

  REQUIRE(spec.springs.size() == 1);
  CHECK(spec.springs[0].table_force_N == std::vector<double>{250, 400, 580});
  CHECK(spec.springs[0].surge_masses == 4);
  REQUIRE(spec.gas_forces.size() == 1);
  CHECK(spec.gas_forces[0].force_N[1] == 50.0);
}

TEST_CASE("the example in docs/design-format.md parses", "[io][design]") {
  std::ifstream in(fs::path(CAMOPT_SOURCE_DIR) / "docs" / "design-format.md");
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const std::size_t heading = text.find("## Complete example");
  REQUIRE(heading != std::string::npos);
  const std::size_t begin = text.find("```toml\n", heading);
  REQUIRE(begin != std::string::npos);
  const std::size_t end = text.find("```", begin + 8);
  REQUIRE(end != std::string::npos);
  const camopt::DesignSpec spec = io::parse_design(text.substr(begin + 8, end - begin - 8), "example.toml", ".");
  CHECK(spec.name == "rocker_cvvl");
  CHECK(spec.nodes.size() == 3);
  CHECK(spec.connections.size() == 2);
}

TEST_CASE("profile and gas tables are read from CSV files next to the design", "[io][design]") {
  const TempDir dir;
  dir.write("lobe.csv", "# polar lobe\npolar_angle_deg, radius_mm\n0,20\n60,21\n120,24\n180,25\n240,24\n300,21\n");
  dir.write("gas.csv", "crank_deg;force_N\n0;0\n360;40\n720;0\n");
  const std::string text = kBase + R"([[profile]]
name = "lobe"
form = "polar"
file = "lobe.csv"
[[gas_force]]
node = "valve"
file = "gas.csv"
)";
  const camopt::DesignSpec spec = io::parse_design(text, "case.toml", dir.path().string());
  REQUIRE(spec.profiles.size() == 1);
  CHECK(spec.profiles[0].angle_deg == std::vector<double>{0, 60, 120, 180, 240, 300});
  CHECK(spec.profiles[0].radius_mm[4] == 24.0);
  CHECK(spec.profiles[0].source_file == (dir.path() / "lobe.csv").string());
  CHECK(spec.gas_forces[0].crank_angle_deg.back() == 720.0);

  // load_design resolves against the file's own directory
  const std::string path = dir.write("design.toml", text);
  CHECK(io::load_design(path).profiles[0].radius_mm.size() == 6);
}

// ---- one test per error class: file name, line, key path and value in the message

TEST_CASE("design error: TOML syntax", "[io][design]") {
  const std::string text = kBase + "[[node]]\nname = \"rocker\ntype = \"rotational\"\n";
  const std::string message = error_of(text);
  CHECK_THAT(message, Contains("case.toml:" + std::to_string(line_of(text, "name = \"rocker")) + ":"));
  CHECK_THAT(message, Contains("TOML syntax error"));
}

TEST_CASE("design error: unknown key", "[io][design]") {
  const std::string text = kBase + R"([[connection]]
name = "c1"
type = "link"
a = { node = "cam", point_mm = [0, 10] }
b = { node = "valve", point_mm = [0, 40] }
lenght_mm = 30
)";
  CHECK_THAT(error_of(text), Contains(at(text, "lenght_mm") + ": connection[0]: unknown key 'lenght_mm' " +
                                      "(allowed: name, type, a, b, length_mm, "
                                      "stiffness_N_per_mm, damping_ratio)"));
}

TEST_CASE("design error: wrong type", "[io][design]") {
  const std::string text = kBase + "[[node]]\nname = \"rocker\"\ntype = \"rotational\"\npivot_mm = \"a\"\n";
  CHECK_THAT(error_of(text),
             Contains(at(text, "\"a\"") + ": node[2].pivot_mm: expected an array of 2 numbers, got string \"a\""));
}

TEST_CASE("design error: missing required key", "[io][design]") {
  const std::string text = kBase + "[[node]]\nname = \"rocker\"\npivot_mm = [1, 2]\n";
  CHECK_THAT(error_of(text), Contains(at(text, "[[node]]\nname = \"rocker\"") + ": node[2]: missing required key 'type'"));
}

TEST_CASE("design error: value out of range", "[io][design]") {
  const std::string text = kBase + R"([[connection]]
name = "c1"
type = "contact"
a = { node = "cam", shape = "circle", center_mm = [0, 5], radius_mm = 20 }
b = { node = "valve", shape = "circle", center_mm = [0, 40], radius_mm = -2 }
)";
  CHECK_THAT(error_of(text), Contains(at(text, "-2 }") + ": connection[0].b.radius_mm: value -2 must be in [0.001, 1e+06]"));

  // inline table values are named by their index
  const std::string table = kBase + R"([[profile]]
name = "lobe"
form = "polar"
angle_deg = [0, 60, 120, 180, 240, 300]
radius_mm = [20, 21, 24, 25, 24, -1]
)";
  CHECK_THAT(error_of(table), Contains(at(table, "-1]") + ": profile[0].radius_mm[5]: value -1 must be > 0"));
}

TEST_CASE("design error: bad enum value", "[io][design]") {
  const std::string text = kBase + "[[connection]]\nname = \"g\"\ntype = \"gearbox\"\n";
  CHECK_THAT(error_of(text), Contains(at(text, "\"gearbox\"") + ": connection[0].type: value \"gearbox\" must be " +
                                      "one of: link, crank_slider, gear, variable_gear, rack_pinion, contact"));
}

TEST_CASE("design error: duplicate name", "[io][design]") {
  const std::string text = kBase + "[[node]]\nname = \"cam\"\ntype = \"floating\"\n";
  CHECK_THAT(error_of(text), Contains(at(text, "\"cam\"\ntype = \"floating\"") +
                                      ": node[2].name: duplicate name \"cam\" (already used by node[0] at line 7)"));
}

TEST_CASE("design error: unknown reference", "[io][design]") {
  const std::string text = kBase + R"([[connection]]
name = "c1"
type = "link"
a = { node = "cam", point_mm = [0, 10] }
b = { node = "rockr", point_mm = [0, 40] }
)";
  CHECK_THAT(error_of(text),
             Contains(at(text, "\"rockr\"") + ": connection[0].b.node: unknown node \"rockr\" (defined: cam, valve; or 'ground' for the fixed frame)"));
}

TEST_CASE("design error: missing CSV file", "[io][design]") {
  const TempDir dir;
  const std::string text = kBase + "[[profile]]\nname = \"lobe\"\nform = \"polar\"\nfile = \"no_lobe.csv\"\n";
  const std::string resolved = (dir.path() / "no_lobe.csv").string();
  CHECK_THAT(error_of(text, dir.path().string()),
             Contains(at(text, "\"no_lobe.csv\"") + ": profile[0].file: file \"no_lobe.csv\" not found (resolved to \"" +
                      resolved + "\")"));
}

TEST_CASE("design error: bad cell in a referenced CSV file", "[io][design]") {
  const TempDir dir;
  const std::string csv = dir.write("lobe.csv", "angle_deg,radius_mm\n0,20\n60,21\n120,abc\n180,25\n240,24\n300,21\n");
  const std::string text = kBase + "[[profile]]\nname = \"lobe\"\nform = \"polar\"\nfile = \"lobe.csv\"\n";
  const std::string message = error_of(text, dir.path().string());
  CHECK_THAT(message, Contains(at(text, "\"lobe.csv\"") + ": profile[0].file: " + csv + ":4:"));
  CHECK_THAT(message, Contains("'abc'"));

  // table rules on CSV values name the CSV line
  dir.write("lobe.csv", "angle_deg,radius_mm\n0,20\n60,21\n120,24\n180,25\n240,-3\n300,21\n");
  CHECK_THAT(error_of(text, dir.path().string()),
             Contains("profile[0].file: " + csv + ":6: radius_mm: value -3 must be > 0"));
}

// ---- tests/data/bad_designs: each file states the message it must produce

TEST_CASE("every bad design file gives its expected error", "[io][design]") {
  const fs::path folder = fs::path(CAMOPT_SOURCE_DIR) / "tests" / "data" / "bad_designs";
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".toml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 10);

  for (const fs::path& file : files) {
    INFO(file.string());
    std::ifstream in(file);
    std::string first_line;
    std::getline(in, first_line);
    const std::string prefix = "# expect: ";
    REQUIRE(first_line.rfind(prefix, 0) == 0);
    const std::string expected = first_line.substr(prefix.size());
    std::string message;
    try {
      (void)io::load_design(file.string());
    } catch (const InputError& e) {
      message = e.what();
    }
    CHECK_THAT(message, Contains(expected));
  }
}
