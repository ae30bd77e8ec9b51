// Ipopt 3.11 TNLP around a CamProblem (Wächter & Biegler, Math. Prog. 106 (2006) 25-57).
// g = (closure A u - b, inequalities); bounds [0, 0] and (-inf, 0]. no exception leaves a
// callback: every callback catches and reports failure to Ipopt.
#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "backends.hpp"

namespace camopt::opt::detail {

namespace {

using Ipopt::Index;
using Ipopt::Number;

class CamTnlp : public Ipopt::TNLP {
 public:
  CamTnlp(CamProblem& p, const std::vector<double>& start, double time_limit, bool hessian)
      : cache_(p), start_(start), time_limit_(time_limit), hessian_(hessian), t0_(std::chrono::steady_clock::now()) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    CamProblem& p = cache_.problem();
    n = p.variables();
    m = neq() + static_cast<Index>(p.rows().size());
    nnz_jac_g = neq() * n + static_cast<Index>(p.jacobian_pattern().size());
    nnz_h_lag = hessian_ ? n * (n + 1) / 2 : 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    CamProblem& p = cache_.problem();
    for (Index j = 0; j < n; ++j) {
      x_l[j] = p.lower()[static_cast<std::size_t>(j)];
      x_u[j] = p.upper()[static_cast<std::size_t>(j)];
    }
    for (Index i = 0; i < m; ++i) {
      g_l[i] = i < neq() ? 0.0 : -2e19;
      g_u[i] = 0.0;
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    if (init_x)
      for (Index j = 0; j < n; ++j) x[j] = start_[static_cast<std::size_t>(j)];
    return true;
  }

  bool eval_f(Index, const Number* x, bool, Number& f) override {
    if (!guarded(x, false)) return false;
    f = cache_.eval().objective;
    return true;
  }

  bool eval_grad_f(Index n, const Number* x, bool, Number* grad) override {
    if (!guarded(x, true)) return false;
    for (Index j = 0; j < n; ++j) grad[j] = cache_.eval().gradient(j);
    return true;
  }

  bool eval_g(Index, const Number* x, bool, Index m, Number* g) override {
    if (!guarded(x, false)) return false;
    const Evaluation& e = cache_.eval();
    const Index ne = neq();
    for (Index i = 0; i < ne; ++i) g[i] = e.equality(i);
    for (Index i = ne; i < m; ++i) g[i] = e.g(i - ne);
    return true;
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* values) override {
    CamProblem& p = cache_.problem();
    const auto& pattern = p.jacobian_pattern();
    if (values == nullptr) {
      Index k = 0;
      for (Index r = 0; r < neq(); ++r)
        for (Index j = 0; j < n; ++j, ++k) {
          rows[k] = r;
          cols[k] = j;
        }
      for (const auto& [r, j] : pattern) {
        rows[k] = r + neq();
        cols[k] = j;
        ++k;
      }
      return true;
    }
    if (!guarded(x, true)) return false;
    const Evaluation& e = cache_.eval();
    Index k = 0;
    for (Index r = 0; r < neq(); ++r)
      for (Index j = 0; j < n; ++j) values[k++] = p.equality_matrix()(r, j);
    for (const auto& [r, j] : pattern) values[k++] = e.jacobian(r, j);
    return true;
  }

