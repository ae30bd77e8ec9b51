// mode (a) rigid dynamics against closed forms and independent Newton-Euler balances:
// a direct-acting valve (F = m a + k (x + x0) + gas), a four-bar and a slider-crank with
// massive output links (force balances written here from the oracles' motion), the
// power balance of the CVVL (drive power = d(kinetic + spring energy)/dt + friction
// losses), exact separation speeds, and Hertz line contact against a hand computation.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "camopt/core/units.hpp"
#include "dynamics/dynamics_test_support.hpp"
#include <cmath>
#include <string>
#include <vector>

#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/io/design_file.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::kin_test;
using camopt::dyn_test::steel;
using camopt::oracles::wrap_angle;
namespace tol = camopt::test::tol;

namespace {

constexpr double kRpm = 6000.0;

Vector2d polar(double r, double a) { return {r * std::cos(a), r * std::sin(a)}; }
double cross2(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }


// ---- direct-acting valve: eccentric disc + flat tappet (oracle (a)) ----
struct ValveCase {
  double R = 18, e = 4, phase = -90 * deg;  // lift starts from the base
  double mass = 0.06, spring_mass = 0.03, rate = 40, preload = 250, friction = 0.0;
  bool gas = false;
};

// gas force table [crank deg, N] used by the valve tests: a triangle over the first 100 crank deg
const std::vector<double> kGasCrank{0, 40, 100}, kGasForce{0, 150, 0};
double gas_at(double crank_deg) {
  const double x = std::fmod(crank_deg, 720.0);
  if (x <= 40) return 150 * x / 40;
  if (x <= 100) return 150 * (100 - x) / 60;
  return 0;
}

DesignSpec valve_design(const ValveCase& c, double face_height) {
  DesignSpec d = design("direct_valve", "cam", "tappet");
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, face_height}, {0, 1})};
  d.nodes[1].mass_kg = c.mass;
  d.profiles = {eccentric_profile("disc", c.R, c.e)};
  ConnectionSpec k = contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, c.phase / deg),
                             line_surface("tappet", {0, face_height}, {0, -1}));
  k.material_a = k.material_b = "steel";
  k.width_mm = 8;
  if (c.friction > 0) k.friction_coefficient = c.friction;
  d.connections = {k};
  d.materials = {steel()};
  SpringSpec s;
  s.name = "valve_spring";
  s.node = "tappet";
  s.rate_N_per_mm = c.rate;
  s.preload_N = c.preload;
  s.mass_kg = c.spring_mass;
  d.springs = {s};
  if (c.gas) {
    GasForceSpec g;
    g.node = "tappet";
    g.crank_angle_deg = kGasCrank;
    g.force_N = kGasForce;
    d.gas_forces = {g};
  }
  return d;
}

struct Compiled {
  kin::Mechanism mech;
  dynamics::Model model;
  explicit Compiled(const DesignSpec& d) : mech(kin::compile(d)), model(dynamics::compile_dynamics(d, mech)) {}
};

dynamics::RigidSweep sweep_of(const Compiled& c, double step = 0.5, std::vector<double> controls = {}) {
  if (controls.empty())
    for (const auto& ctl : c.mech.controls) controls.push_back(ctl.default_value);
  dynamics::RigidSweep s;
  const Status st = dynamics::rigid_sweep(c.mech, c.model, controls, 0.0, 360.0, step, s);
  INFO(st.str());
  REQUIRE(st.ok());
  return s;
}

DesignSpec load(const std::string& name) { return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name); }

}  // namespace

TEST_CASE("rigid (a): direct-acting valve against F = m a + k (x + x0) + gas, torque F s' + mu F y",
          "[dynamics][rigid]") {
  for (const bool gas : {false, true})
    for (const double mu : {0.0, 0.1}) {
      ValveCase c;
      c.gas = gas;
      c.friction = mu;
      const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
      const Compiled m(valve_design(c, o.face_height(0)[0]));
      const auto s = sweep_of(m);
      const double w = dynamics::cam_speed_rad_per_s(kRpm, 2.0);
      const double m_eff = c.mass + c.spring_mass / 3.0;  // [kg]
      ScalarCompare force("contact force gas " + std::to_string(gas) + " mu " + std::to_string(mu)),
          torque("cam torque"), guide("guide reaction x"), axial("guide reaction y");
      for (std::size_t i = 0; i < s.points(); ++i) {
        const double t = s.cam_deg[i] * deg;
        const auto y = o.face_height(t);
        const double x = y[0] - o.face_height(0)[0];
        const double f = 1e-3 * m_eff * w * w * y[2] + c.rate * x + c.preload + (gas ? gas_at(2 * s.cam_deg[i]) : 0.0);
        force.add(t, s.force_at(i, 0, w), f);
        torque.add(t, s.torque_at(i, w), f * y[1] + mu * f * y[0]);
        guide.add(t, s.reaction_at(i, 2, 0, w), mu * f);
        axial.add(t, s.reaction_at(i, 2, 1, w), 0.0);
      }
      CHECK_SERIES(force.compare(tol::kRigidForceRel));
      CHECK_SERIES(torque.compare(tol::kRigidForceRel));
      CHECK_SERIES(guide.compare(tol::kRigidForceRel));
      CHECK_SERIES(axial.compare(0.0, tol::kZeroReactionAbs));
    }
}

