// ipopt's row screening (ipopt_backend.cpp): solved on a working set of the rows near their
// limits, re-solved with the rows found violated, the result must be the optimum of every
// row: the same objective as ipopt on all rows (conventional cams) or as SLSQP on all rows
// (swing cam), with every row of the problem within the feasibility tolerance.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"
#include "opt/opt_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

// a bundled constraint set on its design, its grid coarsened to keep the full-row solve short
struct Bundled {
  DesignSpec design;
  opt::OptimizationSpec set;
};
Bundled bundled(const std::string& design, const std::string& set, double grid_step_deg) {
  const std::string root = CAMOPT_SOURCE_DIR;
  Bundled b{io::load_design(root + "/designs/" + design), io::load_constraints(root + "/constraints/" + set)};
  b.set.grid_step_deg = grid_step_deg;
  return b;
}


opt::SolveResult ipopt(opt::CamProblem& p, bool screening) {
  opt::SolverOptions so;
  so.solver = opt::SolverKind::ipopt;
  so.ipopt_screening = screening;
  opt::SolveResult r = opt::optimize(p, so);
  INFO(r.status.str() << " / " << r.solver_message);
  REQUIRE(r.status.ok());
  REQUIRE(r.evaluated);
  return r;
}

void check_same_optimum(opt::CamProblem& p) {
  const opt::SolveResult full = ipopt(p, false);
  const opt::SolveResult screened = ipopt(p, true);
  INFO(screened.solver_message);
  // the screen left rows out, and the result still meets every row of the problem
  CHECK(screened.solver_rows < full.solver_rows);
  CHECK(screened.max_violation <= opt::SolverOptions{}.constraint_tolerance);
  CHECK(screened.final.g.maxCoeff() <= 1e-6);
  CHECK_NEAR(screened.final.objective, full.final.objective, tol::kSameOptimumRel, tol::kSameOptimumRel);
}

}  // namespace

TEST_CASE("ipopt row screening: roller finger follower, the full-row optimum with every row met", "[opt][ipopt]") {
  const Bundled b = bundled("roller_finger_follower.toml", "passenger_car_intake.toml", 1.0);
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(b.design, b.set, nullptr);
  opt::CamProblem& p = *made_p;
  check_same_optimum(p);
}

TEST_CASE("ipopt row screening: bucket tappet with a peak-stress objective, the full-row optimum", "[opt][ipopt]") {
  const Bundled b = bundled("bucket_tappet.toml", "high_speed_bucket.toml", 1.0);
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(b.design, b.set, nullptr);
  opt::CamProblem& p = *made_p;
  check_same_optimum(p);
}

TEST_CASE("ipopt row screening: swing cam at three control positions, SLSQP's optimum on every row", "[opt][ipopt]") {
  Bundled b = bundled("cvvl_swing_cam.toml", "cvvl_swing_cam.toml", 1.0);
  b.set.cam = "swing";
  b.set.swing.positions = {0.0, 8.0, 16.0};
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(b.design, b.set, nullptr);
  opt::CamProblem& p = *made_p;
  const opt::SolveResult screened = ipopt(p, true);
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  const opt::SolveResult reference = opt::optimize(p, so);
  REQUIRE(reference.status.ok());
  INFO(screened.solver_message);
  CHECK(screened.solver_rows < static_cast<int>(p.rows().size()));
  CHECK(screened.max_violation <= so.constraint_tolerance);
  CHECK_NEAR(screened.final.objective, reference.final.objective, tol::kSameOptimumRel, tol::kSameOptimumRel);
}

TEST_CASE("ipopt row screening: an infeasible set is reported at the full-row solve's point and worst row",
          "[opt][ipopt]") {
  // 8.5 mm of lift needs more acceleration than 0.004 mm/deg^2 allows in this event (2 deg
  // grid: ipopt's restoration phase is long on an infeasible set)
  Bundled b = bundled("roller_finger_follower.toml", "passenger_car_intake.toml", 2.0);
  // the kinematic and Hertz limits only: the load rows' own local infeasible points are not
  // what this compares
  b.set.limits.min_separation_speed_rpm.reset();
  b.set.limits.min_spring_margin.reset();
  b.set.limits.min_film_thickness_um.reset();
  b.set.limits.acc_max_mm_per_deg2 = 0.004;
  b.set.limits.max_lift_mm = 9.0;
  b.set.limits.min_max_lift_mm = 8.5;
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(b.design, b.set, nullptr);
  opt::CamProblem& p = *made_p;
  opt::SolverOptions so;
  so.solver = opt::SolverKind::ipopt;
  so.feasibility_phase = false;  // the solvers' own points and worst rows (feasibility_test.cpp: the keys)
  const opt::SolveResult screened = opt::optimize(p, so);
  so.ipopt_screening = false;
  const opt::SolveResult full = opt::optimize(p, so);
  INFO(screened.status.str() << " / " << full.status.str());
  REQUIRE(screened.evaluated);
  REQUIRE(full.evaluated);
  CHECK(screened.status.code == StatusCode::infeasible);
  CHECK(full.status.code == StatusCode::infeasible);
  // the working set's own infeasible point would leave the rows outside it anywhere: the
  // screened run ends with the solve on every row, so it names the same conflict
  CHECK(screened.solver_rows == full.solver_rows);
  CHECK(screened.status.where == full.status.where);
  CHECK_REL(screened.max_violation, full.max_violation, tol::kSameInfeasiblePointRel);
}
