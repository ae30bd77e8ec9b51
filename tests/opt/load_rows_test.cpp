// the optimiser's durability rows (separation speed, contact force, spring margin, cam
// torque, EHL film, lambda) and their one source of loads: gradients against central
// differences, a separation limit active at the optimum checked by bisection on the rpm of
// the rigid model of the synthesized cam (an independent formulation), the Hertz row against
// p0 = sqrt(F E* / (pi L R*)) from that model, and a set that disagrees with its design.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <numbers>
#include <set>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "opt/opt_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

constexpr double kPi = camopt::pi;

DesignSpec design(const std::string& name) {
  return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name);
}

// the RFF without friction (the optimiser's loads leave it out), with spring dampers and a
// gas force on the valve, so the rows see every load case
DesignSpec rff_loaded() {
  DesignSpec d = design("roller_finger_follower.toml");
  for (auto& c : d.connections) c.friction_coefficient.reset();
  for (auto& s : d.springs) s.damping_N_s_per_m = 60.0;
  GasForceSpec gas;
  gas.node = d.output_node;
  gas.crank_angle_deg = {0, 200, 300, 420, 720};
  gas.force_N = {0, 0, 150, 30, 0};
  d.gas_forces = {gas};
  return d;
}

opt::OptimizationSpec rff_set() {
  opt::OptimizationSpec s;
  s.event.start_deg = 114.0;
  s.event.duration_deg = 128.0;
  s.event.opening_ramp = {0.2, 18.0};
  s.event.closing_ramp = {0.2, 18.0};
  s.event.coefficients = 16;
  s.initial_max_lift_mm = 8.0;
  s.rpm = 6500;
  s.grid_step_deg = 1.0;
  s.objective.area_weight = 1.0;
  return s;
}

void check_jacobian(opt::CamProblem& p, const std::vector<double>& u, const std::vector<opt::ConstraintKind>& kinds) {
  opt::Evaluation e;
  REQUIRE(p.evaluate(u, e, true).ok());
  std::vector<int> count(kinds.size(), 0);
  const double h = 1e-6;
  for (int j = 0; j < p.spline_variables(); ++j) {
    std::vector<double> up = u, um = u;
    up[static_cast<std::size_t>(j)] += h;
    um[static_cast<std::size_t>(j)] -= h;
    opt::Evaluation ep, em;
    REQUIRE(p.evaluate(up, ep, false).ok());
    REQUIRE(p.evaluate(um, em, false).ok());
    for (std::size_t r = 0; r < p.rows().size(); ++r) {
      const auto& row = p.rows()[r];
      const auto it = std::find(kinds.begin(), kinds.end(), row.kind);
      if (it == kinds.end()) continue;
      if (j == 0) ++count[static_cast<std::size_t>(it - kinds.begin())];
      const auto k = static_cast<Eigen::Index>(r);
      INFO("variable " << j << " row " << opt::to_string(row.kind) << " " << p.item_name(row) << " at cam "
                       << row.cam_deg << " position " << row.position);
      CHECK_NEAR(e.jacobian(k, j), (ep.g(k) - em.g(k)) / (2 * h), tol::kOptLoadRowFdAbs, tol::kOptRowFdRel);
    }
  }
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    INFO(opt::to_string(kinds[k]));
    CHECK(count[k] > 10);
  }
}

}  // namespace

TEST_CASE("durability rows: gradients against central differences (roller finger follower)", "[opt][durability]") {
  opt::OptimizationSpec s = rff_set();
  s.limits.min_separation_speed_rpm = 8000;
  s.limits.min_contact_force_N = 100;
  s.limits.min_spring_margin = 0.2;
  s.limits.max_cam_torque_Nm = 12;
  s.limits.min_film_thickness_um = 0.2;
  s.limits.min_lambda = 1.0;
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(rff_loaded(), s, nullptr);  // the design's [oil]
  opt::CamProblem& p = *made_p;
  std::vector<double> u = p.start();
  for (int j = 0; j < p.spline_variables(); ++j) u[static_cast<std::size_t>(j)] += 0.01 * std::sin(1.0 + j);
  check_jacobian(p, u,
                 {opt::ConstraintKind::separation, opt::ConstraintKind::contact_force, opt::ConstraintKind::spring_margin,
                  opt::ConstraintKind::cam_torque, opt::ConstraintKind::film_thickness, opt::ConstraintKind::lambda});
  // separation rows for the cam contact and the pad behind it
  std::set<std::string> contacts;
  for (const auto& row : p.rows())
    if (row.kind == opt::ConstraintKind::separation) contacts.insert(p.item_name(row));
  CHECK(contacts == std::set<std::string>{"cam_roller", "pad_valve"});
}

