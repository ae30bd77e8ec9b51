// scene-driven computation: the rigid model carries no spring masses (a spring's
// mass enters as m/3 on its node whatever its surge setting; only the flexible model makes
// surge masses), and a kinematics run never builds the dynamics model (it runs on a design
// whose dynamics data would be rejected).
#include <catch2/catch.hpp>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cli/cli_support.hpp"
#include "dynamics/dynamics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using camopt::dyn_test::valve_with_spring_mass;

TEST_CASE("scene: rigid mode carries no spring masses, whatever the spring's surge setting", "[dynamics][scene]") {
  const DesignSpec massless_spec = valve_with_spring_mass(0);
  const kin::Mechanism massless_mech = kin::compile(massless_spec);
  const DesignSpec surge_spec = valve_with_spring_mass(6);
  const kin::Mechanism surge_mech = kin::compile(surge_spec);
  const dynamics::Model massless = dynamics::compile_dynamics(massless_spec, massless_mech);
  const dynamics::Model surge = dynamics::compile_dynamics(surge_spec, surge_mech);
  const int tappet = massless_mech.node_index("tappet");
  // the spring's mass enters the rigid model once, as m/3 on its node [kg]
  CHECK_REL(massless.bodies[tappet].mass, 0.07 + 0.045 / 3, camopt::test::tol::kUlpRel);
  CHECK(surge.bodies[tappet].mass == massless.bodies[tappet].mass);
  // one free coordinate (the tappet): no row for a spring mass
  CHECK(surge.free_variables.size() == 1);
  dynamics::RigidWorkspace ws_massless(massless_mech, massless), ws_surge(surge_mech, surge);
  for (double deg : {0.0, 40.0, 90.0, 135.0, 200.0}) {
    INFO("cam " << deg << " deg");
    REQUIRE(dynamics::solve_rigid(massless_mech, massless, ws_massless, deg * pi / 180).ok());
    REQUIRE(dynamics::solve_rigid(surge_mech, surge, ws_surge, deg * pi / 180).ok());
    CHECK(ws_surge.mass.rows() == 1);
    // the same numbers, bit for bit: the surge setting does not reach the rigid solve
    CHECK(ws_surge.mass(0, 0) == ws_massless.mass(0, 0));
    CHECK(ws_surge.force.size() > 0);
    CHECK((ws_surge.force.array() == ws_massless.force.array()).all());
    CHECK((ws_surge.torque.array() == ws_massless.torque.array()).all());
  }
  // the flexible model does make them: one more natural frequency per surge mass
  dynamics::FlexibleOptions opt;
  std::vector<double> f_massless, f_surge;
  REQUIRE(dynamics::flexible_modes(massless_mech, massless, {}, 0.0, opt, false, f_massless).ok());
  REQUIRE(dynamics::flexible_modes(surge_mech, surge, {}, 0.0, opt, false, f_surge).ok());
  CHECK(f_surge.size() == f_massless.size() + 6);
}

TEST_CASE("scene: camopt kinematics does not build the dynamics model", "[dynamics][scene][cli]") {
  using namespace camopt::test;
  TempDir tmp;
  // the bucket tappet without the tappet's mass: dynamics rejects it, kinematics needs none of it
  std::string text = read_file(source_dir() / "designs/bucket_tappet.toml");
  const std::string stripped = std::regex_replace(text, std::regex("mass_kg = 0.0573[^\n]*\n"), "\n");
  REQUIRE(stripped != text);
  text = std::regex_replace(stripped, std::regex("file = \"profiles/"),
                            "file = \"" + (source_dir() / "designs/profiles/").string());
  const fs::path design = tmp / "no_mass.toml";
  write_text(design, text);
  const auto dyn = run_camopt({"dynamics", design.string(), "--rpm", "3000", "--out", (tmp / "dyn").string()});
  INFO(dyn.command << "\n" << dyn.all());
  REQUIRE(dyn.exit_code == cli_input_error);
  REQUIRE(dyn.err.find("mass_kg is required") != std::string::npos);
  const fs::path out = tmp / "kin";
  const auto kin = run_camopt({"kinematics", design.string(), "--out", out.string(), "--step", "1"});
  INFO(kin.command << "\n" << kin.all());
  CHECK(kin.exit_code == cli_ok);
  // and gives the same lift as the complete design
  const fs::path full_out = tmp / "kin_full";
  const auto full = run_camopt({"kinematics", (source_dir() / "designs/bucket_tappet.toml").string(), "--out",
                                full_out.string(), "--step", "1"});
  REQUIRE(full.exit_code == cli_ok);
  const std::string csv = read_file(out / "kinematics.csv");
  CHECK(csv.size() > 1000);
  CHECK(csv == read_file(full_out / "kinematics.csv"));
}