TEST_CASE("rigid (a): progressive spring table, piecewise linear and extrapolated", "[dynamics][rigid]") {
  ValveCase c;
  const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
  DesignSpec d = valve_design(c, o.face_height(0)[0]);
  d.springs[0].rate_N_per_mm = 0;
  d.springs[0].preload_N = 0;
  d.springs[0].table_displacement_mm = {0, 2, 5};  // lift reaches 8 mm: extrapolated above 5
  d.springs[0].table_force_N = {200, 260, 400};
  const Compiled m(d);
  const auto s = sweep_of(m);
  const double w = dynamics::cam_speed_rad_per_s(kRpm, 2.0);
  ScalarCompare force("contact force, progressive spring");
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double t = s.cam_deg[i] * deg;
    const auto y = o.face_height(t);
    const double x = y[0] - o.face_height(0)[0];
    const double spring = x <= 2 ? 200 + 30 * x : 260 + (400 - 260) / 3.0 * (x - 2);
    force.add(t, s.force_at(i, 0, w), 1e-3 * (c.mass + c.spring_mass / 3) * w * w * y[2] + spring);
  }
  CHECK_SERIES(force.compare(tol::kRigidForceRel));
}

TEST_CASE("rigid (a): separation speed is exact from the rpm^2 split", "[dynamics][rigid]") {
  ValveCase c;
  c.gas = true;
  const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
  const Compiled m(valve_design(c, o.face_height(0)[0]));
  const auto s = sweep_of(m);
  // closed form: F = m w^2 y'' + k x + F0 + gas = 0 -> w^2 = -(k x + F0 + gas) / (m y'')
  const double m_eff = c.mass + c.spring_mass / 3.0;
  double w_min = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    const auto y = o.face_height(s.cam_deg[i] * deg);
    const double rest = c.rate * (y[0] - o.face_height(0)[0]) + c.preload + gas_at(2 * s.cam_deg[i]);
    if (y[2] < 0) w_min = std::min(w_min, std::sqrt(-rest / (1e-3 * m_eff * y[2])));
  }
  const auto sep = dynamics::separation_speed(s, m.model, 0);
  const double rpm = dynamics::engine_rpm(w_min, 2.0);
  CHECK_REL(sep.engine_rpm, rpm, tol::kSeparationRpmRel);
  // the force is positive everywhere just below it and reaches zero at it
  const double w = dynamics::cam_speed_rad_per_s(sep.engine_rpm, 2.0);
  double min_below = INFINITY, min_at = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    min_below = std::min(min_below, s.force_at(i, 0, w * (1 - 1e-6)));
    min_at = std::min(min_at, s.force_at(i, 0, w));
  }
  CHECK(min_below > 0.0);
  CHECK_ABS(min_at, 0.0, tol::kSeparationForceRel * c.preload);
  // spring margin: one spring loading one contact fully, so the margin is the contact force
  // (the spring load that could go before the tappet lifts off); zero at the separation speed
  double min_margin = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double margin = dynamics::spring_margin(s, m.model, i, 0, w);
    CHECK_NEAR(margin, s.force_at(i, 0, w), tol::kSeparationForceRel * c.preload, tol::kSpringMarginRel);
    min_margin = std::min(min_margin, margin);
  }
  CHECK_ABS(min_margin, 0.0, tol::kSeparationForceRel * c.preload);
  // a quantity at two speeds is A + B w^2 exactly
  const std::size_t i = s.points() / 3;
  const double w1 = 100, w2 = 400, w3 = 250;
  const double f1 = s.force_at(i, 0, w1), f2 = s.force_at(i, 0, w2);
  const double b = (f2 - f1) / (w2 * w2 - w1 * w1);
  CHECK_REL(s.force_at(i, 0, w3), f1 + b * (w3 * w3 - w1 * w1), tol::kQuadraticInSpeedRel);
}

