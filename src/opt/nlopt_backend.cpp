// NLopt (C api) around a CamProblem: SLSQP and COBYLA take the closure equalities as
// they are; MMA, which has no equality constraints, runs in the null space of the closure
// (u = u_p + N z, N orthonormal, the variable bounds become linear inequalities).
// a failed evaluation forces the run to stop (nlopt_force_stop); nothing is thrown.
// progress is reported from the objective's callback, at most every kProgressInterval; the
// caller ends the phase once it has evaluated the result (no evaluation here: the contact
// model's warm starts would make the next solve differ at round-off).
#include <nlopt.h>

#include <Eigen/Dense>

#include <cmath>

#include "backends.hpp"

namespace camopt::opt::detail {

namespace {

struct Context {
  CachedProblem* cache = nullptr;
  ProgressReporter* progress = nullptr;
  nlopt_opt opt = nullptr;  // the optimiser (force stop)
  bool failed = false;
  // null-space runs: u = particular + basis z
  bool reduced = false;
  Eigen::VectorXd particular;
  Eigen::MatrixXd basis;
  std::vector<double> u;
};

// the evaluation at x (the cache keeps a failure's status, an exception's message included);
// a failure stops the run
bool ok_at(Context& c, const double* x, bool gradients) noexcept {
  const bool ok = c.cache->at(x, gradients);
  if (!ok) {
    c.failed = true;
    nlopt_force_stop(c.opt);
  }
  return ok;
}

// the objective's callback: the point's progress report, when one is due
void report(Context& c) noexcept {
  if (!c.progress->enabled() || !c.progress->due()) return;
  const Evaluation& e = c.cache->eval();
  c.progress->iteration(c.cache->evaluations(), e.objective, violation(e), true);
}

double objective(unsigned n, const double* x, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (!ok_at(c, x, grad != nullptr)) return HUGE_VAL;
  report(c);
  if (c.progress->stopped()) nlopt_force_stop(c.opt);
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

// ---- null-space form (mma) ----
const double* full_point(Context& c, const double* z) {
  const Eigen::Map<const Eigen::VectorXd> zv(z, c.basis.cols());
  const Eigen::VectorXd u = c.particular + c.basis * zv;
  c.u.assign(u.data(), u.data() + u.size());
  return c.u.data();
}

double reduced_objective(unsigned nz, const double* z, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (!ok_at(c, full_point(c, z), grad != nullptr)) return HUGE_VAL;
  report(c);
  const Evaluation& e = c.cache->eval();
  if (grad) Eigen::Map<Eigen::VectorXd>(grad, nz) = c.basis.transpose() * e.gradient;
  return e.objective;
}

// the problem's inequalities, then u - upper <= 0 and lower - u <= 0
void reduced_inequalities(unsigned m, double* result, unsigned nz, const double* z, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  CamProblem& p = c.cache->problem();
  const unsigned n = static_cast<unsigned>(p.variables());
  const unsigned mg = m - 2 * n;
  const double* u = full_point(c, z);
  if (!ok_at(c, u, grad != nullptr)) {
    for (unsigned i = 0; i < m; ++i) result[i] = HUGE_VAL;
    return;
  }
  const Evaluation& e = c.cache->eval();
  for (unsigned i = 0; i < mg; ++i) result[i] = e.g(i);
  for (unsigned j = 0; j < n; ++j) {
    result[mg + j] = u[j] - p.upper()[j];
    result[mg + n + j] = p.lower()[j] - u[j];
  }
  if (grad) {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> g(grad, m, nz);
    g.topRows(mg) = e.jacobian * c.basis;
    g.middleRows(mg, n) = c.basis;
    g.bottomRows(n) = -c.basis;
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
               SolveResult& result, ProgressReporter& progress, const std::string& phase) {
  const unsigned n = static_cast<unsigned>(problem.variables());
  const unsigned m = static_cast<unsigned>(problem.rows().size());
  CachedProblem cache(problem);
  Context ctx;
  ctx.cache = &cache;
  ctx.progress = &progress;

  const unsigned neq = static_cast<unsigned>(problem.equality_matrix().rows());
  const bool reduced = algorithm == SolverKind::mma && neq > 0;
  nlopt_algorithm alg = algorithm == SolverKind::mma      ? NLOPT_LD_MMA
                        : algorithm == SolverKind::cobyla ? NLOPT_LN_COBYLA
                                                          : NLOPT_LD_SLSQP;
  std::vector<double> x = start;
  unsigned dim = n;
  if (reduced) {
    // closure A u = b: u = u_p + N z with N an orthonormal basis of the null space of A
    const Eigen::MatrixXd& a = problem.equality_matrix();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a.transpose());
    const Eigen::MatrixXd q = qr.householderQ();
    ctx.reduced = true;
    ctx.basis = q.rightCols(n - neq);
    ctx.particular = a.transpose() * (a * a.transpose()).ldlt().solve(problem.equality_rhs());
    const Eigen::Map<const Eigen::VectorXd> u0(start.data(), n);
    const Eigen::VectorXd z0 = ctx.basis.transpose() * (u0 - ctx.particular);
    x.assign(z0.data(), z0.data() + z0.size());
    dim = n - neq;
  }
  nlopt_opt opt = nlopt_create(alg, dim);
  ctx.opt = opt;
  if (reduced) {
    // |z| <= |u - u_p| <= the diameter of the variable box
    double diameter = 0.0;
    for (unsigned j = 0; j < n; ++j) diameter += std::pow(problem.upper()[j] - problem.lower()[j], 2);
    const std::vector<double> lo(dim, -std::sqrt(diameter)), hi(dim, std::sqrt(diameter));
    nlopt_set_lower_bounds(opt, lo.data());
    nlopt_set_upper_bounds(opt, hi.data());
    nlopt_set_min_objective(opt, reduced_objective, &ctx);
    const std::vector<double> tol(m + 2 * n, options.constraint_tolerance);
    nlopt_add_inequality_mconstraint(opt, m + 2 * n, reduced_inequalities, &ctx, tol.data());
    // the dual subproblem has one variable per constraint: its default tolerance (1e-14)
    // costs seconds per outer iteration with ~10^3 constraints for no gain in the result
    nlopt_set_param(opt, "dual_ftol_rel", 1e-9);
  } else {
    nlopt_set_lower_bounds(opt, problem.lower().data());
    nlopt_set_upper_bounds(opt, problem.upper().data());
    nlopt_set_min_objective(opt, objective, &ctx);
    const std::vector<double> tol_g(m, options.constraint_tolerance), tol_h(neq, 1e-12);
    if (m > 0) nlopt_add_inequality_mconstraint(opt, m, inequalities, &ctx, tol_g.data());
    if (neq > 0) nlopt_add_equality_mconstraint(opt, neq, equalities, &ctx, tol_h.data());
  }
  // the lift-matching objective is ill-conditioned in the acceleration coefficients (a
  // double integral): stop on the objective's change three orders below the tolerance
  nlopt_set_ftol_rel(opt, 1e-3 * options.tolerance);
  nlopt_set_xtol_rel(opt, options.tolerance);
  nlopt_set_maxeval(opt, options.max_iterations);
  nlopt_set_maxtime(opt, options.time_limit_s);
  if (algorithm == SolverKind::cobyla) {
    std::vector<double> step(n, 0.05);
    nlopt_set_initial_step(opt, step.data());
  }

  double f = 0.0;
  progress.begin(phase);
  const nlopt_result r = nlopt_optimize(opt, x.data(), &f);
  result.u = reduced ? std::vector<double>(full_point(ctx, x.data()), full_point(ctx, x.data()) + n) : x;
  result.evaluations = cache.evaluations();
  const Status failure = cache.status();
  result.iterations = nlopt_get_numevals(opt);
  result.solver_message = std::string("nlopt ") + to_string(algorithm) + ": " + describe(r);
  if (ctx.failed) result.solver_message += "; failed evaluation: " + failure.str();
  const bool converged = r == NLOPT_SUCCESS || r == NLOPT_FTOL_REACHED || r == NLOPT_XTOL_REACHED;
  result.status = converged ? Status::success() : Status{StatusCode::no_convergence, result.solver_message, ""};
  nlopt_destroy(opt);
}

}  // namespace camopt::opt::detail
