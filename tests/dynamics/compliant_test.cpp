// mode (b), stiff separable contacts integrated by CVODE: it converges to mode (a) as the
// contact stiffness grows, finds contact opening / closing events above the separation
// speed, and reports an integrator failure with its time and state.
#include <catch2/catch.hpp>

#include "dynamics/dynamics_test_support.hpp"
#include <cmath>
#include <string>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::kin_test;
namespace tol = camopt::test::tol;

namespace {

// the direct-acting valve with a 40 N/mm, 250 N spring
DesignSpec valve() { return dyn_test::direct_valve(40, 250); }


// mode (b)'s contact force against mode (a)'s over the cycle [N] (the error is the largest
// difference; the allowed error is `allowed` [N])
camopt::test::Comparison force_error(const kin::Mechanism& mech, const dynamics::Model& model, double rpm,
                                     double scale, double allowed) {
  dynamics::RigidSweep a;
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0, 360, 1, a).ok());
  dynamics::CompliantOptions opt;
  opt.stiffness_scale = scale;
  opt.relative_tolerance = 1e-8;
  opt.absolute_tolerance = 1e-10;
  dynamics::CompliantResult b;
  const Status st = dynamics::run_compliant(mech, model, {}, rpm, 0, 360, 1, opt, b);
  INFO(st.str());
  REQUIRE(st.ok());
  const double w = dynamics::cam_speed_rad_per_s(rpm, 2.0);
  camopt::test::Series force("compliant contact force x " + std::to_string(scale) + " [N]", "cam [deg]");
  for (std::size_t i = 0; i < a.points(); ++i) force.add(a.cam_deg[i], b.force[i], a.force_at(i, 0, w));
  return force.compare({.abs = allowed});
}

}  // namespace

TEST_CASE("compliant (b): converges to the rigid mode (a) as the contact stiffness grows", "[dynamics][compliant]") {
  const DesignSpec spec = valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  double previous = INFINITY;
  for (const double scale : {0.01, 0.1, 1.0, 10.0}) {
    const camopt::test::Comparison c = force_error(mech, model, 3000, scale, tol::kCompliantStiffForceAbs);
    INFO("stiffness x " << scale << ": worst force error " << c.error << " N at " << c.where);
    CHECK(c.error < 0.15 * previous);  // first order in 1/k: x0.1 per decade
    previous = c.error;
    if (scale == 10.0) CHECK_COMPARISON(c);  // stiffness x10: 0.01 N of a 563 N peak
  }
}

TEST_CASE("compliant (b): separation and impact events above the separation speed", "[dynamics][compliant]") {
  const DesignSpec spec = valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  dynamics::RigidSweep a;
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0, 360, 1, a).ok());
  const double separation = dynamics::separation_speed(a, model, 0).engine_rpm;
  REQUIRE(std::isfinite(separation));
  dynamics::CompliantResult below, above;
  REQUIRE(dynamics::run_compliant(mech, model, {}, 0.8 * separation, 0, 360, 1, {}, below).ok());
  CHECK(below.events.empty());
  REQUIRE(dynamics::run_compliant(mech, model, {}, 1.1 * separation, 0, 360, 1, {}, above).ok());
  std::string events;
  for (const auto& e : above.events)
    events += e.contact + (e.opens ? " opens at " : " closes at ") + std::to_string(e.cam_deg) + "\n";
  INFO("separation " << separation << " rpm; events at 1.1x:\n" << events);
  REQUIRE(above.events.size() >= 2);
  CHECK(above.events.front().contact == "cam_tappet");
  CHECK(above.events.front().opens);
  // the first opening lies where mode (a) first predicts a negative force at that speed
  const double w = dynamics::cam_speed_rad_per_s(1.1 * separation, 2.0);
  double first_negative = -1;
  for (std::size_t i = 0; i < a.points() && first_negative < 0; ++i)
    if (a.force_at(i, 0, w) < 0) first_negative = a.cam_deg[i];
  CHECK_ABS(above.events.front().cam_deg, first_negative, tol::kSeparationEventAbs);
  bool closes = false;
  for (const auto& e : above.events) closes |= !e.opens;
  CHECK(closes);
}

TEST_CASE("compliant (b): an integrator failure names the time and the state", "[dynamics][compliant]") {
  const DesignSpec spec = valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  dynamics::CompliantOptions opt;
  opt.max_steps = 3;
  dynamics::CompliantResult r;
  const Status st = dynamics::run_compliant(mech, model, {}, 6000, 0, 360, 1, opt, r);
  REQUIRE_FALSE(st.ok());
  CHECK(st.code == StatusCode::integrator_failure);
  CHECK_THAT(st.message, Catch::Contains("CV_TOO_MUCH_WORK"));
  CHECK_THAT(st.where, Catch::Contains("t = "));
  CHECK_THAT(st.where, Catch::Contains("cam "));
  CHECK_THAT(st.where, Catch::Contains("state [dq; dq/dt] = ["));
}

TEST_CASE("compliant (b): a contact without materials or width is an input error", "[dynamics][compliant]") {
  DesignSpec d = valve();
  d.connections[0].width_mm.reset();
  const kin::Mechanism mech = kin::compile(d);
  const dynamics::Model model = dynamics::compile_dynamics(d, mech);
  dynamics::CompliantResult r;
  CHECK_THROWS_WITH(dynamics::run_compliant(mech, model, {}, 3000, 0, 360, 1, {}, r),
                    Catch::Contains("connection 'cam_tappet': the compliant contact model needs materials and width_mm"));
}