TEST_CASE("durability rows: gradients against central differences (CVVL swing cam)", "[opt][durability]") {
  opt::OptimizationSpec s = io::load_constraints(std::string(CAMOPT_SOURCE_DIR) + "/constraints/cvvl_swing_cam.toml");
  s.cam = "swing";
  s.swing.positions = {0.0, 40.0};
  s.grid_step_deg = 2.0;
  s.limits.min_separation_speed_rpm = 7000;
  s.limits.min_contact_force_N = 50;
  s.limits.min_spring_margin = 0.2;
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(design("cvvl_swing_cam.toml"), s, nullptr);
  opt::CamProblem& p = *made_p;
  std::vector<double> u = p.start();
  for (int j = 0; j < p.spline_variables(); ++j) u[static_cast<std::size_t>(j)] *= 1.0 + 0.02 * std::sin(1.0 + j);
  check_jacobian(p, u, {opt::ConstraintKind::separation, opt::ConstraintKind::contact_force, opt::ConstraintKind::spring_margin});
}

TEST_CASE("a separation limit active at the optimum holds by bisection on the rpm of the synthesized cam's rigid model",
          "[opt][durability]") {
  DesignSpec d = design("roller_finger_follower.toml");
  for (auto& c : d.connections) c.friction_coefficient.reset();
  opt::OptimizationSpec s = rff_set();
  s.grid_step_deg = 0.5;
  s.event.coefficients = 24;
  s.limits.acc_max_mm_per_deg2 = 0.02;
  s.limits.acc_min_mm_per_deg2 = -0.011;
  s.limits.jerk_max_mm_per_deg3 = 0.004;
  s.limits.min_radius_of_curvature_mm = 4.0;
  s.limits.max_hertz_stress_MPa = 1300;
  s.limits.min_separation_speed_rpm = 7500;
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(d, s, nullptr);
  opt::CamProblem& p = *made_p;
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  const opt::SolveResult r = opt::optimize(p, so);
  REQUIRE(r.status.ok());
  // the limit is active: the least separation row is at its limit
  double worst = -1e300;
  for (std::size_t k = 0; k < p.rows().size(); ++k)
    if (p.rows()[k].kind == opt::ConstraintKind::separation) worst = std::max(worst, r.final.g(static_cast<Eigen::Index>(k)));
  CHECK_ABS(worst, 0.0, tol::kOptActiveRowAbs);

  // the cam for the optimised lift, as optimize synthesizes it
  const auto coef = p.coefficients(r.u);
  std::vector<double> knots, values;
  for (int i = 0; i < 1440; ++i) {
    knots.push_back(2 * kPi * i / 1440);
    values.push_back(p.lift_model().evaluate(coef, 0.25 * i).lift);
  }
  const PeriodicSpline lift = PeriodicSpline::interpolate(knots, values, 2 * kPi);
  synthesis::SynthesisOptions syn;
  syn.points = 3600;
  syn.samples = 3600;
  synthesis::SynthesisResult res;
  REQUIRE(synthesis::synthesize(d, lift, syn, res).ok());
  const DesignSpec made = synthesis::with_profile(d, res.profile);
  const kin::Mechanism mech = kin::compile(made);
  const dynamics::Model model = dynamics::compile_dynamics(made, mech);
  dynamics::RigidSweep sweep;
  REQUIRE(dynamics::rigid_sweep(mech, model, {}, 0.0, 360.0, 0.1, sweep).ok());
  int conn = -1;
  for (int c = 0; c < static_cast<int>(made.connections.size()); ++c)
    if (made.connections[static_cast<std::size_t>(c)].name == "cam_roller") conn = c;
  REQUIRE(conn >= 0);
  // bisection on the engine speed for the least cam-contact force over the cycle
  auto least = [&](double rpm) {
    const double w = dynamics::cam_speed_rad_per_s(rpm, model.crank_per_cam);
    double f = 1e300;
    for (std::size_t i = 0; i < sweep.points(); ++i) f = std::min(f, sweep.force_at(i, conn, w));
    return f;
  };
  double lo = 1000, hi = 20000;
  REQUIRE(least(lo) > 0);
  REQUIRE(least(hi) < 0);
  for (int it = 0; it < 60; ++it) ((least(0.5 * (lo + hi)) > 0) ? lo : hi) = 0.5 * (lo + hi);
  INFO("separation of the synthesized cam: " << lo << " rpm");
  // the rows hold at the 0.5 deg grid; between its points the force may dip a little lower
  CHECK_REL(lo, 7500.0, tol::kSynthesizedSeparationRel);

  // the Hertz row against p0 = sqrt(F E* / (pi L R*)) from the rigid model's force and the
  // kinematic solver's curvatures of the synthesized cam
  const dynamics::ContactData& cd = model.contacts[static_cast<std::size_t>(conn)];
  const double w = p.cam_speed_rad_per_s();
  dynamics::RigidWorkspace ws(mech, model);
  int compared = 0;
  for (std::size_t k = 0; k < p.rows().size(); ++k) {
    const auto& row = p.rows()[k];
    if (row.kind != opt::ConstraintKind::hertz_stress || std::fmod(row.cam_deg, 2.0) != 0.0) continue;
    // where the ramps join the main lift the lift's jerk jumps: the synthesized cam (a quintic
    // spline through the lift every 0.25 deg) rounds its curvature there
    if (std::abs(row.cam_deg - p.lift_model().main_start_deg()) < 1.0 ||
        std::abs(row.cam_deg - p.lift_model().main_end_deg()) < 1.0)
      continue;
    REQUIRE(dynamics::solve_rigid(mech, model, ws, row.cam_deg * kPi / 180.0).ok());
    double f = 0;
    for (int j = 0; j < ws.cases(); ++j) f += ws.force(conn, j) * ws.case_weight(j, w);
    const kin::ContactState& cs = ws.kin.contacts[static_cast<std::size_t>(conn)];
    const double p0 = std::sqrt(f * cd.e_star * (cs.curvature_a + cs.curvature_b) / (kPi * cd.width));
    INFO("cam " << row.cam_deg);
    CHECK_REL(r.final.physical(static_cast<Eigen::Index>(k)), p0, tol::kSynthesizedHertzRel);
    ++compared;
  }
  CHECK(compared > 40);
}

