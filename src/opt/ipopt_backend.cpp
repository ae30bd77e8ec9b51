// Ipopt 3.11 TNLP around a CamProblem (Wächter & Biegler, Math. Prog. 106 (2006) 25-57).
// g = (closure A u - b, inequalities); bounds [0, 0] and (-inf, 0]. no exception leaves a
// callback: an evaluation's failure, an exception's message included, is kept by the cache
// (CachedProblem::at) and reported to Ipopt as a failed callback. every iteration is reported
// to SolverOptions::progress from intermediate_callback, every working-set round is a phase.
#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "backends.hpp"

namespace camopt::opt::detail {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// one ipopt row: an inequality of CamProblem::rows(), or two of them at one grid angle that
// are affine in one another with opposite gradients as one two-sided row (pair_rows)
struct IpRow {
  int row;       // the inequality (index into CamProblem::rows())
  double lower;  // lower bound on its g (-2e19: none)
};

// distance past the nearer bound of an ipopt row, normalised (<= 0: both rows met). the
// carrying row has the larger gradient, so this bounds the partner's own g too (|a| <= 1)
double excess(const IpRow& r, const Evaluation& e) {
  const double g = e.g(static_cast<Eigen::Index>(r.row));
  return std::max(g, r.lower - g);
}

// one ipopt row per inequality, except that two rows at one grid angle, affine in one
// another with opposite gradients (acc_max / acc_min, the two jerk rows, lift_max /
// lift_nonnegative, a roller's radius_min / concave_radius) become one two-sided row: g1 <= 0 and g2 = a g1 + b <= 0 (a < 0) is
// -b / a <= g1 <= 0. ipopt's time goes into factorising its KKT system (MUMPS), one row per
// constraint: this drops a quarter of them on a conventional cam. e: an evaluation with gradients
std::vector<IpRow> pair_rows(const CamProblem& p, const Evaluation* e) {
  const auto& rows = p.rows();
  std::vector<IpRow> ip_rows;
  std::vector<char> taken(rows.size(), 0);
  const bool can_pair = !p.is_swing() && e != nullptr;
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
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (taken[r]) continue;
    IpRow ip{static_cast<int>(r), -2e19};
    if (can_pair && family(rows[r].kind) != 0 && rows[r].grid >= 0) {
      const auto j1 = e->jacobian.row(static_cast<Eigen::Index>(r));
      const double n1 = j1.squaredNorm();
      for (std::size_t q = r + 1; q < rows.size() && rows[q].grid == rows[r].grid && n1 > 0; ++q) {
        if (taken[q] || family(rows[q].kind) != family(rows[r].kind)) continue;
        const auto j2 = e->jacobian.row(static_cast<Eigen::Index>(q));
        const double a = j2.dot(j1) / n1;
        if (!(a < 0) || (j2 - a * j1).cwiseAbs().maxCoeff() > 1e-12 * j2.cwiseAbs().maxCoeff()) continue;
        const double b = e->g(static_cast<Eigen::Index>(q)) - a * e->g(static_cast<Eigen::Index>(r));
        // the row with the larger gradient carries both (|a| <= 1): ipopt's feasibility
        // tolerance on it then holds for the other row too
        if (a >= -1.0) ip.lower = -b / a;
        else ip = {static_cast<int>(q), b};
        taken[q] = 1;
        break;
      }
    }
    ip_rows.push_back(ip);
  }
  return ip_rows;
}

// the TNLP over a working set of ipopt rows (all of them, or a screened subset); the
// multipliers of the last solve are kept per ipopt row for a warm start of the next
class CamTnlp : public Ipopt::TNLP {
 public:
  CamTnlp(CachedProblem& cache, std::vector<IpRow> all_rows, const std::vector<double>& start, double time_limit,
          bool hessian, ProgressReporter& progress)
      : cache_(cache),
        progress_(progress),
        all_(std::move(all_rows)),
        x_(start),
        lambda_all_(all_.size(), 0.0),
        time_limit_(time_limit),
        hessian_(hessian),
        t0_(std::chrono::steady_clock::now()) {}

