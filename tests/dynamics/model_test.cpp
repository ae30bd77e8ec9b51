// compile_dynamics (model.cpp): the flexible model's data (node compliances, valve seats, link
// stiffness, coil chains, contact laws) compiled from the design once, in the models' units,
// and the dynamics reading only the Model after that. The rigid model's checks of missing or
// bad data are in rigid_test.cpp.
#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "dynamics/dynamics_test_support.hpp"

using namespace camopt;

namespace {

// the direct-acting valve with a compliant valve, a damped 6-mass spring and a given seat
DesignSpec flexible_valve() {
  DesignSpec d = dyn_test::valve_with_spring_mass(6);
  NodeSpec& valve = d.nodes[1];
  valve.axial_stiffness_N_per_mm = 60000;
  valve.damping_N_s_per_m = 200;
  valve.seat.given = true;
  valve.seat.diameter_mm = 30;
  valve.seat.angle_deg = 30;
  SpringSpec& s = d.springs[0];
  s.damping_N_s_per_m = 5;
  s.coil_damping_ratio = 0.02;
  s.installed_length_mm = 38;
  s.solid_length_mm = 27;
  d.connections[0].contact_law.restitution = 0.7;
  return d;
}

}  // namespace

TEST_CASE("model: the flexible model's data is compiled from the design in the models' units", "[dynamics][model]") {
  const DesignSpec spec = flexible_valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  const int valve = mech.node_index("tappet");
  REQUIRE(model.compliances.size() == 1);
  CHECK(model.compliances[0].node == valve);
  CHECK(model.compliances[0].stiffness == 60000);  // [N/mm]
  REQUIRE(model.compliances[0].damping.has_value());
  CHECK(*model.compliances[0].damping == 200 * 1e-3);  // [N s/mm]
  CHECK_FALSE(model.compliances[0].damping_ratio.has_value());
  REQUIRE(model.seats.size() == 1);
  CHECK(model.seats[0].node == valve);
  CHECK(model.seats[0].given);
  CHECK(model.seats[0].diameter == 30);
  CHECK(model.seats[0].angle_deg == 30);
  // no seat material: the valve's contact material (steel) against a steel insert
  CHECK(model.seats[0].e_star == dynamics::contact_modulus(210e3, 0.3, 210e3, 0.3));
  REQUIRE(model.springs.size() == 1);
  const dynamics::Spring& s = model.springs[0];
  CHECK(s.mass == 0.045);
  CHECK(s.surge_masses == 6);
  CHECK(s.damping == 5 * 1e-3);  // [N s/mm]
  REQUIRE(s.coil_damping_ratio.has_value());
  CHECK(*s.coil_damping_ratio == 0.02);
  CHECK_FALSE(s.coil_damping.has_value());
  CHECK(s.solid_travel == 38 - 27);  // [mm]
  REQUIRE(model.contacts.size() == 1);
  CHECK(model.contacts[0].law.restitution == 0.7);
  CHECK(model.links.size() == 1);
  CHECK(model.driver_start_deg == spec.driver.start_deg);
  CHECK_FALSE(model.oil.has_value());
}

TEST_CASE("model: after compile_dynamics the flexible model reads the Model, not the design", "[dynamics][model]") {
  const DesignSpec spec = flexible_valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  // the same Model with a mechanism compiled from a design whose dynamics data say otherwise:
  // the same parameters
  DesignSpec changed = spec;
  changed.nodes[1].axial_stiffness_N_per_mm = 1.0;
  changed.nodes[1].seat.diameter_mm = 50;
  changed.springs[0].surge_masses = 2;
  changed.connections[0].contact_law.restitution = 0.1;
  const kin::Mechanism other = kin::compile(changed);
  const dynamics::FlexibleOptions options;
  const std::vector<dynamics::FlexibleParameter> a = dynamics::flexible_parameters(mech, model, {}, options);
  const std::vector<dynamics::FlexibleParameter> b = dynamics::flexible_parameters(other, model, {}, options);
  REQUIRE(!a.empty());
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO(a[i].key);
    CHECK(a[i].key == b[i].key);
    CHECK(a[i].value == b[i].value);
    CHECK(a[i].from_design == b[i].from_design);
  }
}

TEST_CASE("model: data only the flexible model needs is checked when that model is built, not by compile_dynamics",
          "[dynamics][model]") {
  // the compile keeps the flexible-only data unchecked (the rigid model runs without it)
  DesignSpec d = flexible_valve();
  d.connections[0].contact_law.law = ContactLaw::linear;  // no stiffness_N_per_mm
  const kin::Mechanism mech = kin::compile(d);
  const dynamics::Model model = dynamics::compile_dynamics(d, mech);
  CHECK_THROWS_AS(dynamics::flexible_parameters(mech, model, {}, dynamics::FlexibleOptions{}), InputError);
  CHECK_THROWS_WITH(dynamics::flexible_parameters(mech, model, {}, dynamics::FlexibleOptions{}),
                    Catch::Contains("connection 'cam_tappet': law = \"linear\" needs stiffness_N_per_mm"));
}

TEST_CASE("model: compile_dynamics rejects a spec the mechanism was not compiled from", "[dynamics][model]") {
  const DesignSpec spec = flexible_valve();
  const kin::Mechanism mech = kin::compile(spec);
  REQUIRE_NOTHROW(dynamics::compile_dynamics(spec, mech));
  DesignSpec renamed = spec;
  renamed.name = "another_valve";
  CHECK_THROWS_WITH(dynamics::compile_dynamics(renamed, mech),
                    Catch::Contains("the design spec 'another_valve' is not the one mechanism '" + spec.name +
                                    "' was compiled from"));
  // the same name, its nodes in another order
  DesignSpec reordered = spec;
  REQUIRE(reordered.nodes.size() >= 2);
  std::swap(reordered.nodes[0], reordered.nodes[1]);
  CHECK_THROWS_AS(dynamics::compile_dynamics(reordered, mech), InputError);
  // the same name and nodes, one connection fewer
  DesignSpec fewer = spec;
  fewer.connections.pop_back();
  CHECK_THROWS_AS(dynamics::compile_dynamics(fewer, mech), InputError);
}
