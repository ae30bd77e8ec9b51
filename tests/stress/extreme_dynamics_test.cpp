// dynamics at extreme engine speeds and stiffness ratios, on every bundled design with
// dynamics data: each run yields finite forces or stops with a status naming the time and
// cam angle; never a NaN, never a crash.
#include <catch2/catch.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "stress_support.hpp"
#include "support/compare.hpp"

namespace camopt::stress {
namespace {

DesignSpec bundled(const std::string& name) {
  return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml");
}

std::vector<double> default_controls(const kin::Mechanism& mech) {
  std::vector<double> controls;
  for (const auto& c : mech.controls) controls.push_back(c.default_value);
  return controls;
}

// what a compliant run that succeeds must hold: finite forces and deviations, a contact
// that only pushes (its force is max(0, k delta + c delta'), never a pull), and per contact
// events that alternate (it cannot open twice without closing in between), each in the run
void check_compliant_result(const kin::Mechanism& mech, const dynamics::CompliantResult& result) {
  const auto nc = static_cast<std::size_t>(result.connections);
  REQUIRE(nc == mech.connections.size());
  for (const double d : result.deviation) REQUIRE(std::isfinite(d));
  for (std::size_t i = 0; i < result.cam_deg.size(); ++i)
    for (std::size_t c = 0; c < nc; ++c) {
      const double f = result.force[i * nc + c];
      REQUIRE(std::isfinite(f));
      if (mech.connections[c].kind == ConnectionKind::contact) CHECK(f >= 0.0);
    }
  std::map<std::string, bool> open;  // per contact: its last event opened it
  for (const auto& e : result.events) {
    INFO(e.contact << (e.opens ? " opens" : " closes") << " at cam " << e.cam_deg << " deg");
    CHECK(e.cam_deg >= result.cam_deg.front());
    CHECK(e.cam_deg <= result.cam_deg.back());
    const auto it = open.find(e.contact);
    if (it != open.end()) CHECK(it->second != e.opens);
    open[e.contact] = e.opens;
  }
}

}  // namespace

TEST_CASE("rigid dynamics from 1 to 100000 rpm: finite, and the split load cases add up at every speed",
          "[stress][dynamics]") {
  for (const char* name : {"roller_finger_follower", "bucket_tappet", "rocker_arm", "cvvl_swing_cam"}) {
    INFO(name);
    const DesignSpec spec = bundled(name);
    const kin::Mechanism mech = kin::compile(spec);
    const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
    dynamics::RigidSweep sweep;
    const Status st = dynamics::rigid_sweep(mech, model, default_controls(mech), 0, 360, 1, sweep);
    INFO(st.str());
    REQUIRE(st.ok());
    for (const double rpm : {1.0, 1e3, 1e5}) {
      const double w = dynamics::cam_speed_rad_per_s(rpm, model.crank_per_cam);
      for (std::size_t i = 0; i < sweep.points(); ++i) {
        REQUIRE(std::isfinite(sweep.torque_at(i, w)));
        for (int c = 0; c < sweep.connections; ++c) REQUIRE(std::isfinite(sweep.force_at(i, c, w)));
      }
    }
    // a contact's separation speed is where its force first reaches zero: just below it
    // every closed contact still pushes, just above it the named point pulls
    for (int c = 0; c < sweep.connections; ++c) {
      if (mech.connections[static_cast<std::size_t>(c)].kind != ConnectionKind::contact) continue;
      const dynamics::Separation sep = dynamics::separation_speed(sweep, model, c);
      if (!std::isfinite(sep.engine_rpm) || sep.engine_rpm <= 0) continue;
      const double w_at = dynamics::cam_speed_rad_per_s(sep.engine_rpm, model.crank_per_cam);
      double min_below = 1e300;
      for (std::size_t i = 0; i < sweep.points(); ++i)
        if (!sweep.contact[i * static_cast<std::size_t>(sweep.connections) + static_cast<std::size_t>(c)].open)
          min_below = std::min(min_below, sweep.force_at(i, c, w_at * (1 - 1e-6)));
      INFO("contact " << mech.connections[static_cast<std::size_t>(c)].name << " separates at " << sep.engine_rpm
                      << " rpm");
      CHECK(min_below > 0);
      const auto at = static_cast<std::size_t>(std::lround(sep.cam_deg));  // 1 deg grid from 0
      CHECK(sweep.force_at(at, c, w_at * (1 + 1e-6)) < 0);
    }
  }
}

TEST_CASE("compliant contacts at extreme speeds and stiffness ratios: a result or a clear stop",
          "[stress][dynamics]") {
  const DesignSpec spec = bundled("roller_finger_follower");
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  dynamics::RigidSweep rigid;
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0, 360, 1, rigid).ok());
  // each case's outcome (runs: a result; else a stop), measured: every case runs but 30000 rpm
  // with the contacts x 1e3 stiffer, where the pad chatters (8080 contact events) until the
  // step budget stops it at cam 182 deg
  struct Case {
    double rpm, scale;
    bool runs;  // else it stops at the step budget
  };
  for (const Case& k : std::vector<Case>{{10, 1e-3, true},
                                         {10, 1, true},
                                         {10, 1e3, true},
                                         {6000, 1e-3, true},
                                         {6000, 1, true},
                                         {6000, 1e3, true},
                                         {30000, 1e-3, true},
                                         {30000, 1, true},
                                         {30000, 1e3, false},
                                         {1e6, 1e-3, true},
                                         {1e6, 1, true},
                                         {1e6, 1e3, true}}) {
    INFO(k.rpm << " rpm, stiffness x " << k.scale);
    dynamics::CompliantOptions options;
    options.stiffness_scale = k.scale;
    options.max_steps = 20000;
    dynamics::CompliantResult result;
    const Status st = dynamics::run_compliant(mech, model, {}, k.rpm, 0, 360, 1, options, result);
    INFO(st.str());
    CHECK(st.ok() == k.runs);
    if (!st.ok()) {
      // a clear stop: the integrator's reason, the time and the cam angle where it stopped
      CHECK(st.code == StatusCode::integrator_failure);
      CHECK_THAT(st.message, Catch::Contains("steps and events") && Catch::Contains("contact events"));
      CHECK_THAT(st.where, Catch::Contains("cam "));
      CHECK_THAT(st.where, Catch::Contains("t = "));
      continue;
    }
    check_compliant_result(mech, result);
    if (k.rpm <= 10.0 && k.scale >= 1.0) {
      // quasi-static: the compliant contact forces are the rigid ones to within the
      // contact deflection's share (about force / stiffness / lever) of the peak
      const double w = dynamics::cam_speed_rad_per_s(k.rpm, model.crank_per_cam);
      std::vector<double> compliant, rigid_force;
      for (std::size_t i = 0; i < rigid.points(); ++i)
        for (int c = 0; c < rigid.connections; ++c) {
          rigid_force.push_back(rigid.force_at(i, c, w));
          compliant.push_back(
              result.force[i * static_cast<std::size_t>(result.connections) + static_cast<std::size_t>(c)]);
        }
      CHECK_SERIES(camopt::test::compare_series("compliant contact force [N] (point x connection)", compliant,
                                                rigid_force, {.rel = camopt::test::tol::kQuasiStaticForceRel}));
    }
  }
}