  // the working set: indices into all_rows(), ascending
  void set_working(std::vector<int> working) {
    working_ = std::move(working);
    std::vector<int> slot(cache_.problem().rows().size(), -1);
    for (std::size_t k = 0; k < working_.size(); ++k)
      slot[static_cast<std::size_t>(all_[static_cast<std::size_t>(working_[k])].row)] = static_cast<int>(k);
    pattern_.clear();
    for (const auto& [r, j] : cache_.problem().jacobian_pattern())
      if (slot[static_cast<std::size_t>(r)] >= 0) pattern_.emplace_back(slot[static_cast<std::size_t>(r)], j);
  }
  const std::vector<IpRow>& all_rows() const { return all_; }
  const std::vector<int>& working() const { return working_; }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = cache_.problem().variables();
    m = neq() + static_cast<Index>(working_.size());
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
      g_l[i] = i < neq() ? 0.0 : ip_row(i).lower;
      g_u[i] = 0.0;
    }
    return true;
  }

  // x from the last solve (the start at first); with a warm start also its multipliers,
  // zero for the rows new to the working set
  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_l, Number* z_u, Index m,
                          bool init_lambda, Number* lambda) override {
    if (init_x)
      for (Index j = 0; j < n; ++j) x[j] = x_[static_cast<std::size_t>(j)];
    if (init_z) {
      if (z_l_.size() != static_cast<std::size_t>(n)) return false;
      for (Index j = 0; j < n; ++j) {
        z_l[j] = z_l_[static_cast<std::size_t>(j)];
        z_u[j] = z_u_[static_cast<std::size_t>(j)];
      }
    }
    if (init_lambda) {
      if (lambda_eq_.size() != static_cast<std::size_t>(neq())) return false;
      for (Index i = 0; i < m; ++i)
        lambda[i] = i < neq() ? lambda_eq_[static_cast<std::size_t>(i)]
                              : lambda_all_[static_cast<std::size_t>(working_[static_cast<std::size_t>(i - neq())])];
    }
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
    for (Index i = ne; i < m; ++i) g[i] = e.g(ip_row(i).row);
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
    for (const auto& [r, j] : pattern_) values[k++] = e.jacobian(ip_row(r + neq()).row, j);
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

  // the progress report: the objective and ipopt's own primal infeasibility of the working set
  // (inf_pr; asking ipopt for more would evaluate the problem, and the contact model's warm
  // starts would then make the solve differ at round-off)
  bool intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number obj_value, Number inf_pr, Number, Number, Number,
                             Number, Number, Number, Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    last_iterations_ = iter;
    if (progress_.enabled()) {
      last_objective_ = obj_value;
      last_violation_ = inf_pr;
      progress_.iteration(iter, last_objective_, last_violation_, false);
    }
    return !progress_.stopped() &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count() < time_limit_;
  }

  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number* z_l, const Number* z_u,
                         Index m, const Number*, const Number* lambda, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status_ = status;
    iterations_ += last_iterations_;
    round_iterations_ = last_iterations_;
    last_iterations_ = 0;
    x_.assign(x, x + n);
    z_l_.assign(z_l, z_l + n);
    z_u_.assign(z_u, z_u + n);
    lambda_eq_.assign(lambda, lambda + neq());
    for (Index i = neq(); i < m; ++i)
      lambda_all_[static_cast<std::size_t>(working_[static_cast<std::size_t>(i - neq())])] = lambda[i];
  }

  CachedProblem& cache_;
  ProgressReporter& progress_;
  std::vector<IpRow> all_;
  std::vector<int> working_;                  // indices into all_
  std::vector<std::pair<int, int>> pattern_;  // (working row, column)
  std::vector<double> x_, z_l_, z_u_, lambda_eq_, lambda_all_;
  Ipopt::SolverReturn status_ = Ipopt::INTERNAL_ERROR;
  int iterations_ = 0, last_iterations_ = 0, round_iterations_ = 0;
  double last_objective_ = 0.0, last_violation_ = 0.0;  // at the last intermediate_callback
  double time_limit_;
  bool hessian_ = false;
  std::chrono::steady_clock::time_point t0_;

 private:
  Index neq() { return static_cast<Index>(cache_.problem().equality_matrix().rows()); }
  const IpRow& ip_row(Index i) {
    return all_[static_cast<std::size_t>(working_[static_cast<std::size_t>(i - neq())])];
  }
  // the evaluation at x; a failure (its status, an exception's message included, kept by
  // the cache) is reported to Ipopt as a failed callback
  bool guarded(const Number* x, bool gradients) noexcept { return cache_.at(x, gradients); }
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

// row screening. ipopt's time goes into its KKT system, one row per constraint (MUMPS: the
// cost grows with the rows), and on a cam only the rows near a peak of their quantity can
// be active. the working set starts with the scalar rows, every kStride-th grid point (no
// stretch of the lift is left free) and the rows within kStartMargin of their limit at the
// start. after each solve every row is evaluated: the rows past the feasibility tolerance,
// their neighbours of the same kind within kNeighbours grid points and every row within
// kAddMargin of its limit join the working set, and the next solve starts from the last one's
// point and multipliers, until no row outside the working set is violated. the last round
// allowed takes every row. with an exact hessian the first round stops at kFirstRoundTolerance
// (its point only serves to find the active rows; ipopt's warm start does not shorten a
// second solve from a converged point); with L-BFGS, whose history each solve starts anew,
// it runs to the full tolerance.
constexpr int kStride = 8;
constexpr double kStartMargin = 0.1;
constexpr double kAddMargin = 0.05;
constexpr int kNeighbours = 4;
constexpr int kMaxRounds = 8;
constexpr double kFirstRoundTolerance = 1e-2;

