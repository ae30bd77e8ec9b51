#include "camopt/opt/solve.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "backends.hpp"

namespace camopt::opt {

namespace detail {

bool CachedProblem::at(const double* x, bool gradients) {
  const int n = problem_.variables();
  if (valid_ && (!gradients || eval_.have_gradients) && std::equal(x, x + n, x_.begin())) return status_.ok();
  x_.assign(x, x + n);
  ++evaluations_;
  status_ = problem_.evaluate(x_, eval_, gradients);
  valid_ = true;
  // a non-finite value is a failed evaluation, never handed to a solver
  if (status_.ok() && (!std::isfinite(eval_.objective) || !eval_.g.allFinite() ||
                       (gradients && (!eval_.gradient.allFinite() || !eval_.jacobian.allFinite()))))
    status_ = {StatusCode::no_convergence, "the objective or a constraint is not finite at this design", ""};
  return status_.ok();
}

}  // namespace detail

const char* to_string(SolverKind s) {
  switch (s) {
    case SolverKind::ipopt: return "ipopt";
    case SolverKind::slsqp: return "slsqp";
    case SolverKind::mma: return "mma";
    case SolverKind::cobyla: return "cobyla";
    case SolverKind::global: return "global";
  }
  return "?";
}

SolverKind parse_solver(const std::string& name) {
  for (SolverKind s : {SolverKind::ipopt, SolverKind::slsqp, SolverKind::mma, SolverKind::cobyla, SolverKind::global})
    if (name == to_string(s)) return s;
  throw InputError("--solver: unknown solver '" + name + "' (allowed: ipopt, slsqp, mma, cobyla, global)");
}

namespace {

double violation(const Evaluation& e) {
  double v = 0.0;
  if (e.g.size() > 0) v = std::max(v, e.g.maxCoeff());
  if (e.equality.size() > 0) v = std::max(v, e.equality.cwiseAbs().maxCoeff());
  return v;
}

// radical inverse in base b (Halton sequence)
double halton(int index, int base) {
  double f = 1.0, r = 0.0;
  for (int i = index; i > 0; i /= base) {
    f /= base;
    r += f * (i % base);
  }
  return r;
}

void finish(CamProblem& problem, const SolverOptions& options, SolveResult& r) {
  Status st = problem.evaluate(r.u, r.final, true);
  r.evaluated = st.ok();
  if (!st.ok()) {
    r.status = st;
    return;
  }
  r.max_violation = violation(r.final);
  if (r.max_violation > std::max(options.constraint_tolerance, 1e-6)) {
    // the worst constraint names the conflict
    Eigen::Index worst = 0;
    std::string what = "closure (the lift does not return to the closing ramp)";
    const double eq = r.final.equality.size() > 0 ? r.final.equality.cwiseAbs().maxCoeff() : 0.0;
    if (r.final.g.size() > 0 && r.final.g.maxCoeff() >= eq) {
      r.final.g.maxCoeff(&worst);
      const ConstraintRow& row = problem.rows()[static_cast<std::size_t>(worst)];
      std::ostringstream os;
      os << to_string(row.kind) << " at cam " << row.cam_deg << " deg";
      what = os.str();
    }
    std::ostringstream m;
    m << "no design satisfies every constraint: the largest violation is " << r.max_violation * 100.0
      << " % of its limit (" << what << "); solver: " << r.solver_message;
    r.status = {StatusCode::infeasible, m.str(), what};
  }
}

}  // namespace

SolveResult optimize(CamProblem& problem, const SolverOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  SolveResult result;
  if (options.solver == SolverKind::ipopt) {
    detail::run_ipopt(problem, options, problem.start(), result);
  } else if (options.solver != SolverKind::global) {
    detail::run_nlopt(problem, options, options.solver, problem.start(), result);
  } else {
    // multi-start slsqp: the initial design, then halton points in the box about it
    const int n = problem.variables();
    SolveResult best;
    bool have = false;
    int iterations = 0, evaluations = 0;
    for (int s = 0; s < std::max(1, options.starts); ++s) {
      std::vector<double> start = problem.start();
      if (s > 0) {
        static constexpr int primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71,
                                         73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151};
        for (int j = 0; j < n; ++j) {
          const double h = halton(s, primes[j % 36]) - 0.5;
          const double span = 0.3 * (problem.upper()[static_cast<std::size_t>(j)] - problem.lower()[static_cast<std::size_t>(j)]);
          start[static_cast<std::size_t>(j)] =
              std::clamp(start[static_cast<std::size_t>(j)] + h * span, problem.lower()[static_cast<std::size_t>(j)],
                         problem.upper()[static_cast<std::size_t>(j)]);
        }
      }
      SolveResult r;
      detail::run_nlopt(problem, options, SolverKind::slsqp, start, r);
      iterations += r.iterations;
      evaluations += r.evaluations;
      if (r.u.empty()) continue;
      finish(problem, options, r);
      const double tol = std::max(options.constraint_tolerance, 1e-6);
      if (!r.evaluated) continue;
      const bool feasible = r.max_violation <= tol;
      const bool best_feasible = have && best.max_violation <= tol;
      if (!have || (feasible && !best_feasible) ||
          (feasible == best_feasible && (feasible ? r.final.objective < best.final.objective
                                                  : r.max_violation < best.max_violation))) {
        best = std::move(r);
        have = true;
      }
    }
    result = std::move(best);
    result.iterations = iterations;
    result.evaluations = evaluations;
    result.solver_message = "multi-start slsqp, " + std::to_string(std::max(1, options.starts)) + " starts; best: " +
                            result.solver_message;
  }
  if (result.u.empty()) {
    if (result.status.ok()) result.status = {StatusCode::no_convergence, "the solver returned no design", ""};
  } else {
    const Status backend = result.status;
    result.status = Status::success();
    finish(problem, options, result);
    if (result.status.ok() && !backend.ok()) result.status = backend;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace camopt::opt
