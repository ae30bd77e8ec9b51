// the swing-cam optimisation problem on the bundled CVVL: its jacobian against central
// finite differences (every constraint kind, every position), and a solve whose result
// satisfies every constraint at all 17 control positions and beats the initial design.
#include <catch2/catch.hpp>
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <numbers>

#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "opt/opt_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

DesignSpec cvvl() { return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml"); }

opt::OptimizationSpec swing_spec() {
  opt::OptimizationSpec s;
  s.cam = "swing";
  s.rpm = 5000;
  s.grid_step_deg = 1.0;
  s.limits.acc_max_mm_per_deg2 = 0.032;
  s.limits.acc_min_mm_per_deg2 = -0.009;
  s.limits.jerk_max_mm_per_deg3 = 0.010;
  s.limits.max_lift_mm = 10.0;
  s.limits.min_radius_of_curvature_mm = 3.0;
  s.limits.grinding_wheel_radius_mm = 20.0;
  s.limits.max_pressure_angle_deg = 30.0;
  s.limits.max_roller_speed_rpm = 20000;
  s.limits.max_hertz_stress_MPa = 1500;
  opt::LoadSpec load;
  load.spring_preload_N = 220;
  load.spring_rate_N_per_mm = 35;
  load.moving_mass_kg = 0.07;
  s.load = load;
  s.objective.area_weight = 1.0;
  return s;
}

// a valve-lift target at full lift: a 3-4-5 event of 9.5 mm peaking at cam 180 deg
PeriodicSpline target_lift() {
  synthesis::LiftEventSpec es;
  es.max_lift_mm = 9.5;
  es.peak_deg = 180.0;
  es.opening = {synthesis::LawKind::polynomial_345, 66.0, 0.0, 0.0, {}, 3};
  es.closing = {synthesis::LawKind::polynomial_345, 66.0, 0.0, 0.0, {}, 3};
  const auto ev = synthesis::LiftEvent::compile(es);
  std::vector<double> x, y;
  for (int i = 0; i < 1440; ++i) {
    x.push_back(2 * std::numbers::pi * i / 1440);
    y.push_back(ev.evaluate(i * 0.25).lift);
  }
  return PeriodicSpline::interpolate(x, y, 2 * std::numbers::pi);
}

// SLSQP on p: converged, with every row at every position within 1e-6 of its limit (normalised)
opt::SolveResult solve_within_limits(opt::CamProblem& p) {
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  so.max_iterations = 400;
  opt::SolveResult r = opt::optimize(p, so);
  INFO(r.status.str() << " " << r.solver_message << " iterations " << r.iterations);
  REQUIRE(r.evaluated);
  CHECK(r.status.ok());
  CHECK(r.final.g.maxCoeff() <= 1e-6);
  return r;
}

}  // namespace

TEST_CASE("swing problem jacobian matches central finite differences", "[opt][swing]") {
  opt::OptimizationSpec s = swing_spec();
  s.swing.positions = {0.0, 8.0, 16.0};
  s.grid_step_deg = 2.0;
  s.limits.min_max_lift_mm = 9.0;
  s.limits.duration_check_height_mm = 1.0;
  s.limits.min_duration_deg = 100.0;
  s.limits.max_duration_deg = 140.0;
  s.objective.peak_weight = 0.3;
  s.objective.peak = opt::Quantity::pressure_angle;
  s.objective.target_weight = 0.5;  // least squares at full lift, one-sided where the target is shut
  s.objective.target_file = "(in memory)";
  const PeriodicSpline target = target_lift();
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(cvvl(), s, &target);
  opt::CamProblem& p = *made_p;
  REQUIRE(p.is_swing());
  REQUIRE(p.equality_matrix().rows() == 0);
  const int n = p.variables();
  std::vector<double> u = p.start();
  for (int j = 0; j < p.spline_variables(); ++j) u[static_cast<std::size_t>(j)] *= 1.0 + 0.02 * std::sin(1.0 + j);
  opt::Evaluation e;
  REQUIRE(p.evaluate(u, e, true).ok());
  REQUIRE(e.g.size() > 500);
  const double h = 1e-6;
  for (int j = 0; j < n; ++j) {
    std::vector<double> up = u, um = u;
    up[static_cast<std::size_t>(j)] += h;
    um[static_cast<std::size_t>(j)] -= h;
    opt::Evaluation ep, em;
    REQUIRE(p.evaluate(up, ep, false).ok());
    REQUIRE(p.evaluate(um, em, false).ok());
    INFO("variable " << j);
    // the objective by a wider difference: the target term weighs squared micrometres (1e6 /
    // mm^2 over ~150 points), so the newton solves' 1e-14 floor leaves ~3e-9 of noise in f
    // (margin 5e-5 = 2 x that / 1e-4)
    {
      const double ho = 1e-4;
      std::vector<double> uo_p = u, uo_m = u;
      uo_p[static_cast<std::size_t>(j)] += ho;
      uo_m[static_cast<std::size_t>(j)] -= ho;
      opt::Evaluation op, om;
      REQUIRE(p.evaluate(uo_p, op, false).ok());
      REQUIRE(p.evaluate(uo_m, om, false).ok());
      CHECK_NEAR(e.gradient(j), (op.objective - om.objective) / (2 * ho), tol::kSwingObjectiveFdAbs,
                 tol::kOptObjectiveFdRel);
    }
    for (Eigen::Index r = 0; r < e.g.size(); ++r) {
      const double fd = (ep.g(r) - em.g(r)) / (2 * h);
      INFO("row " << r << " " << opt::to_string(p.rows()[static_cast<std::size_t>(r)].kind) << " at "
                  << p.rows()[static_cast<std::size_t>(r)].cam_deg << " position "
                  << p.rows()[static_cast<std::size_t>(r)].position);
      CHECK_NEAR(e.jacobian(r, j), fd, tol::kOptRowFdAbs, tol::kOptRowFdRel);
    }
  }
}