TEST_CASE("rigid (a): a damped valve spring: F = m a + k (x + x0) + c v, separation at the quadratic's root",
          "[dynamics][rigid]") {
  ValveCase c;
  c.gas = true;
  const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
  DesignSpec d = valve_design(c, o.face_height(0)[0]);
  const double damping = 400.0;  // [N s/m]
  d.springs[0].damping_N_s_per_m = damping;
  const Compiled m(d);
  const auto s = sweep_of(m);
  const double m_eff = 1e-3 * (c.mass + c.spring_mass / 3.0), cd = damping * 1e-3;  // [N per mm/s^2], [N s/mm]
  // the force at 6000 rpm, and the separation speed: per point the smallest positive root w of
  // m y'' w^2 + c y' w + (k x + F0 + gas) = 0, written here from the quadratic formula
  const double w6 = dynamics::cam_speed_rad_per_s(kRpm, 2.0);
  ScalarCompare force("damped contact force");
  double w_min = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double t = s.cam_deg[i] * deg;
    const auto y = o.face_height(t);
    const double rest = c.rate * (y[0] - o.face_height(0)[0]) + c.preload + gas_at(2 * s.cam_deg[i]);
    force.add(t, s.force_at(i, 0, w6), m_eff * w6 * w6 * y[2] + cd * w6 * y[1] + rest);
    const double qa = m_eff * y[2], qb = cd * y[1], disc = qb * qb - 4 * qa * rest;
    if (std::abs(qa) < 1e-15 || disc < 0) continue;
    for (double root : {(-qb + std::sqrt(disc)) / (2 * qa), (-qb - std::sqrt(disc)) / (2 * qa)})
      if (root > 0) w_min = std::min(w_min, root);
  }
  CHECK_SERIES(force.compare(tol::kRigidForceRel));
  const auto sep = dynamics::separation_speed(s, m.model, 0);
  CHECK_REL(sep.engine_rpm, dynamics::engine_rpm(w_min, 2.0), tol::kSeparationRpmRel);
  // the undamped separation speed differs: the damper matters here
  ValveCase u = c;
  const Compiled mu(valve_design(u, o.face_height(0)[0]));
  const double undamped = dynamics::separation_speed(sweep_of(mu), mu.model, 0).engine_rpm;
  INFO("damped " << sep.engine_rpm << " rpm, undamped " << undamped << " rpm");
  CHECK(std::abs(sep.engine_rpm - undamped) > 10.0);
  // the force is positive just below it and reaches zero at it
  const double w = dynamics::cam_speed_rad_per_s(sep.engine_rpm, 2.0);
  double min_below = INFINITY, min_at = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    min_below = std::min(min_below, s.force_at(i, 0, w * (1 - 1e-6)));
    min_at = std::min(min_at, s.force_at(i, 0, w));
  }
  CHECK(min_below > 0.0);
  CHECK_ABS(min_at, 0.0, tol::kSeparationForceRel * c.preload);
}

TEST_CASE("rigid (a): the separation speed refined between grid points is the exact least over the cycle",
          "[dynamics][rigid]") {
  // the eccentric's greatest deceleration, where the force first reaches zero, falls 0.25 deg
  // before the grid point at 180 deg: face height y = R + e sin(theta + phase), y'' = -e at
  // theta* = 90 deg - phase, and there m y'' w^2 + k x + F0 = 0 gives the exact least
  //   w*^2 = (k e (1 - sin phase) + F0) / (m e)
  // (no smaller root elsewhere: with u = sin(theta + phase) in (0, 1] the root is
  // w^2 = k / m + (F0 - k e sin phase) / (m e u), least at u = 1)
  ValveCase c;
  c.phase = (-90 + 0.25) * deg;
  const Compiled m(valve_design(c, c.R + c.e * std::sin(c.phase)));
  const double m_eff = 1e-3 * (c.mass + c.spring_mass / 3.0);  // [N per mm/s^2]
  const double exact_w = std::sqrt((c.rate * c.e * (1 - std::sin(c.phase)) + c.preload) / (m_eff * c.e));
  const double exact_rpm = dynamics::engine_rpm(exact_w, 2.0), exact_deg = 90 - c.phase / deg;
  for (const double step : {1.0, 0.5, 5.0}) {
    INFO("step " << step << " deg");
    const auto s = sweep_of(m, step);
    dynamics::Separation refined;
    const Status st = dynamics::refined_separation_speed(m.mech, m.model, s, 0, refined);
    INFO(st.str());
    REQUIRE(st.ok());
    const dynamics::Separation grid = dynamics::separation_speed(s, m.model, 0);
    INFO("exact " << exact_rpm << " rpm at " << exact_deg << " deg; refined " << refined.engine_rpm << " at "
                  << refined.cam_deg << "; grid " << grid.engine_rpm << " at " << grid.cam_deg);
    CHECK_REL(refined.engine_rpm, exact_rpm, tol::kSeparationRpmRel);
    // the angle of a quadratic minimum is found to the square root of the value's precision
    CHECK_ABS(refined.cam_deg, exact_deg, tol::kSeparationRefinedAngleAbs);
    // the grid's least misses it by far more than the tolerance
    CHECK(std::abs(grid.engine_rpm - exact_rpm) > 1e3 * tol::kSeparationRpmRel * exact_rpm);
  }
}

