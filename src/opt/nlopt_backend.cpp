// NLopt (C api) around a CamProblem: SLSQP, MMA (closure through AUGLAG_EQ), COBYLA.
// a failed evaluation forces the run to stop (nlopt_force_stop); nothing is thrown.
#include <nlopt.h>

#include <cmath>

#include "backends.hpp"

namespace camopt::opt::detail {

namespace {

struct Context {
  CachedProblem* cache = nullptr;
  nlopt_opt opt = nullptr;  // the outer optimiser (force stop)
  bool failed = false;
};

bool ok_at(Context& c, const double* x, bool gradients) {
  bool ok = false;
  try {
    ok = c.cache->at(x, gradients);
  } catch (...) {
    ok = false;
  }
  if (!ok) {
    c.failed = true;
    nlopt_force_stop(c.opt);
  }
  return ok;
}

double objective(unsigned n, const double* x, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (!ok_at(c, x, grad != nullptr)) return HUGE_VAL;
  const Evaluation& e = c.cache->eval();
  if (grad)
    for (unsigned j = 0; j < n; ++j) grad[j] = e.gradient(j);
  return e.objective;
}

void inequalities(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (!ok_at(c, x, grad != nullptr)) {
    for (unsigned i = 0; i < m; ++i) result[i] = HUGE_VAL;
    return;
  }
  const Evaluation& e = c.cache->eval();
  for (unsigned i = 0; i < m; ++i) {
    result[i] = e.g(i);
    if (grad)
      for (unsigned j = 0; j < n; ++j) grad[i * n + j] = e.jacobian(i, j);
  }
}

void equalities(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  CamProblem& p = c.cache->problem();
  for (unsigned i = 0; i < m; ++i) {
    double v = -p.equality_rhs()(i);
    for (unsigned j = 0; j < n; ++j) {
      v += p.equality_matrix()(i, j) * x[j];
      if (grad) grad[i * n + j] = p.equality_matrix()(i, j);
    }
    result[i] = v;
  }
}

const char* describe(nlopt_result r) {
  switch (r) {
    case NLOPT_SUCCESS: return "success";
    case NLOPT_STOPVAL_REACHED: return "stop value reached";
    case NLOPT_FTOL_REACHED: return "converged (objective tolerance)";
    case NLOPT_XTOL_REACHED: return "converged (variable tolerance)";
    case NLOPT_MAXEVAL_REACHED: return "maximum number of evaluations reached";
    case NLOPT_MAXTIME_REACHED: return "time limit reached";
    case NLOPT_FAILURE: return "generic failure";
    case NLOPT_INVALID_ARGS: return "invalid arguments";
    case NLOPT_OUT_OF_MEMORY: return "out of memory";
    case NLOPT_ROUNDOFF_LIMITED: return "roundoff limited";
    case NLOPT_FORCED_STOP: return "stopped after a failed evaluation";
    default: return "unknown result";
  }
}

}  // namespace

void run_nlopt(CamProblem& problem, const SolverOptions& options, SolverKind algorithm, const std::vector<double>& start,
               SolveResult& result) {
  const unsigned n = static_cast<unsigned>(problem.variables());
  const unsigned m = static_cast<unsigned>(problem.rows().size());
  CachedProblem cache(problem);
  Context ctx;
  ctx.cache = &cache;

  nlopt_algorithm alg = NLOPT_LD_SLSQP;
  if (algorithm == SolverKind::mma) alg = NLOPT_AUGLAG_EQ;
  if (algorithm == SolverKind::cobyla) alg = NLOPT_LN_COBYLA;
  nlopt_opt opt = nlopt_create(alg, n);
  nlopt_opt local = nullptr;
  ctx.opt = opt;
  if (algorithm == SolverKind::mma) {
    local = nlopt_create(NLOPT_LD_MMA, n);
    nlopt_set_ftol_rel(local, options.tolerance);
    nlopt_set_xtol_rel(local, options.tolerance);
    nlopt_set_maxeval(local, options.max_iterations);
    nlopt_set_local_optimizer(opt, local);
  }
  nlopt_set_lower_bounds(opt, problem.lower().data());
  nlopt_set_upper_bounds(opt, problem.upper().data());
  nlopt_set_min_objective(opt, objective, &ctx);
  const std::vector<double> tol_g(m, options.constraint_tolerance), tol_h(2, 1e-12);
  if (m > 0) nlopt_add_inequality_mconstraint(opt, m, inequalities, &ctx, tol_g.data());
  nlopt_add_equality_mconstraint(opt, 2, equalities, &ctx, tol_h.data());
  nlopt_set_ftol_rel(opt, options.tolerance);
  nlopt_set_xtol_rel(opt, options.tolerance);
  nlopt_set_maxeval(opt, options.max_iterations);
  nlopt_set_maxtime(opt, options.time_limit_s);
  if (algorithm == SolverKind::cobyla) {
    std::vector<double> step(n, 0.05);
    nlopt_set_initial_step(opt, step.data());
  }

  std::vector<double> x = start;
  double f = 0.0;
  const nlopt_result r = nlopt_optimize(opt, x.data(), &f);
  result.u = x;
  result.evaluations = cache.evaluations();
  result.iterations = nlopt_get_numevals(opt);
  result.solver_message = std::string("nlopt ") + to_string(algorithm) + ": " + describe(r);
  if (ctx.failed) result.solver_message += "; failed evaluation: " + cache.status().str();
  const bool converged = r == NLOPT_SUCCESS || r == NLOPT_FTOL_REACHED || r == NLOPT_XTOL_REACHED;
  result.status = converged ? Status::success() : Status{StatusCode::no_convergence, result.solver_message, ""};
  if (local) nlopt_destroy(local);
  nlopt_destroy(opt);
}

}  // namespace camopt::opt::detail