TEST_CASE("compliant (b): a four-bar's link force approaches mode (a) as the link stiffens", "[dynamics][compliant]") {
  // designs/four_bar.toml geometry with a massive rocker (no contacts: links are bilateral springs)
  DesignSpec d = design("four_bar", "crank", "rocker");
  d.driver.crank_per_cam = 1;
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", {60, 0})};
  d.nodes[1].mass_kg = 0.06;
  d.nodes[1].cg_mm = Vec2{68.3333, 23.5702};
  d.nodes[1].inertia_kg_mm2 = 12.5;
  d.connections = {link("coupler", "crank", {17.0370, 10.4757}, "rocker", {76.6667, 47.1405})};
  d.connections[0].length_mm = 70;
  const kin::Mechanism mech = kin::compile(d);
  const dynamics::Model model = dynamics::compile_dynamics(d, mech);
  dynamics::RigidSweep a;
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0, 360, 1, a).ok());
  const double rpm = 3000, w = dynamics::cam_speed_rad_per_s(rpm, 1.0);
  double previous = INFINITY;
  for (const double k : {1e4, 1e6}) {
    dynamics::CompliantOptions opt;  // tight: the model error is measured, not the integrator's
    opt.link_stiffness = k;
    opt.relative_tolerance = 1e-9;
    opt.absolute_tolerance = 1e-12;
    dynamics::CompliantResult b;
    const Status st = dynamics::run_compliant(mech, model, {}, rpm, 0, 360, 1, opt, b);
    INFO(st.str());
    REQUIRE(st.ok());
    camopt::test::Series force("link force, stiffness " + std::to_string(k) + " N/mm [N]", "cam [deg]");
    for (std::size_t i = 0; i < a.points(); ++i) force.add(a.cam_deg[i], b.force[i], a.force_at(i, 0, w));
    const camopt::test::Comparison c = force.compare({.rel = tol::kStiffLinkForceRel});
    INFO("link stiffness " << k << " N/mm: worst force error " << c.error << " N at " << c.where);
    CHECK(c.error < 0.2 * previous);
    previous = c.error;
    if (k == 1e6) CHECK_COMPARISON(c);  // of the peak force
  }
}

namespace {

// `options` with one field changed fails validate() with a message holding `text`
template <class Set>
void check_option_rule(Set&& set, const std::string& text) {
  dynamics::CompliantOptions options;
  set(options);
  INFO(text);
  CHECK_THROWS_AS(options.validate(), InputError);
  CHECK_THROWS_WITH(options.validate(), Catch::Contains(text));
}

}  // namespace

TEST_CASE("compliant (b) options: the defaults are valid", "[dynamics][compliant][input]") {
  CHECK_NOTHROW(dynamics::CompliantOptions{}.validate());
}

TEST_CASE("compliant (b) options: contact stiffness and damping", "[dynamics][compliant][input]") {
  check_option_rule([](auto& o) { o.stiffness_scale = 0; }, "CompliantOptions::stiffness_scale = 0 must be > 0");
  check_option_rule([](auto& o) { o.damping_ratio = -0.05; }, "CompliantOptions::damping_ratio = -0.05 must be >= 0");
  check_option_rule([](auto& o) { o.link_stiffness = -1; }, "CompliantOptions::link_stiffness = -1 must be > 0");
  check_option_rule([](auto& o) { o.reference_force = -1; }, "CompliantOptions::reference_force = -1 must be >= 0");
}

TEST_CASE("compliant (b) options: path table, tolerances and step budget", "[dynamics][compliant][input]") {
  check_option_rule([](auto& o) { o.table_step_deg = 0; }, "CompliantOptions::table_step_deg = 0 must be > 0");
  check_option_rule([](auto& o) { o.relative_tolerance = 0; }, "CompliantOptions::relative_tolerance = 0 must be > 0");
  check_option_rule([](auto& o) { o.absolute_tolerance = 0; }, "CompliantOptions::absolute_tolerance = 0 must be > 0");
  check_option_rule([](auto& o) { o.max_steps = 0; }, "CompliantOptions::max_steps = 0 must be >= 1");
}

TEST_CASE("compliant (b): bad arguments are input errors naming the argument and the rule",
          "[dynamics][compliant][input]") {
  const DesignSpec spec = valve();
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  const dynamics::CompliantOptions ok;
  dynamics::CompliantResult r;
  CHECK_THROWS_AS(dynamics::run_compliant(mech, model, {}, 6000, 0, 360, 0, ok, r), InputError);
  CHECK_THROWS_WITH(dynamics::run_compliant(mech, model, {}, 6000, 0, 360, 0, ok, r),
                    Catch::Contains("run_compliant: step_deg = 0 must be > 0 (rule: step_deg > 0)"));
  CHECK_THROWS_WITH(dynamics::run_compliant(mech, model, {}, 6000, 90, 90, 1, ok, r),
                    Catch::Contains("run_compliant: stop_deg = 90 must be > start_deg = 90"));
  CHECK_THROWS_WITH(dynamics::run_compliant(mech, model, {}, 0, 0, 360, 1, ok, r),
                    Catch::Contains("run_compliant: engine_rpm_value = 0 must be > 0"));
  dynamics::CompliantOptions bad;
  bad.stiffness_scale = -1;
  CHECK_THROWS_WITH(dynamics::run_compliant(mech, model, {}, 6000, 0, 360, 1, bad, r),
                    Catch::Contains("CompliantOptions::stiffness_scale = -1"));
}