TEST_CASE("rigid (a): separation speed with the gas force acting where the valve decelerates",
          "[dynamics][rigid]") {
  // an exhaust valve whose cylinder pressure pushes on its head while it is open, also over
  // the nose of the lift where the inertia pulls the tappet off the cam and, with the
  // spring's damper, on the closing flank where the damper unloads it: the gas force loads
  // the contact where it separates, so it raises the separation speed. per point the
  // smallest positive root w of m y'' w^2 + c y' w + (k x + F0 + gas) = 0, written here from
  // the quadratic formula with the gas table interpolated here: 0 N at 0 crank deg, 300 N
  // from 100 to 600, 0 N again at 700 (cam 50 .. 300 deg at 300 N)
  ValveCase c;
  const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
  auto gas_force = [](double crank_deg) {
    const double x = std::fmod(crank_deg, 720.0);
    if (x <= 100) return 300 * x / 100;
    if (x <= 600) return 300.0;
    if (x <= 700) return 300 * (700 - x) / 100;
    return 0.0;
  };
  for (const double damping : {0.0, 400.0}) {  // [N s/m]
    INFO("spring damping " << damping << " N s/m");
    DesignSpec d = valve_design(c, o.face_height(0)[0]);
    d.springs[0].damping_N_s_per_m = damping;
    GasForceSpec g;
    g.node = "tappet";
    g.crank_angle_deg = {0, 100, 600, 700, 720};
    g.force_N = {0, 300, 300, 0, 0};
    d.gas_forces = {g};
    const Compiled m(d);
    const auto s = sweep_of(m);
    const double m_eff = 1e-3 * (c.mass + c.spring_mass / 3.0), cd = damping * 1e-3;  // [N per mm/s^2], [N s/mm]
    // the smallest positive root over the sweep, with and without the gas force
    auto first_zero = [&](bool gas, double& at_deg) {
      double w_min = INFINITY;
      for (std::size_t i = 0; i < s.points(); ++i) {
        const auto y = o.face_height(s.cam_deg[i] * deg);
        const double rest = c.rate * (y[0] - o.face_height(0)[0]) + c.preload + (gas ? gas_force(2 * s.cam_deg[i]) : 0.0);
        const double qa = m_eff * y[2], qb = cd * y[1], disc = qb * qb - 4 * qa * rest;
        if (std::abs(qa) < 1e-15 || disc < 0) continue;
        for (double root : {(-qb + std::sqrt(disc)) / (2 * qa), (-qb - std::sqrt(disc)) / (2 * qa)})
          if (root > 0 && root < w_min) w_min = root, at_deg = s.cam_deg[i];
      }
      return dynamics::engine_rpm(w_min, 2.0);
    };
    double at = -1, at_no_gas = -1;
    const double rpm = first_zero(true, at), no_gas = first_zero(false, at_no_gas);
    const auto sep = dynamics::separation_speed(s, m.model, 0);
    INFO("separation " << sep.engine_rpm << " rpm at cam " << sep.cam_deg << " deg; closed form " << rpm << " rpm at "
                       << at << " deg, " << no_gas << " rpm without the gas force");
    // the gas force acts where the contact separates, and moves the separation speed
    REQUIRE(gas_force(2 * at) == 300.0);
    REQUIRE(rpm > 1.02 * no_gas);
    CHECK_REL(sep.engine_rpm, rpm, tol::kSeparationRpmRel);
    CHECK(sep.cam_deg == at);
  }
}

TEST_CASE("rigid (a): spring margin is the load a spring can lose before a contact it loads opens",
          "[dynamics][rigid]") {
  // rocker arm: the valve spring loads the pad and, through the rocker, the cam roller
  DesignSpec d = load("rocker_arm.toml");
  const Compiled m(d);
  const auto s = sweep_of(m, 1.0);
  const double w = dynamics::cam_speed_rad_per_s(9000, 2.0);
  std::size_t at = 0;
  double fraction = INFINITY;
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double f = dynamics::spring_margin(s, m.model, i, 0, w) / s.spring_load[i];
    if (f < fraction) fraction = f, at = i;
  }
  REQUIRE(fraction > 0.0);
  REQUIRE(fraction < 1.0);
  // scale the spring law by (1 - margin / load): at that angle a contact force reaches zero
  for (auto& sp : d.springs) {
    sp.rate_N_per_mm *= 1 - fraction;
    sp.preload_N *= 1 - fraction;
  }
  const Compiled weak(d);
  const auto s2 = sweep_of(weak, 1.0);
  double min_force = INFINITY, peak = 0;
  for (int c = 0; c < s2.connections; ++c) {
    min_force = std::min(min_force, s2.force_at(at, c, w));
    peak = std::max(peak, std::abs(s.force_at(at, c, w)));
  }
  INFO("min margin fraction " << fraction << " at cam " << s.cam_deg[at] << " deg");
  CHECK_ABS(min_force, 0.0, tol::kSeparationForceRel * peak);
}

