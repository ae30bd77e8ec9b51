#pragma once
// solver backends behind opt::optimize (solve.cpp); not public
#include "camopt/opt/solve.hpp"

namespace camopt::opt::detail {

// evaluation cache shared by the backends: solvers ask for f, g and their derivatives in
// separate calls at the same point
class CachedProblem {
 public:
  explicit CachedProblem(CamProblem& p) : problem_(p) {}
  // evaluates at x unless it is the cached point (with gradients if asked); false on a
  // failed evaluation (status() says why)
  bool at(const double* x, bool gradients);
  const Evaluation& eval() const { return eval_; }
  const Status& status() const { return status_; }
  CamProblem& problem() { return problem_; }
  int evaluations() const { return evaluations_; }

 private:
  CamProblem& problem_;
  std::vector<double> x_;
  Evaluation eval_;
  Status status_;
  bool valid_ = false;
  int evaluations_ = 0;
};

// fill result.u / iterations / solver_message and a status for a backend run from start
void run_ipopt(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start, SolveResult& result);
void run_nlopt(CamProblem& problem, const SolverOptions& options, SolverKind algorithm, const std::vector<double>& start,
               SolveResult& result);

}  // namespace camopt::opt::detail
