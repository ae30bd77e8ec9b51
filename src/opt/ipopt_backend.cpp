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
      : cache_(p), start_(start), time_limit_(time_limit), hessian_(hessian), t0_(std::chrono::steady_clock::now()) {
    pair_rows();
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    CamProblem& p = cache_.problem();
    n = p.variables();
    (void)p;
    m = neq() + static_cast<Index>(ip_rows_.size());
    nnz_jac_g = neq() * n + static_cast<Index>(pattern_.size());
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
      g_l[i] = i < neq() ? 0.0 : ip_rows_[static_cast<std::size_t>(i - neq())].lower;
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
    for (Index i = ne; i < m; ++i) g[i] = e.g(ip_rows_[static_cast<std::size_t>(i - ne)].row);
    return true;
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* values) override {
    CamProblem& p = cache_.problem();
    if (values == nullptr) {
      Index k = 0;
      for (Index r = 0; r < neq(); ++r)
        for (Index j = 0; j < n; ++j, ++k) {
          rows[k] = r;
          cols[k] = j;
        }
      for (const auto& [r, j] : pattern_) {
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
    for (const auto& [r, j] : pattern_) values[k++] = e.jacobian(ip_rows_[static_cast<std::size_t>(r)].row, j);
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

  struct IpRow {
    int row;       // the inequality (index into CamProblem::rows())
    double lower;  // lower bound on its g (-2e19: none)
  };
  CachedProblem cache_;
  std::vector<double> start_, x_;
  std::vector<IpRow> ip_rows_;
  std::vector<std::pair<int, int>> pattern_;  // (ipopt inequality row, column)
  Ipopt::SolverReturn status_ = Ipopt::INTERNAL_ERROR;
  int iterations_ = 0;
  double time_limit_;
  bool hessian_ = false;
  std::chrono::steady_clock::time_point t0_;

 private:
  Index neq() { return static_cast<Index>(cache_.problem().equality_matrix().rows()); }

  // one ipopt row per inequality, except that two rows at one grid angle, affine in one
  // another with opposite gradients (acc_max / acc_min, the two jerk rows, lift_max /
  // lift_nonnegative, a roller's radius_min / concave_radius) become one two-sided row: g1 <= 0 and g2 = a g1 + b <= 0 (a < 0) is
  // -b / a <= g1 <= 0. ipopt's time goes into factorising its KKT system (MUMPS), one row per
  // constraint: this drops a quarter of them on a conventional cam.
  void pair_rows() {
    CamProblem& p = cache_.problem();
    const auto& rows = p.rows();
    ip_rows_.clear();
    std::vector<char> taken(rows.size(), 0);
    const bool can_pair = !p.is_swing() && guarded(start_.data(), true);
    // rows that are affine in one another wherever they are evaluated: the valve-motion rows
    // (linear in u), and the two radius rows of a roller (both affine in the pitch curvature)
    auto family = [](ConstraintKind k) {
      switch (k) {
        case ConstraintKind::acc_max:
        case ConstraintKind::acc_min:
        case ConstraintKind::jerk_max:
        case ConstraintKind::lift_max:
        case ConstraintKind::lift_nonnegative: return 1;
        case ConstraintKind::radius_min:
        case ConstraintKind::concave_radius: return 2;
        default: return 0;
      }
    };
    std::vector<int> slot(rows.size(), -1);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      if (taken[r]) continue;
      IpRow ip{static_cast<int>(r), -2e19};
      if (can_pair && family(rows[r].kind) != 0 && rows[r].grid >= 0) {
        const Evaluation& e = cache_.eval();
        const auto j1 = e.jacobian.row(static_cast<Eigen::Index>(r));
        const double n1 = j1.squaredNorm();
        for (std::size_t q = r + 1; q < rows.size() && rows[q].grid == rows[r].grid && n1 > 0; ++q) {
          if (taken[q] || family(rows[q].kind) != family(rows[r].kind)) continue;
          const auto j2 = e.jacobian.row(static_cast<Eigen::Index>(q));
          const double a = j2.dot(j1) / n1;
          if (!(a < 0) || (j2 - a * j1).cwiseAbs().maxCoeff() > 1e-12 * j2.cwiseAbs().maxCoeff()) continue;
          const double b = e.g(static_cast<Eigen::Index>(q)) - a * e.g(static_cast<Eigen::Index>(r));
          // the row with the larger gradient carries both (|a| <= 1): ipopt's feasibility
          // tolerance on it then holds for the other row too
          if (a >= -1.0) ip.lower = -b / a;
          else ip = {static_cast<int>(q), b};
          taken[q] = 1;
          break;
        }
      }
      slot[r] = static_cast<int>(ip_rows_.size());
      ip_rows_.push_back(ip);
    }
    pattern_.clear();
    for (const auto& [r, j] : p.jacobian_pattern())
      if (slot[static_cast<std::size_t>(r)] >= 0) pattern_.emplace_back(slot[static_cast<std::size_t>(r)], j);
  }
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
  const bool objective_hessian =
      options.ipopt_hessian == IpoptHessian::objective ||
      (options.ipopt_hessian == IpoptHessian::automatic && !problem.is_swing());
  Ipopt::SmartPtr<CamTnlp> nlp = new CamTnlp(problem, start, options.time_limit_s, objective_hessian);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", std::getenv("CAMOPT_IPOPT_PRINT") ? 5 : 0);
  app->Options()->SetStringValue("sb", "yes");
  // CAMOPT_IPOPT_PRINT: ipopt's iteration log and where its time goes (profiling)
  if (std::getenv("CAMOPT_IPOPT_PRINT")) app->Options()->SetStringValue("print_timing_statistics", "yes");
  app->Options()->SetStringValue("hessian_approximation", objective_hessian ? "exact" : "limited-memory");
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
  app->Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  app->Options()->SetIntegerValue("limited_memory_max_history", 20);
  app->Options()->SetNumericValue("bound_push", 1e-6);
  app->Options()->SetNumericValue("bound_frac", 1e-6);
  // ipopt relaxes every bound by this times max(1, |bound|); the two-sided rows' lower bounds
  // reach -3: the default 1e-8 would let them miss by 3e-8, past the feasibility tolerance
  app->Options()->SetNumericValue("bound_relax_factor", 0.1 * options.constraint_tolerance);
  if (const char* extra = std::getenv("CAMOPT_IPOPT_OPTIONS")) app->Options()->SetStringValue("option_file_name", extra);
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