TEST_CASE("rigid (a): a follower at rest on the base circle feels no friction", "[dynamics][rigid]") {
  // rocker arm, pad on the valve with mu 0.08: on the base circle nothing slides, so the
  // forces are the preload's, the same at every angle (no sign of round-off sliding)
  const Compiled m(load("rocker_arm.toml"));
  const auto s = sweep_of(m, 1.0);
  const double w = dynamics::cam_speed_rad_per_s(6000, 2.0);
  for (int c = 0; c < s.connections; ++c)
    for (std::size_t i = 1; i <= 80; ++i) CHECK_REL(s.force_at(i, c, w), s.force_at(0, c, w), tol::kBaseCircleForceRel);
}

TEST_CASE("rigid (a): four-bar with a massive rocker against a Newton-Euler balance", "[dynamics][rigid]") {
  // designs/four_bar.toml geometry: ground 60, crank 20, coupler 70, rocker 50
  const oracles::FourBar f{{0, 0}, {60, 0}, 20, 70, 50, 1};
  const double crank0 = 31.6 * deg;
  const int branch = f.branch_through(crank0, std::atan2(47.1405, 16.6667));
  const oracles::FourBar fb{f.crank_pivot, f.rocker_pivot, f.crank, f.coupler, f.rocker, branch};
  const double th4_0 = fb.solve(crank0).rocker_angle[0];
  const Vector2d A0 = polar(20, crank0), D = fb.rocker_pivot, B0 = D + polar(50, th4_0);
  const Vector2d cg0 = D + polar(30, th4_0) + polar(6, th4_0 + 90 * deg);  // off the rocker line
  const double mass = 0.06, inertia = 12.5;  // [kg], [kg mm^2] about the cg
  DesignSpec d = design("four_bar", "crank", "rocker");
  d.driver.crank_per_cam = 1;
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", {D.x(), D.y()})};
  d.nodes[1].mass_kg = mass;
  d.nodes[1].inertia_kg_mm2 = inertia;
  d.nodes[1].cg_mm = Vec2{cg0.x(), cg0.y()};
  SpringSpec ts;  // torsion spring on the rocker
  ts.name = "rocker_spring";
  ts.kind = SpringKind::torsion;
  ts.node = "rocker";
  ts.rate_Nmm_per_deg = 20;
  ts.preload_Nmm = 300;
  d.springs = {ts};
  d.connections = {link("coupler", "crank", {A0.x(), A0.y()}, "rocker", {B0.x(), B0.y()})};
  const Compiled m(d);
  const auto s = sweep_of(m);
  const double w = dynamics::cam_speed_rad_per_s(3000, 1.0);
  const int rocker = m.mech.node_index("rocker");
  ScalarCompare link_force("coupler force"), torque("crank torque"), rx("rocker pivot x"), ry("rocker pivot y"),
      cx("crank pivot x");
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double th = s.cam_deg[i] * deg;
    const auto st = fb.solve(crank0 + th);
    const auto& psi = st.rocker_angle;  // absolute rocker angle and its derivatives per rad of crank
    const double turn = psi[0] - th4_0;
    const Vector2d A = polar(20, crank0 + th), B = D + polar(50, psi[0]);
    const Vector2d r = Eigen::Rotation2Dd(turn) * (cg0 - D);
    // cg acceleration per (rad/s)^2: psi'' z x r - psi'^2 r  [mm/rad^2]
    const Vector2d acc = psi[2] * Vector2d(-r.y(), r.x()) - psi[1] * psi[1] * r;
    const Vector2d ma = 1e-3 * mass * w * w * acc;                           // [N]
    const double i_alpha = 1e-3 * inertia * w * w * psi[2];                  // [N mm]
    const double spring = -(300 + 20 * wrap_angle(turn) / deg);              // [N mm]
    // rocker about D: (B - D) x (lambda u) + spring = I alpha + r x m a, u = (B - A)/|B - A|
    const Vector2d u = (B - A).normalized();
    const double lambda = (i_alpha + cross2(r, ma) - spring) / cross2(B - D, u);
    link_force.add(th, s.force_at(i, 0, w), lambda);
    // crank (no inertia at constant speed): T + A x (-lambda u) = 0
    torque.add(th, s.torque_at(i, w), cross2(A, lambda * u));
    // rocker pivot: R = m a - lambda u; crank pivot: R = lambda u
    rx.add(th, s.reaction_at(i, rocker, 0, w), ma.x() - lambda * u.x());
    ry.add(th, s.reaction_at(i, rocker, 1, w), ma.y() - lambda * u.y());
    cx.add(th, s.reaction_at(i, 1, 0, w), lambda * u.x());
  }
  CHECK_SERIES(link_force.compare(tol::kRigidForceRel));
  CHECK_SERIES(torque.compare(tol::kRigidForceRel));
  CHECK_SERIES(rx.compare(tol::kRigidForceRel));
  CHECK_SERIES(ry.compare(tol::kRigidForceRel));
  CHECK_SERIES(cx.compare(tol::kRigidForceRel));
}