TEST_CASE("swing problem: the optimised profile satisfies every constraint at all 17 positions", "[opt][swing]") {
  opt::OptimizationSpec s = swing_spec();
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(cvvl(), s, nullptr);
  opt::CamProblem& p = *made_p;
  REQUIRE(p.swing()->positions().size() == 17);
  opt::Evaluation e0;
  REQUIRE(p.evaluate(p.start(), e0, false).ok());
  const opt::SolveResult r = solve_within_limits(p);
  int positions_seen = 0;
  std::vector<char> seen(17, 0);
  for (const auto& row : p.rows()) seen[static_cast<std::size_t>(row.position)] = 1;
  for (char c : seen) positions_seen += c;
  CHECK(positions_seen == 17);
  // more lift area at full lift than the design's own swing cam
  CHECK(r.final.objective < e0.objective - 0.02);
}

TEST_CASE("swing problem: the VVLD working curve optimised at 4 control positions, checked by the kinematic solver",
          "[opt][swing][vvld]") {
  const DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/vvld.toml");
  // the bundled set on a 1 deg grid at 4 of its 11 positions (all of them: the CLI test and
  // bench_optimize)
  opt::OptimizationSpec s = io::load_constraints(std::string(CAMOPT_SOURCE_DIR) + "/constraints/vvld_swing_cam.toml");
  s.cam = "swing";
  s.grid_step_deg = 1.0;
  s.swing.positions = {0.0, 30.0, 70.0, 100.0};
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(d, s, nullptr);
  opt::CamProblem& p = *made_p;
  opt::Evaluation e0;
  REQUIRE(p.evaluate(p.start(), e0, false).ok());
  CHECK(e0.g.maxCoeff() > 0.5);  // the design's own arm breaks the set (acceleration by 67 %)
  const opt::SolveResult r = solve_within_limits(p);
  CHECK(r.final.objective < e0.objective);

  // the written profile through the kinematic solver at every position: the optimiser's lift
  // at every working point
  opt::SwingCamLift& model = *p.swing();
  const std::vector<double> c = p.coefficients(r.u);
  ProfileSpec prof;
  for (const auto& pr : d.profiles)
    if (pr.name == model.profile_name()) prof = pr;
  prof.source_file.clear();
  REQUIRE(model.profile_table(c, 7200, 3.0, prof.angle_deg, prof.radius_mm).ok());
  const kin::Mechanism mech = kin::compile(synthesis::with_profile(d, prof));
  const int valve = mech.nodes[static_cast<std::size_t>(mech.output_node)].first_variable;
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows(4, model.variables());
  test::Series lift("valve lift [mm]", "point");
  std::vector<double> peak(4, 0.0);
  for (int k = 0; k < 4; ++k) {
    kin::SweepSpec sw;
    sw.start = 0;
    sw.stop = 360;
    sw.step = 1.0;
    sw.control_positions = {model.controls(k)};
    sw.request = {0, false};
    const kin::SweepResult sr = kin::sweep(mech, sw);
    INFO("position " << k << ": " << sr.positions[0].status.str());
    REQUIRE(sr.positions[0].status.ok());
    for (std::size_t i = 0; i < model.points().size(); ++i) {
      if (model.points()[i].position != k) continue;
      double mo[4];
      REQUIRE(model.evaluate(static_cast<int>(i), c, mo, rows).ok());
      const auto at = static_cast<std::size_t>(std::lround(std::fmod(model.points()[i].cam_deg, 360.0)));
      lift.add(static_cast<double>(i), sr.positions[0].value(at % 360, valve, 0), mo[0]);
      peak[static_cast<std::size_t>(k)] = std::max(peak[static_cast<std::size_t>(k)], mo[0]);
    }
  }
  INFO("compared " << lift.size() << " points; peak lift " << peak[0] << " / " << peak[1] << " / " << peak[2] << " / "
                     << peak[3] << " mm at control 0 / 30 / 70 / 100");
  CHECK(lift.size() > 300);
  CHECK_SERIES(lift.compare({.abs = tol::kSwingTableLiftAbs}));
  CHECK_ABS(peak[0], 10.5, tol::kActiveLiftCapAbs);  // the lift cap is active at full lift
  // lift falls with the control shaft (the design's own arm: 10.69 .. 0.58 mm)
  CHECK(peak[1] < peak[0]);
  CHECK(peak[2] < peak[1]);
  CHECK(peak[3] < peak[2]);
  CHECK(peak[3] < 1.0);
}