std::vector<int> initial_working_set(const CamProblem& p, const std::vector<IpRow>& all, const Evaluation& e) {
  std::vector<int> w;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const ConstraintRow& row = p.rows()[static_cast<std::size_t>(all[k].row)];
    if (row.grid < 0 || row.grid % kStride == 0 || excess(all[k], e) > -kStartMargin) w.push_back(static_cast<int>(k));
  }
  return w;
}

// the working set grown at the evaluation e; false when no row outside it is past tolerance
bool grow_working_set(const CamProblem& p, const std::vector<IpRow>& all, const Evaluation& e, double tolerance,
                      std::vector<int>& working) {
  std::vector<char> in(all.size(), 0);
  for (int k : working) in[static_cast<std::size_t>(k)] = 1;
  // kinds (bit per ConstraintKind) violated within kNeighbours of each grid point
  std::vector<std::uint32_t> hot(p.grid_deg().size(), 0);
  bool violated = false;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const ConstraintRow& row = p.rows()[static_cast<std::size_t>(all[k].row)];
    if (in[k] || excess(all[k], e) <= tolerance) continue;
    violated = true;
    if (row.grid < 0) continue;
    const int lo = std::max(0, row.grid - kNeighbours);
    const int hi = std::min(static_cast<int>(hot.size()) - 1, row.grid + kNeighbours);
    for (int g = lo; g <= hi; ++g) hot[static_cast<std::size_t>(g)] |= 1u << static_cast<unsigned>(row.kind);
  }
  for (std::size_t k = 0; k < all.size(); ++k) {
    const ConstraintRow& row = p.rows()[static_cast<std::size_t>(all[k].row)];
    const bool near_violation = row.grid >= 0 && ((hot[static_cast<std::size_t>(row.grid)] >> static_cast<unsigned>(row.kind)) & 1u);
    if (!in[k] && (near_violation || excess(all[k], e) > -kAddMargin)) in[k] = 1;
  }
  working.clear();
  for (std::size_t k = 0; k < in.size(); ++k)
    if (in[k]) working.push_back(static_cast<int>(k));
  return violated;
}

// ipopt's options for a run (CAMOPT_IPOPT_PRINT, CAMOPT_IPOPT_OPTIONS: its log and an options file)
void configure(Ipopt::IpoptApplication& app, const SolverOptions& options, bool objective_hessian) {
  app.Options()->SetIntegerValue("print_level", std::getenv("CAMOPT_IPOPT_PRINT") ? 5 : 0);
  app.Options()->SetStringValue("sb", "yes");
  // CAMOPT_IPOPT_PRINT: ipopt's iteration log and where its time goes (profiling)
  if (std::getenv("CAMOPT_IPOPT_PRINT")) app.Options()->SetStringValue("print_timing_statistics", "yes");
  app.Options()->SetStringValue("hessian_approximation", objective_hessian ? "exact" : "limited-memory");
  app.Options()->SetNumericValue("tol", options.tolerance);
  app.Options()->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
  app.Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
  app.Options()->SetIntegerValue("max_iter", options.max_iterations);
  app.Options()->SetStringValue("mu_strategy", "adaptive");
  app.Options()->SetIntegerValue("limited_memory_max_history", 20);
  app.Options()->SetNumericValue("bound_push", 1e-6);
  app.Options()->SetNumericValue("bound_frac", 1e-6);
  // ipopt relaxes every bound by this times max(1, |bound|); the two-sided rows' lower bounds
  // reach -3: the default 1e-8 would let them miss by 3e-8, past the feasibility tolerance
  app.Options()->SetNumericValue("bound_relax_factor", 0.1 * options.constraint_tolerance);
  if (const char* extra = std::getenv("CAMOPT_IPOPT_OPTIONS")) app.Options()->SetStringValue("option_file_name", extra);
}

// the progress phase of a working-set round
std::string round_phase(int round, std::size_t working, std::size_t all, bool screening, bool restart) {
  if (!screening) return "ipopt (" + std::to_string(all) + " rows)";
  std::string phase = "ipopt round " + std::to_string(round);
  if (restart) return phase + " (every row, from the initial design)";
  return phase + " (" + std::to_string(working) + " of " + std::to_string(all) + " rows)";
}

}  // namespace