TEST_CASE("rigid (a): offset slider-crank with a massive slider against a Newton-Euler balance",
          "[dynamics][rigid]") {
  // designs/offset_slider_crank.toml geometry: crank 20, rod 70, offset 10, slide along +y
  const oracles::SliderCrank sc{{0, 0}, 20, 70, {10, 0}, {0, 1}, 1, 1};
  const Vector2d A0(-4, -19.5959), B0(10, 48.9898);
  const double crank0 = std::atan2(A0.y(), A0.x());
  const int branch = sc.branch_through(crank0, B0.y());
  const oracles::SliderCrank o{sc.crank_pivot, 20, 70, sc.slide_point, sc.slide_direction, branch, 1};
  const double x0 = o.solve(crank0).slider[0];
  DesignSpec d = design("slider_crank", "crank", "slider");
  d.driver.crank_per_cam = 1;
  const Vector2d Bd(10, x0), Ad = polar(20, crank0);
  d.nodes = {rotational("crank", {0, 0}), translational("slider", {Bd.x(), Bd.y()}, {0, 1})};
  d.nodes[1].mass_kg = 0.15;
  ConnectionSpec rod = link("rod", "crank", {Ad.x(), Ad.y()}, "slider", {Bd.x(), Bd.y()});
  rod.kind = ConnectionKind::crank_slider;
  d.connections = {rod};
  const Compiled m(d);
  const auto s = sweep_of(m);
  const double w = dynamics::cam_speed_rad_per_s(4000, 1.0);
  ScalarCompare rod_force("rod force"), torque("crank torque"), guide("slider guide x");
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double th = s.cam_deg[i] * deg;
    const auto st = o.solve(crank0 + th);
    const Vector2d A = polar(20, crank0 + th), B(10, st.slider[0]);
    const Vector2d u = (B - A).normalized();
    const double ma = 1e-3 * 0.15 * w * w * st.slider[2];  // along +y [N]
    const double lambda = ma / u.y();                        // rod compression along u
    rod_force.add(th, s.force_at(i, 0, w), lambda);
    torque.add(th, s.torque_at(i, w), cross2(A, lambda * u));
    guide.add(th, s.reaction_at(i, 2, 0, w), -lambda * u.x());
  }
  CHECK_SERIES(rod_force.compare(tol::kRigidForceRel));
  CHECK_SERIES(torque.compare(tol::kRigidForceRel));
  CHECK_SERIES(guide.compare(tol::kRigidForceRel));
}

TEST_CASE("rigid (a): gear and rack-pinion transmit the spring loads, torque by virtual work",
          "[dynamics][rigid]") {
  // a crank drives a wheel through a gear (ratio -0.5, torsion spring on the wheel) and a
  // rack (pitch radius 12 mm, compression spring on the rack); constant speed: no inertia
  DesignSpec d = design("gears", "crank", "rack");
  d.driver.crank_per_cam = 1;
  d.nodes = {rotational("crank", {0, 0}), rotational("wheel", {0, 120}), translational("rack", {0, -12}, {1, 0})};
  d.nodes[1].inertia_kg_mm2 = 50;
  d.nodes[2].mass_kg = 0.2;
  ConnectionSpec gear;
  gear.name = "timing";
  gear.kind = ConnectionKind::gear;
  gear.node_a = "crank";
  gear.node_b = "wheel";
  gear.ratio = -0.5;
  ConnectionSpec mesh;
  mesh.name = "mesh";
  mesh.kind = ConnectionKind::rack_pinion;
  mesh.node_a = "crank";
  mesh.node_b = "rack";
  mesh.pitch_radius_mm = 12;
  d.connections = {gear, mesh};
  SpringSpec ws;
  ws.name = "wheel_spring";
  ws.kind = SpringKind::torsion;
  ws.node = "wheel";
  ws.rate_Nmm_per_deg = 3;
  ws.preload_Nmm = 400;
  SpringSpec rs;
  rs.name = "rack_spring";
  rs.node = "rack";
  rs.rate_N_per_mm = 2;
  rs.preload_N = 30;
  d.springs = {ws, rs};
  const Compiled m(d);
  dynamics::RigidSweep s;
  REQUIRE(dynamics::rigid_sweep(m.mech, m.model, {}, 0, 180, 1, s).ok());
  const double w = dynamics::cam_speed_rad_per_s(1000, 1.0);
  ScalarCompare gear_torque("gear torque on the wheel"), rack_force("rack force"), torque("crank torque");
  for (std::size_t i = 0; i < s.points(); ++i) {
    const double t = s.cam_deg[i] * deg;
    const double wheel = 400 + 3 * (-0.5 * s.cam_deg[i]);  // [N mm]
    const double rack = 30 + 2 * 12 * t;                    // [N]
    gear_torque.add(t, s.force_at(i, 0, w), wheel);
    rack_force.add(t, s.force_at(i, 1, w), rack);
    torque.add(t, s.torque_at(i, w), -0.5 * wheel + 12 * rack);
  }
  CHECK_SERIES(gear_torque.compare(tol::kRigidForceRel));
  CHECK_SERIES(rack_force.compare(tol::kRigidForceRel));
  CHECK_SERIES(torque.compare(tol::kRigidForceRel));
}

