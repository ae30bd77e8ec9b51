#pragma once
// shared pieces of the optimisation tests: a CamProblem built through its factory, a
// failing build failing the test with its status named
#include <catch2/catch.hpp>
#include <memory>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/opt/problem.hpp"

namespace camopt::opt_test {

// opt::CamProblem::create, required to succeed
inline std::unique_ptr<opt::CamProblem> make_problem(const DesignSpec& design, const opt::OptimizationSpec& set,
                                                     const PeriodicSpline* target_lift) {
  std::unique_ptr<opt::CamProblem> problem;
  const Status st = opt::CamProblem::create(design, set, target_lift, problem);
  INFO(st.str());
  REQUIRE(st.ok());
  return problem;
}

}  // namespace camopt::opt_test
