// flexible model against independent formulations: the exact piecewise-analytic single-mass
// valve (linear contacts, lash, seat, damped spring: tests/oracles/valve_oracle), a multi-mass
// spring against exact modal superposition (tests/oracles/spring_chain_oracle), the power
// balance with every contact law and damper, starting from rest, and the reported revolution.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/design_file.hpp"
#include "dynamics/dynamics_test_support.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "oracles/spring_chain_oracle.hpp"
#include "oracles/valve_oracle.hpp"
#include "support/compare.hpp"

using namespace camopt;
using camopt::dyn_test::direct_valve;
using camopt::pi;
using camopt::test::Series;
namespace tol = camopt::test::tol;

namespace {

constexpr double kEccentricity = 4.0;  // [mm] direct_valve's disc: lift e (1 - cos theta)

// the direct-acting valve of the exact solution: 50 g, spring 40 N/mm and 250 N with 20 N s/m,
// 0.15 mm lash, linear cam contact 2e5 N/mm with 500 N s/m, linear seat 5e5 N/mm with 1000 N s/m
DesignSpec linear_valve() {
  DesignSpec d = direct_valve(40, 250);
  d.nodes[1].mass_kg = 0.05;
  d.springs[0].damping_N_s_per_m = 20;
  ConnectionSpec& c = d.connections[0];
  c.lash_mm = 0.15;
  c.contact_law.law = ContactLaw::linear;
  c.contact_law.stiffness_N_per_mm = 2e5;
  c.contact_law.damping_N_s_per_m = 500;
  SeatSpec& seat = d.nodes[1].seat;
  seat.law.law = ContactLaw::linear;
  seat.law.stiffness_N_per_mm = 5e5;
  seat.law.damping_N_s_per_m = 1000;
  return d;
}

oracles::ValveParams linear_valve_oracle(double cam_rad_per_s) {
  oracles::ValveParams p;
  p.mass = 0.05;
  p.eccentricity = kEccentricity * 1e-3;
  p.cam_speed = cam_rad_per_s;
  p.lash = 0.15e-3;
  p.preload = 250;
  p.spring_rate = 40e3;
  p.spring_damping = 20;
  p.cam_stiffness = 2e8;
  p.cam_damping = 500;
  p.seat_stiffness = 5e8;
  p.seat_damping = 1000;
  return p;
}

struct Run {
  kin::Mechanism mech;
  dynamics::Model model;
  dynamics::FlexibleResult res;
  Status status;
  explicit Run(const DesignSpec& d) : mech(kin::compile(d)), model(dynamics::compile_dynamics(d, mech)) {}
  Run& go(double rpm, double start, double stop, double step, const dynamics::FlexibleOptions& opt) {
    status = dynamics::run_flexible(mech, model, {}, rpm, start, stop, step, opt, res);
    return *this;
  }
};

}  // namespace