TEST_CASE("a constraint set whose [load] disagrees with its design is an input error naming both files",
          "[opt][durability]") {
  const std::string set = R"(schema = 1
[set]
name = "t"
rpm = 6000
initial_max_lift_mm = 8
[event]
start_deg = 114
duration_deg = 128
[limits]
min_separation_speed_rpm = 7000
[load]
spring_preload_N = 230
spring_rate_N_per_mm = 35
moving_mass_kg = 0.08
[objective]
area_weight = 1
)";
  const DesignSpec d = design("roller_finger_follower.toml");
  const opt::OptimizationSpec s = io::parse_constraints(set, "set.toml", ".");
  try {
    (void)opt_test::make_problem(d, s, nullptr);
    FAIL("no error");
  } catch (const InputError& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(m.find("set.toml:12:20: load.spring_preload_N") != std::string::npos);
    CHECK(m.find("230 N disagrees") != std::string::npos);
    CHECK(m.find("roller_finger_follower.toml:") != std::string::npos);
    CHECK(m.find("220 N") != std::string::npos);
    CHECK(m.find("override_design") != std::string::npos);
  }
  // the design's own values pass, and an override is echoed with the design's value
  std::string agree = set;
  agree.replace(agree.find("230"), 3, "220");
  agree.replace(agree.find("moving_mass_kg = 0.08\n"), 22, "");
  CHECK_NOTHROW(opt_test::make_problem(d, io::parse_constraints(agree, "set.toml", "."), nullptr));
  std::string over = set;
  over.replace(over.find("[load]\n"), 7, "[load]\noverride_design = true\n");
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(d, io::parse_constraints(over, "set.toml", "."), nullptr);
  opt::CamProblem& p = *made_p;
  CHECK(p.load_source().find("override_design") != std::string::npos);
  const auto o = p.load_overrides();
  REQUIRE(o.size() == 3);
  CHECK(o[0].key == "load.spring_preload_N");
  CHECK(o[0].set_value == 230);
  CHECK(o[0].design_value.find("220 N") == 0);
  // the film's oil: a set's [oil] that disagrees with the design's is an input error
  opt::OptimizationSpec film = rff_set();
  film.limits.min_film_thickness_um = 0.1;
  film.oil = opt::OilSetSpec{8.0, 15.8, 0.25, SourceRef{"set.toml", 30, 1, "oil"}};
  CHECK_THROWS_WITH(opt_test::make_problem(d, film, nullptr),
                    Catch::Contains("set.toml:30:1: oil: oil.viscosity_mPa_s disagrees with the design's [oil]"));
}