TEST_CASE("flexible model at extreme stiffness ratios, speeds and time scales: a result or a clear stop",
          "[stress][dynamics]") {
  // the CVVL (three compliant nodes, three Hertz contacts, a 5-segment valve spring) with its
  // component stiffnesses x 1e-3 .. 1e3, at 10 .. 1e5 rpm, and with the contacts x 1e4 stiffer
  // (a ~100x shorter contact period): finite outputs, or an integrator_failure naming the
  // time, cam angle and rpm within the step budget
  // each case's outcome, measured: a result (stop == nullptr), or a stop whose message says
  // why. 10 rpm needs 11.6k to 45.5k steps (flexible_test.cpp) and the contacts x 1e4 chatter
  // (96 events): both exceed the 3000-step budget; at 20000 rpm the swing's roller is thrown
  // so far off its cam (far past the separation speed) that its linearised gap is off by
  // 0.2 mm, which the model refuses; at 1e5 rpm the run completes
  struct Case {
    double rpm, component_scale, contact_scale;
    const char* stop;  // a part of the stop's message; nullptr: runs
  };
  const char* budget = "steps and events";
  const char* gap = "linearised gap is off by";
  for (const Case& k : std::vector<Case>{{10, 1, 1, budget},
                                         {20000, 1e-3, 1, gap},
                                         {20000, 1e3, 1, gap},
                                         {1e5, 1, 1, nullptr},
                                         {1e5, 1e3, 1, nullptr},
                                         {3000, 1e3, 1e4, budget}}) {
    INFO(k.rpm << " rpm, component stiffness x " << k.component_scale << ", contact stiffness x " << k.contact_scale);
    DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
    for (NodeSpec& n : d.nodes) {
      if (n.torsional_stiffness_Nm_per_rad) *n.torsional_stiffness_Nm_per_rad *= k.component_scale;
      if (n.axial_stiffness_N_per_mm) *n.axial_stiffness_N_per_mm *= k.component_scale;
    }
    const kin::Mechanism mech = kin::compile(d);
    const dynamics::Model model = dynamics::compile_dynamics(d, mech);
    dynamics::FlexibleOptions options;
    options.revolutions = 1;
    options.contact_stiffness_scale = k.contact_scale;
    options.max_steps = 3000;
    dynamics::FlexibleResult result;
    const Status st = dynamics::run_flexible(mech, model, {0.0}, k.rpm, 0, 360, 2, options, result);
    INFO(st.str());
    CHECK(st.ok() == (k.stop == nullptr));
    if (!st.ok()) {
      // a clear stop: the integrator's reason, the time, cam angle and speed where it stopped
      CHECK(st.code == StatusCode::integrator_failure);
      if (k.stop != nullptr) CHECK_THAT(st.message, Catch::Contains(k.stop));
      CHECK_THAT(st.where, Catch::Contains("t = "));
      CHECK_THAT(st.where, Catch::Contains(" deg"));
      CHECK_THAT(st.where, Catch::Contains(" rpm"));
      // stopped within the budget: checked at every event and output point, so at most one
      // output interval (itself capped at max_steps by CVODE) beyond it
      CHECK(result.steps > 0);
      CHECK(result.steps <= 2 * options.max_steps);
      continue;
    }
    for (const auto* v : {&result.lift, &result.force, &result.seat_force, &result.cam_torque, &result.deformation,
                          &result.coil_force_top, &result.energy})
      for (const double x : *v) REQUIRE(std::isfinite(x));
    CHECK(result.steps + static_cast<long>(result.events.size()) <= options.max_steps);
    // one-sided contacts and seats push, never pull; each one's events alternate
    const auto nc = static_cast<std::size_t>(result.connections);
    for (std::size_t i = 0; i < result.cam_deg.size(); ++i) {
      CHECK(result.seat_force[i] >= 0.0);
      for (std::size_t c = 0; c < nc; ++c)
        if (model.contacts[c].is_contact && !model.contacts[c].two_sided) CHECK(result.force[i * nc + c] >= 0.0);
    }
    std::map<std::string, bool> open;
    for (const auto& e : result.events) {
      INFO(e.what << (e.opens ? " opens" : " closes") << " at cam " << e.cam_deg << " deg");
      const auto it = open.find(e.what);
      if (it != open.end()) CHECK(it->second != e.opens);
      open[e.what] = e.opens;
    }
  }
}

}  // namespace camopt::stress