TEST_CASE("flexible: a single-mass valve with linear contacts, lash and a damped spring equals the exact solution",
          "[dynamics][flexible]") {
  // 4700 cam rpm: the valve skips off the cam on the opening flank and bounces five times on
  // its seat, the last flight 12 us long (the oracle's own tests)
  const double engine_rpm = 9400;
  Run run(linear_valve());
  dynamics::FlexibleOptions opt;  // default tolerances
  opt.revolutions = 1;
  run.go(engine_rpm, 0, 359.9, 0.1, opt);
  INFO(run.status.str());
  REQUIRE(run.status.ok());
  const dynamics::FlexibleResult& r = run.res;
  const double w = dynamics::cam_speed_rad_per_s(engine_rpm, 2.0);
  // the kinematic path is the eccentric's lift less the lash (to the Catmull-Rom
  // interpolation of its 0.25 deg table: 5e-9 mm measured)
  Series path("kinematic lift [mm]", "cam [deg]");
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
    const double th = r.cam_deg[i] * kin_test::deg;
    path.add(r.cam_deg[i], r.lift_kinematic[i], std::max(0.0, kEccentricity * (1 - std::cos(th)) - 0.15));
  }
  CHECK_SERIES(path.compare({.abs = tol::kPathTableAbs}));
  // the exact solution from camopt's start (the valve on its seat, at rest)
  const oracles::ValveParams p = linear_valve_oracle(w);
  const double n = r.layout.size();
  const oracles::ValveTrajectory exact =
      oracles::integrate_valve(p, {0.0, r.initial_state[0] * 1e-3, r.initial_state[n] * 1e-3}, 2 * pi / w);
  // every event, in order, at the same cam angle (0.01 deg) and speed
  std::vector<oracles::ValveEvent> expected;
  for (const auto& e : exact.events)
    if (e.t > 1e-9) expected.push_back(e);
  REQUIRE(r.events.size() == expected.size());
  Series angle("event cam angle [deg]", "event"), speed("seat impact speed [m/s]", "event");
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const auto& e = expected[k];
    const auto& c = r.events[k];
    INFO("event " << k << ": camopt " << c.what << (c.opens ? " opens" : " closes") << " at " << c.cam_deg
                  << " deg; exact " << (e.contact == oracles::ValveContact::cam ? "cam" : "seat")
                  << (e.engages ? " closes" : " opens") << " at " << e.t * w / kin_test::deg << " deg");
    CHECK(c.what == (e.contact == oracles::ValveContact::cam ? "cam_tappet" : "tappet seat"));
    CHECK(c.opens == !e.engages);
    angle.add(static_cast<double>(k), c.cam_deg, e.t * w / kin_test::deg);
    if (e.contact == oracles::ValveContact::seat) speed.add(static_cast<double>(k), c.speed_m_per_s, std::abs(e.v));
  }
  const camopt::test::Comparison angles = angle.compare({.abs = tol::kValveEventAngleAbs}),
                                 speeds = speed.compare({.abs = tol::kSeatSpeedAbs});
  WARN(angles.describe() << "\n" << speeds.describe());
  CHECK_COMPARISON(angles);
  CHECK_COMPARISON(speeds);
  // the seating velocity and a bounce shorter than 0.1 ms
  double seating = -1, shortest = 1e9, opened = -1;
  for (const auto& e : r.events) {
    if (e.what != "tappet seat") continue;
    if (!e.opens && seating < 0) seating = e.speed_m_per_s;
    if (e.opens) opened = e.cam_deg;
    else if (opened >= 0) shortest = std::min(shortest, (e.cam_deg - opened) * kin_test::deg / w), opened = -1;
  }
  CHECK_ABS(seating, exact.seating_velocity(0, 2 * pi / w), tol::kSeatSpeedAbs);
  CHECK(shortest < 1e-4);
  // the lift at every output point [mm]
  Series lift("lift [mm]", "cam [deg]");
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i)
    lift.add(r.cam_deg[i], r.lift[i], 1e3 * exact.at(r.cam_deg[i] * kin_test::deg / w).x);
  const camopt::test::Comparison lifts = lift.compare({.abs = tol::kValveLiftExactAbs});
  WARN(lifts.describe());
  CHECK_COMPARISON(lifts);
}

TEST_CASE("flexible: a multi-mass spring driven from rest equals exact modal superposition", "[dynamics][flexible]") {
  // the retainer follows the eccentric through a stiff, critically damped linear contact
  // (1e8 N/mm: 4e-6 mm under 400 N, 1.4e-3 N of top-segment force); no seat, no coil damping
  constexpr int kMasses = 8;
  DesignSpec d = direct_valve(40, 250);
  d.nodes[1].mass_kg = 0.02;
  d.nodes[1].seat.enabled = false;
  d.springs[0].mass_kg = 0.045;
  d.springs[0].surge_masses = kMasses;
  d.springs[0].coil_damping_ratio = 0.0;
  ConnectionSpec& c = d.connections[0];
  c.contact_law.law = ContactLaw::linear;
  c.contact_law.stiffness_N_per_mm = 1e8;
  c.contact_law.damping_N_s_per_m = 2 * std::sqrt(1e11 * 0.02);
  const double engine_rpm = 6000;
  Run run(d);
  dynamics::FlexibleOptions opt;
  opt.revolutions = 1;
  // 3e-4 N at these; 0.003 N at rtol 1e-6 with atol 1e-12, 0.04 N at the defaults
  opt.relative_tolerance = 1e-8;
  opt.absolute_tolerance = 1e-10;
  run.go(engine_rpm, 0, 359, 1, opt);
  INFO(run.status.str());
  REQUIRE(run.status.ok());
  const dynamics::FlexibleResult& r = run.res;
  const double w = dynamics::cam_speed_rad_per_s(engine_rpm, 2.0);
  oracles::SpringChain chain;
  chain.rate = 40e3;
  chain.mass = 0.045;
  chain.masses = kMasses;
  chain.preload = 250;
  chain.eccentricity = kEccentricity * 1e-3;
  chain.cam_speed = w;
  const oracles::SpringChainOracle exact(chain);
  Series top("coil force at the top [N]", "cam [deg]"), base("coil force at the base [N]", "cam [deg]");
  double surge = 0;
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
    const double t = r.cam_deg[i] * kin_test::deg / w;
    top.add(r.cam_deg[i], r.coil_force_top[i], exact.top_force(t));
    base.add(r.cam_deg[i], r.coil_force_base[i], exact.base_force(t));
    surge = std::max(surge, std::abs(exact.base_force(t) - (250 + 40 * r.lift_kinematic[i])));
  }
  INFO("surge amplitude " << surge << " N");
  CHECK(surge > 1.0);  // the surge is there to be matched
  CHECK_SERIES(top.compare({.abs = tol::kCoilForceAbs}));
  CHECK_SERIES(base.compare({.abs = tol::kCoilForceAbs}));
}