  // the objective's hessian (lower triangle, dense); the constraints' curvature is left out
  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index, const Number*, bool, Index, Index* rows,
              Index* cols, Number* values) override {
    if (!hessian_) return false;
    Index k = 0;
    if (values == nullptr) {
      for (Index i = 0; i < n; ++i)
        for (Index j = 0; j <= i; ++j, ++k) {
          rows[k] = i;
          cols[k] = j;
        }
      return true;
    }
    if (!guarded(x, false)) return false;
    const Eigen::MatrixXd h = cache_.problem().objective_hessian();
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j <= i; ++j) values[k++] = obj_factor * h(i, j);
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number, Number, Number, Number, Number, Number, Number,
                             Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    iterations_ = iter;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count() < time_limit_;
  }

  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status_ = status;
    x_.assign(x, x + n);
  }

  CachedProblem cache_;
  std::vector<double> start_, x_;
  Ipopt::SolverReturn status_ = Ipopt::INTERNAL_ERROR;
  int iterations_ = 0;
  double time_limit_;
  bool hessian_ = false;
  std::chrono::steady_clock::time_point t0_;

 private:
  Index neq() { return static_cast<Index>(cache_.problem().equality_matrix().rows()); }
  bool guarded(const Number* x, bool gradients) {
    try {
      return cache_.at(x, gradients);
    } catch (...) {
      return false;
    }
  }
};

const char* describe(Ipopt::SolverReturn s) {
  switch (s) {
    case Ipopt::SUCCESS: return "optimal solution found";
    case Ipopt::MAXITER_EXCEEDED: return "maximum number of iterations exceeded";
    case Ipopt::CPUTIME_EXCEEDED: return "time limit exceeded";
    case Ipopt::STOP_AT_TINY_STEP: return "stopped at a tiny step";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT: return "stopped at an acceptable point";
    case Ipopt::LOCAL_INFEASIBILITY: return "converged to a point of local infeasibility";
    case Ipopt::USER_REQUESTED_STOP: return "stopped: time limit";
    case Ipopt::DIVERGING_ITERATES: return "iterates diverging";
    case Ipopt::RESTORATION_FAILURE: return "restoration phase failed";
    case Ipopt::ERROR_IN_STEP_COMPUTATION: return "error in step computation";
    case Ipopt::INVALID_NUMBER_DETECTED: return "invalid number detected";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM: return "too few degrees of freedom";
    case Ipopt::INVALID_OPTION: return "invalid option";
    case Ipopt::OUT_OF_MEMORY: return "out of memory";
    default: return "internal error";
  }
}

}  // namespace

void run_ipopt(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start, SolveResult& result) {
  Ipopt::SmartPtr<CamTnlp> nlp = new CamTnlp(problem, start, options.time_limit_s, options.ipopt_objective_hessian);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", std::getenv("CAMOPT_IPOPT_PRINT") ? 5 : 0);
  app->Options()->SetStringValue("sb", "yes");
  // CAMOPT_IPOPT_PRINT: ipopt's iteration log and where its time goes (profiling)
  if (std::getenv("CAMOPT_IPOPT_PRINT")) app->Options()->SetStringValue("print_timing_statistics", "yes");
  app->Options()->SetStringValue("hessian_approximation", options.ipopt_objective_hessian ? "exact" : "limited-memory");
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
  app->Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  app->Options()->SetIntegerValue("limited_memory_max_history", 20);
  app->Options()->SetNumericValue("bound_push", 1e-6);
  app->Options()->SetNumericValue("bound_frac", 1e-6);
  if (app->Initialize() != Ipopt::Solve_Succeeded) {
    result.status = {StatusCode::no_convergence, "Ipopt could not be initialised", ""};
    return;
  }
  app->OptimizeTNLP(nlp);
  result.u = nlp->x_;
  result.iterations = nlp->iterations_;
  result.evaluations = nlp->cache_.evaluations();
  result.solver_message = std::string("ipopt: ") + describe(nlp->status_);
  if (!nlp->cache_.status().ok() && nlp->status_ != Ipopt::SUCCESS)
    result.solver_message += "; last failed evaluation: " + nlp->cache_.status().str();
  const bool converged = nlp->status_ == Ipopt::SUCCESS || nlp->status_ == Ipopt::STOP_AT_ACCEPTABLE_POINT;
  result.status = converged ? Status::success()
                            : Status{StatusCode::no_convergence, result.solver_message, ""};
}

}  // namespace camopt::opt::detail
