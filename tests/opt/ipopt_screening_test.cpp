// ipopt's row screening (ipopt_backend.cpp): solved on a working set of the rows near their
// limits, re-solved with the rows found violated, the result must be the optimum of every
// row: the same objective as ipopt on all rows (conventional cams) or as SLSQP on all rows
// (swing cam), with every row of the problem within the feasibility tolerance.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"

using namespace camopt;

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

// relative objective agreement of two solves of one problem (both reach the kkt point to
// the optimality tolerance 1e-9; 1e-7 leaves room for the conditioning of the active set)
constexpr double kObjectiveTolerance = 1e-7;

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
  CHECK(std::abs(screened.final.objective - full.final.objective) <=
        kObjectiveTolerance * std::max(1.0, std::abs(full.final.objective)));
}

}  // namespace

TEST_CASE("ipopt row screening: roller finger follower, the full-row optimum with every row met", "[opt][ipopt]") {
  const Bundled b = bundled("roller_finger_follower.toml", "passenger_car_intake.toml", 1.0);
  opt::CamProblem p(b.design, b.set, nullptr);
  check_same_optimum(p);
}

TEST_CASE("ipopt row screening: bucket tappet with a peak-stress objective, the full-row optimum", "[opt][ipopt]") {
  const Bundled b = bundled("bucket_tappet.toml", "high_speed_bucket.toml", 1.0);
  opt::CamProblem p(b.design, b.set, nullptr);
  check_same_optimum(p);
}

TEST_CASE("ipopt row screening: swing cam at three control positions, SLSQP's optimum on every row", "[opt][ipopt]") {
  Bundled b = bundled("cvvl_swing_cam.toml", "cvvl_swing_cam.toml", 1.0);
  b.set.cam = "swing";
  b.set.swing.positions = {0.0, 8.0, 16.0};
  opt::CamProblem p(b.design, b.set, nullptr);
  const opt::SolveResult screened = ipopt(p, true);
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  const opt::SolveResult reference = opt::optimize(p, so);
  REQUIRE(reference.status.ok());
  INFO(screened.solver_message);
  CHECK(screened.solver_rows < static_cast<int>(p.rows().size()));
  CHECK(screened.max_violation <= so.constraint_tolerance);
  CHECK(std::abs(screened.final.objective - reference.final.objective) <=
        kObjectiveTolerance * std::max(1.0, std::abs(reference.final.objective)));
}