TEST_CASE("rigid (a): power balance, drive power = d(kinetic + spring energy)/dt + friction loss",
          "[dynamics][rigid]") {
  // the CVVL with and without lash; the Valvetronic (a floating lever held by three
  // contacts) and the VVLD (two rockers coupled by contacts)
  for (const auto& [file, zero_lash] : {std::pair<const char*, bool>{"cvvl_swing_cam.toml", false},
                                        {"cvvl_swing_cam.toml", true},
                                        {"valvetronic.toml", false},
                                        {"vvld.toml", false}}) {
    INFO(file);
    DesignSpec d = load(file);
    if (zero_lash)
      for (auto& c : d.connections) c.lash_mm = 0.0;
    const Compiled m(d);
    const double w = dynamics::cam_speed_rad_per_s(kRpm, 2.0);
    dynamics::RigidWorkspace ws(m.mech, m.model);
    std::vector<double> controls;
    for (const auto& c : m.mech.controls) controls.push_back(c.default_value);
    ws.kin.set_controls(controls);
    ScalarCompare power(std::string(file) + " torque vs energy rate, zero lash " + std::to_string(zero_lash));
    double work = 0.0, abs_work = 0.0, prev = 0.0;
    const double step = 0.5;
    for (int i = 0; i <= 720; ++i) {
      const double th = i * step * deg;
      const Status st = dynamics::solve_rigid(m.mech, m.model, ws, th);
      REQUIRE(st.ok());
      // d(E)/dtheta with E = sum 1/2 (m |v_cg|^2 + I phi'^2) w^2 + spring energy
      double de = 0.0;
      for (std::size_t n = 1; n < m.mech.nodes.size(); ++n) {
        const auto& b = m.model.bodies[n];
        const auto pose = kin::node_pose(m.mech, static_cast<int>(n), ws.kin.vars.data(), ws.kin.pivots().data());
        const auto cg = pose.apply(b.cg.x(), b.cg.y());
        const double vx = cg.x.c[1], vy = cg.y.c[1], ax = 2 * cg.x.c[2], ay = 2 * cg.y.c[2];
        de += 1e-3 * b.mass * w * w * (vx * ax + vy * ay);
        const auto& node = m.mech.nodes[n];
        if (node.kind != NodeKind::translational && node.control < 0) {
          const auto& phi = ws.kin.vars[node.first_variable + (node.kind == NodeKind::floating ? 2 : 0)];
          de += 1e-3 * b.inertia * w * w * phi.c[1] * 2 * phi.c[2];
        }
      }
      for (std::size_t k = 0; k < m.model.springs.size(); ++k) {
        const dynamics::Spring& sp = m.model.springs[k];
        double rate = ws.kin.vars[m.mech.nodes[sp.node].first_variable].c[1];
        if (sp.on_point) {  // a point of a floating body: its travel rate along the spring's line
          const auto p = kin::node_pose(m.mech, sp.node, ws.kin.vars.data(), ws.kin.pivots().data())
                             .apply(sp.point.x(), sp.point.y());
          rate = sp.direction.x() * p.x.c[1] + sp.direction.y() * p.y.c[1];
        }
        de += ws.spring_load(static_cast<Eigen::Index>(k)) * rate;
      }
      // friction loss per rad: mu N |sliding|
      double loss = 0.0;
      for (std::size_t c = 0; c < m.mech.connections.size(); ++c) {
        const auto& cd = m.model.contacts[c];
        if (!cd.is_contact || cd.rolling || ws.kin.contacts[c].open) continue;
        double n_force = 0.0;
        for (int j = 0; j < ws.cases(); ++j) n_force += ws.case_weight(j, w) * ws.force(static_cast<Eigen::Index>(c), j);
        loss += cd.friction * n_force * std::abs(ws.kin.contacts[c].sliding);
      }
      double torque = 0.0;
      for (int j = 0; j < ws.cases(); ++j) torque += ws.case_weight(j, w) * ws.torque(j);
      power.add(th, torque, de + loss);
      if (i > 0) {
        work += 0.5 * (torque + prev) * step * deg;
        abs_work += 0.5 * (std::abs(torque) + std::abs(prev)) * step * deg;
      }
      prev = torque;
    }
    CHECK_SERIES(power.compare(tol::kRigidForceRel));
    if (zero_lash && std::string(file) == "cvvl_swing_cam.toml") {
      // friction (pad on the valve tip, mu 0.08) is the only net work over a closed cycle
      INFO("net work " << work << " N mm rad of " << abs_work);
      CHECK(work > 0.0);
    }
  }
}