void run_ipopt(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start, SolveResult& result,
               ProgressReporter& progress) {
  const bool objective_hessian =
      options.ipopt_hessian == IpoptHessian::objective ||
      (options.ipopt_hessian == IpoptHessian::automatic && !problem.is_swing());
  CachedProblem cache(problem);
  const bool start_ok = cache.at(start.data(), true);
  Ipopt::SmartPtr<CamTnlp> nlp = new CamTnlp(cache, pair_rows(problem, start_ok ? &cache.eval() : nullptr), start,
                                             options.time_limit_s, objective_hessian, progress);
  const bool screening = options.ipopt_screening && start_ok;
  std::vector<int> working;
  auto take_every_row = [&] {
    working.resize(nlp->all_rows().size());
    for (std::size_t k = 0; k < working.size(); ++k) working[k] = static_cast<int>(k);
  };
  if (screening) working = initial_working_set(problem, nlp->all_rows(), cache.eval());
  else take_every_row();
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  configure(*app, options, objective_hessian);
  if (app->Initialize() != Ipopt::Solve_Succeeded) {
    result.status = {StatusCode::no_convergence, "Ipopt could not be initialised", ""};
    return;
  }
  const bool loose_first = screening && objective_hessian;
  if (loose_first) {
    app->Options()->SetNumericValue("tol", kFirstRoundTolerance);
    app->Options()->SetNumericValue("acceptable_tol", kFirstRoundTolerance);
  }
  int rounds = 0;
  bool restart = false;
  for (;;) {
    nlp->set_working(working);
    ++rounds;
    progress.begin(round_phase(rounds, working.size(), nlp->all_rows().size(), screening, restart));
    app->OptimizeTNLP(nlp);
    progress.end(nlp->round_iterations_, nlp->last_objective_, nlp->last_violation_);
    const bool solved = nlp->status_ == Ipopt::SUCCESS || nlp->status_ == Ipopt::STOP_AT_ACCEPTABLE_POINT;
    const bool out_of_time = nlp->status_ == Ipopt::USER_REQUESTED_STOP || nlp->status_ == Ipopt::MAXITER_EXCEEDED ||
                             nlp->status_ == Ipopt::CPUTIME_EXCEEDED;
    if (!solved) {
      if (!screening || out_of_time || working.size() == nlp->all_rows().size()) break;
      // the working set alone failed (locally infeasible): one solve on every row from the
      // start, so that the point reported, and its worst row, are those of the whole problem
      take_every_row();
      restart = true;
      nlp->x_ = start;
      app->Options()->SetStringValue("warm_start_init_point", "no");
      app->Options()->SetNumericValue("tol", options.tolerance);
      app->Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
      continue;
    }
    restart = false;
    if (!screening) break;
    const bool first_loose = loose_first && rounds == 1;
    if (!first_loose && working.size() == nlp->all_rows().size()) break;
    if (!cache.at(nlp->x_.data(), false)) break;
    if (!grow_working_set(problem, nlp->all_rows(), cache.eval(), options.constraint_tolerance, working) && !first_loose)
      break;
    if (rounds + 1 >= kMaxRounds) take_every_row();
    if (first_loose) {
      app->Options()->SetNumericValue("tol", options.tolerance);
      app->Options()->SetNumericValue("acceptable_tol", 1e3 * options.tolerance);
    }
    // warm start from the last solve's point and multipliers (zero for the new rows)
    app->Options()->SetStringValue("warm_start_init_point", "yes");
    app->Options()->SetNumericValue("warm_start_bound_push", 1e-6);
    app->Options()->SetNumericValue("warm_start_mult_bound_push", 1e-6);
  }
  result.u = nlp->x_;
  result.iterations = nlp->iterations_;
  result.evaluations = cache.evaluations();
  result.solver_rows = static_cast<int>(working.size());
  result.rounds = rounds;
  result.solver_message = std::string("ipopt: ") + describe(nlp->status_);
  if (screening)
    result.solver_message += " (" + std::to_string(working.size()) + " of " + std::to_string(nlp->all_rows().size()) +
                             " rows, " + std::to_string(rounds) + " rounds)";
  if (!cache.status().ok() && nlp->status_ != Ipopt::SUCCESS)
    result.solver_message += "; last failed evaluation: " + cache.status().str();
  const bool converged = nlp->status_ == Ipopt::SUCCESS || nlp->status_ == Ipopt::STOP_AT_ACCEPTABLE_POINT;
  result.status = converged ? Status::success()
                            : Status{StatusCode::no_convergence, result.solver_message, ""};
}

}  // namespace camopt::opt::detail