TEST_CASE("flexible: power balance with every contact law and damper, lash and seat events", "[dynamics][flexible]") {
  struct Case {
    const char* name;
    ContactLaw law;
    ContactDampingLaw damping;
  };
  for (const Case& k : {Case{"hertz, hunt-crossley", ContactLaw::hertz, ContactDampingLaw::hunt_crossley},
                        Case{"hertz, linear damping", ContactLaw::hertz, ContactDampingLaw::linear},
                        Case{"linear", ContactLaw::linear, ContactDampingLaw::hunt_crossley}}) {
    DesignSpec d = direct_valve(40, 250);
    d.springs[0].mass_kg = 0.045;
    d.springs[0].surge_masses = 6;
    d.springs[0].damping_N_s_per_m = 30;
    d.springs[0].coil_damping_ratio = 0.02;
    d.nodes[1].axial_stiffness_N_per_mm = 60000;
    d.nodes[1].damping_N_s_per_m = 200;
    ConnectionSpec& c = d.connections[0];
    c.lash_mm = 0.1;
    c.friction_coefficient = 0.08;
    c.contact_law.law = k.law;
    c.contact_law.damping_law = k.damping;
    c.contact_law.damping_N_s_per_m = 300;
    if (k.law == ContactLaw::linear) c.contact_law.stiffness_N_per_mm = 3e5;
    d.nodes[1].seat.law = c.contact_law;
    Run run(d);
    dynamics::FlexibleOptions opt;
    opt.revolutions = 1;
    opt.relative_tolerance = 1e-9;
    opt.absolute_tolerance = 1e-11;
    run.go(8000, 0, 359, 1, opt);
    INFO(k.name << ": " << run.status.str());
    REQUIRE(run.status.ok());
    const dynamics::FlexibleResult& r = run.res;
    int seat_events = 0;
    for (const auto& e : r.events) seat_events += e.what == "tappet seat";
    INFO(k.name << ": viscous loss " << r.viscous_loss.back() << " N mm, seat events " << seat_events);
    CHECK(seat_events >= 2);
    CHECK(r.viscous_loss.back() - r.viscous_loss.front() > 1.0);
    CHECK_COMPARISON(dyn_test::power_balance(r, tol::kPowerBalanceRel));
  }
}

TEST_CASE("flexible: started from rest, every body is still at the start and every revolution is reported",
          "[dynamics][flexible]") {
  DesignSpec d = direct_valve(40, 250);
  d.connections[0].lash_mm = 0.1;
  Run run(d);
  dynamics::FlexibleOptions opt;
  opt.revolutions = 2;
  opt.start_at_rest = true;
  run.go(3000, 0, 359, 1, opt);
  INFO(run.status.str());
  REQUIRE(run.status.ok());
  const dynamics::FlexibleResult& r = run.res;
  REQUIRE(r.cam_deg.size() == 720);
  CHECK_ABS(r.cam_deg.back(), 719, tol::kOutputAngleAbs);
  CHECK_ABS(r.velocity[0], 0.0, tol::kAtRestAbs);
  CHECK(r.lift[0] < 0.0);  // on its seat, pressed in by the preload
  for (std::size_t i = 1; i < r.cam_deg.size(); ++i) REQUIRE(r.cam_deg[i] > r.cam_deg[i - 1]);
  // the valve opens to its peak (8 mm less the 0.1 mm lash) in each revolution
  for (int rev = 0; rev < 2; ++rev) {
    const auto first = r.lift.begin() + rev * 360;
    CHECK_ABS(*std::max_element(first, first + 360), 7.9, tol::kPeakLiftDeflectionAbs);
  }
}

