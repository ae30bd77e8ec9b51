#pragma once
// shared pieces of the design-file tests: where a snippet sits in a text, the error a text
// gives, and two complete designs (kBase, kGood) to edit
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/io/design_file.hpp"

namespace camopt::design_file_test {

// "case.toml:LINE:COL" of the first occurrence of `snippet` in `text`
inline std::string at(const std::string& text, const std::string& snippet, const std::string& file = "case.toml") {
  const std::size_t pos = text.find(snippet);
  REQUIRE(pos != std::string::npos);
  const std::size_t line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n');
  const std::size_t line_start = text.rfind('\n', pos == 0 ? 0 : pos - 1);
  const std::size_t column = line_start == std::string::npos || pos == 0 ? pos + 1 : pos - line_start;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

inline int line_of(const std::string& text, const std::string& snippet) {
  const std::string where = at(text, snippet);
  const std::size_t a = where.find(':') + 1;
  return std::stoi(where.substr(a, where.find(':', a) - a));
}

// the InputError message parse_design gives for `text`
inline std::string error_of(const std::string& text, const std::string& directory = ".") {
  try {
    (void)io::parse_design(text, "case.toml", directory);
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("expected an InputError for:\n" << text);
  return {};
}


// smallest valid design; error cases append one section to it
inline const std::string kBase = R"(schema = 1
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

inline const std::string kGood = R"(schema = 1

[design]
name = "rocker_cvvl"
description = "roller rocker with an eccentric control shaft"
output_node = "valve"

[driver]
node = "cam"
step_deg = 0.5

[[control]]
name = "shaft"
min = 0
max = 16
default = 4

[[node]]
name = "cam"
type = "rotational"
pivot_mm = [0, 0]
inertia_kg_mm2 = 120

[[node]]
name = "rocker"
type = "rotational"
pivot_mm = [40, 30]
pivot_motion = { control = "shaft", about_mm = [40, 45], gain = 1.5 }
mass_kg = 0.08

[[node]]
name = "valve"
type = "translational"
origin_mm = [80, 20]
direction = [0, -1]
mass_kg = 0.05

[[profile]]
name = "lobe"
form = "base_plus_lift"
base_radius_mm = 18
angle_deg = [0, 60, 120, 180, 240, 300]
lift_mm = [0, 2, 6, 8, 6, 2]

[[material]]
name = "steel"
youngs_modulus_GPa = 210
poisson_ratio = 0.3

[[connection]]
name = "cam_roller"
type = "contact"
a = { node = "cam", shape = "profile", profile = "lobe", orientation_deg = 90 }
b = { node = "rocker", shape = "circle", center_mm = [0, 30], radius_mm = 10, roller = true }
materials = ["steel", "steel"]
width_mm = 12

[[connection]]
name = "pad_valve"
type = "contact"
a = { node = "rocker", shape = "circle", center_mm = [80, 28], radius_mm = 8 }
b = { node = "valve", shape = "line", point_mm = [80, 20], normal = [0, 1] }
lash_mm = 0.1

[[spring]]
name = "valve_spring"
type = "compression"
node = "valve"
table = { displacement_mm = [0, 5, 10], force_N = [250, 400, 580] }
mass_kg = 0.03
surge_masses = 4

[[gas_force]]
node = "valve"
crank_angle_deg = [0, 180, 360]
force_N = [0, 50, 0]
)";

}  // namespace camopt::design_file_test