TEST_CASE("rigid (a): conservative cycle does zero net work", "[dynamics][rigid]") {
  DesignSpec d = load("cvvl_swing_cam.toml");
  for (auto& c : d.connections) {
    c.lash_mm = 0.0;
    c.friction_coefficient.reset();
  }
  const Compiled m(d);
  const double w = dynamics::cam_speed_rad_per_s(kRpm, 2.0);
  const auto s = sweep_of(m, 0.25, {0.0});
  double work = 0.0, abs_work = 0.0;
  for (std::size_t i = 1; i < s.points(); ++i) {
    const double a = s.torque_at(i - 1, w), b = s.torque_at(i, w);
    work += 0.5 * (a + b) * 0.25 * deg;
    abs_work += 0.5 * (std::abs(a) + std::abs(b)) * 0.25 * deg;
  }
  INFO("net work " << work << " of " << abs_work << " N mm");
  CHECK_ABS(work, 0.0, tol::kCycleWorkRel * abs_work);
}

TEST_CASE("rigid (a): every bundled design runs at 6000 rpm", "[dynamics][rigid]") {
  for (const char* name : {"bucket_tappet.toml", "cvvl_swing_cam.toml", "eccentric_flat_follower.toml",
                           "eccentric_offset_roller.toml", "eccentric_oscillating_roller.toml", "four_bar.toml",
                           "offset_slider_crank.toml", "rocker_arm.toml", "roller_finger_follower.toml",
                           "valvetronic.toml", "vvld.toml"}) {
    INFO(name);
    const Compiled m(load(name));
    const auto s = sweep_of(m, 1.0);
    CHECK(s.points() == 361);
    for (double v : s.force) REQUIRE(std::isfinite(v));
  }
}

TEST_CASE("rigid (a): missing or bad dynamics data is an InputError naming the field", "[dynamics][input]") {
  ValveCase c;
  const double h = oracles::EccentricFlatFollower{c.R, c.e, c.phase}.face_height(0)[0];
  auto throws_with = [](const DesignSpec& d, const std::string& text) {
    const kin::Mechanism mech = kin::compile(d);
    CHECK_THROWS_WITH(dynamics::compile_dynamics(d, mech), Catch::Contains(text));
  };
  DesignSpec d = valve_design(c, h);
  d.nodes[1].mass_kg.reset();
  throws_with(d, "node 'tappet': mass_kg is required");
  d = valve_design(c, h);
  d.nodes[1].mass_kg = -0.1;
  throws_with(d, "mass_kg: value -0.1 must be > 0");
  d = valve_design(c, h);
  d.springs[0].rate_N_per_mm = 0;
  throws_with(d, "spring 'valve_spring': rate_N_per_mm: value 0 must be > 0");
  d = valve_design(c, h);
  d.springs[0].mass_kg = 0.0;
  throws_with(d, "spring 'valve_spring': mass_kg");
  d = valve_design(c, h);
  d.nodes.push_back(rotational("arm", {30, 0}));
  d.nodes.back().mass_kg = 0.01;
  d.nodes.back().cg_mm = Vec2{31, 0};
  d.nodes.back().inertia_kg_mm2 = 0.0;
  d.connections.push_back(link("arm_link", "tappet", {0, h}, "arm", {30, h}));
  // the extra link makes the arm a driven body: its inertia must be positive
  throws_with(d, "node 'arm': inertia_kg_mm2: value 0 must be > 0");
}

TEST_CASE("rigid (a): bad sweep arguments and a connection that is no contact are input errors", "[dynamics][input]") {
  const DesignSpec spec = dyn_test::direct_valve(40, 250);
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
  dynamics::RigidSweep s;
  CHECK_THROWS_AS(dynamics::rigid_sweep(mech, model, {}, 0, 360, 0, s), InputError);
  CHECK_THROWS_WITH(dynamics::rigid_sweep(mech, model, {}, 0, 360, -1, s),
                    Catch::Contains("rigid_sweep: step_deg = -1 must be > 0"));
  CHECK_THROWS_WITH(dynamics::rigid_sweep(mech, model, {}, 10, 0, 1, s),
                    Catch::Contains("rigid_sweep: stop_deg = 0 must be >= start_deg = 10"));
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0, 360, 10, s).ok());
  CHECK_THROWS_AS(dynamics::separation_speed(s, model, 1), InputError);
  CHECK_THROWS_WITH(dynamics::separation_speed(s, model, -1),
                    Catch::Contains("separation_speed: connection = -1 must be a contact"));
}