TEST_CASE("flexible: events and their angles lie inside the reported revolution", "[dynamics][flexible]") {
  DesignSpec d = direct_valve(40, 250);
  d.connections[0].lash_mm = 0.1;
  Run run(d);
  dynamics::FlexibleOptions opt;
  opt.revolutions = 10;
  opt.relative_tolerance = 1e-8;
  opt.absolute_tolerance = 1e-9;
  run.go(3000, 0, 359, 1, opt);
  INFO(run.status.str());
  REQUIRE(run.status.ok());
  REQUIRE(!run.res.events.empty());
  for (const auto& e : run.res.events) {
    INFO(e.what << " at " << e.cam_deg);
    CHECK(e.cam_deg >= 0.0);
    CHECK(e.cam_deg <= 359.0);
  }
  for (double k : run.res.kink_deg) CHECK((k >= 0.0 && k < 360.0));
  CHECK(run.res.kink_deg.size() == 2);  // the lash closes and opens once
}

TEST_CASE("flexible: no bundled valve passes through its seat beyond the seat's elastic approach, 1000-9000 rpm",
          "[dynamics][flexible][designs]") {
  // the seats' default law: hertz line contact of length pi 29 mm, crown radius 5 mm, steel on
  // steel at 45 deg (axial approach = normal approach(F / cos) / cos), hunt-crossley damping
  // with restitution 0.8 at 0.5 m/s (alpha = 0.4 s/m): F = F_e (1 + 1.5 alpha rate)
  const double e_star = 210e3 / (2 * (1 - 0.3 * 0.3)), ca = std::cos(pi / 4), alpha = 0.4e-3;  // [s/mm]
  auto seat_approach = [&](double axial_force) {
    if (axial_force <= 0) return 0.0;
    const double a = axial_force / ca / (pi * pi * 29 * e_star);
    return a * (std::log(4 * 5 / a) - 1) / ca;
  };
  int results = 0;
  for (const char* name : {"bucket_tappet", "cvvl_swing_cam", "eccentric_flat_follower", "eccentric_offset_roller",
                           "offset_slider_crank", "rocker_arm", "roller_finger_follower", "vvld", "valvetronic"}) {
    const DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml");
    Run run(d);
    std::vector<double> controls;
    for (const ControlSpec& c : d.controls) controls.push_back(c.default_value);
    for (double rpm : {1000.0, 5000.0, 9000.0}) {
      INFO(name << " at " << rpm << " rpm");
      dynamics::FlexibleOptions opt;
      run.status = dynamics::run_flexible(run.mech, run.model, controls, rpm, 0, 359.75, 0.25, opt, run.res);
      INFO(run.status.str());
      if (!run.status.ok()) {
        // the one stop allowed: bodies so far off their path that the contacts' linearised gap fails
        CHECK(run.status.str().find("its linearised gap is off by") != std::string::npos);
        continue;
      }
      ++results;
      const dynamics::FlexibleResult& r = run.res;
      REQUIRE(r.seat_names.size() == 1);
      double deepest = 0, loaded_depth = 0, max_seat = 0;
      for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
        const double pen = -r.lift[i];
        deepest = std::max(deepest, pen);
        max_seat = std::max(max_seat, r.seat_force[i]);
        if (!(r.seat_force[i] > 0)) continue;
        // where the seat carries load, the valve is in by the elastic approach of its load
        const double elastic = r.seat_force[i] / (1 + 1.5 * alpha * ca * -r.velocity[i]);  // normal rate
        INFO("cam " << r.cam_deg[i] << ": in by " << pen << " mm, elastic approach " << seat_approach(elastic));
        REQUIRE(pen <= seat_approach(elastic) * (1 + 1e-6) + 1e-9);
        loaded_depth = std::max(loaded_depth, seat_approach(elastic));
      }
      INFO("deepest " << deepest << " mm; largest elastic approach where loaded " << loaded_depth
                      << " mm; largest seat force " << max_seat << " N");
      CHECK(max_seat > 0.0);
      CHECK(deepest <= 1.5 * loaded_depth + 1e-9);
    }
  }
  CHECK(results >= 25);
}
