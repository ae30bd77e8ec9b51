// the swing-cam optimisation problem on the bundled CVVL: its jacobian against central
// finite differences (every constraint kind, every position), and a solve whose result
// satisfies every constraint at all 17 control positions and beats the initial design.
#include <catch2/catch.hpp>
#include <Eigen/Core>
#include <cmath>

#include "camopt/io/design_file.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"

using namespace camopt;

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
  opt::CamProblem p(cvvl(), s, nullptr);
  REQUIRE(p.is_swing());
  REQUIRE(p.equality_matrix().rows() == 0);
  const int n = p.variables();
  std::vector<double> u = p.start();
  for (int j = 0; j < p.spline_variables(); ++j) u[static_cast<std::size_t>(j)] *= 1.0 + 0.02 * std::sin(1.0 + j);
  opt::Evaluation e;
  REQUIRE(p.evaluate(u, e, true).ok());
  REQUIRE(e.g.size() > 500);
  const double h = 1e-6;
  double worst = 0.0;
  for (int j = 0; j < n; ++j) {
    std::vector<double> up = u, um = u;
    up[static_cast<std::size_t>(j)] += h;
    um[static_cast<std::size_t>(j)] -= h;
    opt::Evaluation ep, em;
    REQUIRE(p.evaluate(up, ep, false).ok());
    REQUIRE(p.evaluate(um, em, false).ok());
    INFO("variable " << j);
    CHECK(e.gradient(j) == Approx((ep.objective - em.objective) / (2 * h)).epsilon(1e-6).margin(1e-8));
    for (Eigen::Index r = 0; r < e.g.size(); ++r) {
      const double fd = (ep.g(r) - em.g(r)) / (2 * h);
      worst = std::max(worst, std::abs(e.jacobian(r, j) - fd));
      INFO("row " << r << " " << opt::to_string(p.rows()[static_cast<std::size_t>(r)].kind) << " at "
                  << p.rows()[static_cast<std::size_t>(r)].cam_deg << " position "
                  << p.rows()[static_cast<std::size_t>(r)].position);
      CHECK(e.jacobian(r, j) == Approx(fd).epsilon(1e-5).margin(1e-6));
    }
  }
}

TEST_CASE("swing problem: the optimised profile satisfies every constraint at all 17 positions", "[opt][swing]") {
  opt::OptimizationSpec s = swing_spec();
  opt::CamProblem p(cvvl(), s, nullptr);
  REQUIRE(p.swing()->positions().size() == 17);
  opt::Evaluation e0;
  REQUIRE(p.evaluate(p.start(), e0, false).ok());
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  so.max_iterations = 400;
  const opt::SolveResult r = opt::optimize(p, so);
  INFO(r.status.str() << " " << r.solver_message << " iterations " << r.iterations);
  REQUIRE(r.evaluated);
  CHECK(r.status.ok());
  // every row at every position within 1e-6 of its limit (normalised)
  CHECK(r.final.g.maxCoeff() <= 1e-6);
  int positions_seen = 0;
  std::vector<char> seen(17, 0);
  for (const auto& row : p.rows()) seen[static_cast<std::size_t>(row.position)] = 1;
  for (char c : seen) positions_seen += c;
  CHECK(positions_seen == 17);
  // more lift area at full lift than the design's own swing cam
  CHECK(r.final.objective < e0.objective - 0.02);
}
