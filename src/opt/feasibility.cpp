// the feasibility phase (feasibility.hpp): elastic programs on NLopt SLSQP, a deletion filter
// over the constraint-set keys, and each conflicting key's best achievable value.
// J. W. Chinneck, Feasibility and Infeasibility in Optimization, Springer 2008: the elastic
// program (ch. 6: one nonnegative slack per relaxed constraint, their sum minimised) and the
// deletion filter (ch. 7: drop a constraint for good when the set without it is still
// infeasible; what is left is an irreducible infeasible subset, IIS). here the "constraints"
// of the filter are the user's keys, each standing for all its rows over the grid.
// no exception crosses the NLopt callbacks: a failed evaluation stops the solve
// (nlopt_force_stop) and its status is returned.
#include "camopt/opt/feasibility.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "backends.hpp"

namespace camopt::opt {

namespace detail {

namespace {

// least evaluation budget of one solve of the phase, whatever SolverOptions::max_iterations
// asks of the optimisation (the elastic solves of the bundled sets take 3 to 60)
constexpr int kPhaseEvaluations = 1000;

// one constraint-set key and its rows
struct KeyRows {
  std::string key;
  ConstraintKind kind = ConstraintKind::acc_max;
  std::vector<int> rows;
};

// a key's part in one elastic program: left out, held (g <= 0), or relaxed (g <= s_k)
enum class Role : char { dropped, hard, elastic };

// the rows grouped by key, in the order of CamProblem::rows(); the rows of no key (the valve
// staying open: lift_nonnegative) are always held and go to `base`; peak_bound rows belong to
// the objective and are left out
std::vector<KeyRows> group_rows(const CamProblem& p, std::vector<int>& base) {
  std::vector<KeyRows> keys;
  for (std::size_t r = 0; r < p.rows().size(); ++r) {
    const ConstraintKind kind = p.rows()[r].kind;
    if (kind == ConstraintKind::peak_bound) continue;
    const char* key = limit_key(kind);
    if (key == nullptr) {
      base.push_back(static_cast<int>(r));
      continue;
    }
    auto it = std::find_if(keys.begin(), keys.end(), [&](const KeyRows& k) { return k.key == key; });
    if (it == keys.end()) it = keys.insert(keys.end(), KeyRows{key, kind, {}});
    it->rows.push_back(static_cast<int>(r));
  }
  return keys;
}

// one elastic program over x = (u, s): minimise sum s subject to the held rows, the closure
// and the variable bounds
struct Elastic {
  CachedProblem* cache = nullptr;
  ProgressReporter* progress = nullptr;
  nlopt_opt opt = nullptr;
  std::vector<int> rows;      // held rows (hard and elastic)
  std::vector<int> slack_of;  // per held row: its slack's index in s, -1 for a hard row
  int n = 0;
  int evaluations0 = 0;  // the shared cache's count when the solve began
  double tolerance = 1e-6;
  bool stop_when_feasible = false;
  bool failed = false;
  bool feasible = false;  // a point meeting every held row and the closure was evaluated
  std::vector<double> feasible_u;  // that point (sized before the solve: no allocation in a callback)
};

// largest violation at the cached evaluation: of the held rows (hard rows only when
// hard_only), and of the closure
double worst(const Elastic& c, const Evaluation& e, bool hard_only) {
  double v = e.equality.size() > 0 ? e.equality.cwiseAbs().maxCoeff() : 0.0;
  for (std::size_t i = 0; i < c.rows.size(); ++i)
    if (!hard_only || c.slack_of[i] < 0) v = std::max(v, e.g(c.rows[i]));
  return v;
}

// the evaluation at x (the cache keeps a failure's status, an exception's message included);
// a failure stops the run
bool ok_at(Elastic& c, const double* x, bool gradients) noexcept {
  const bool ok = c.cache->at(x, gradients);
  if (!ok) {
    c.failed = true;
    nlopt_force_stop(c.opt);
  }
  return ok;
}

// sum of the slacks; every point is checked: one that meets every held row ends a solve that
// only asks whether the rows can be met (a certificate of feasibility)
double elastic_objective(unsigned nx, const double* x, double* grad, void* data) {
  Elastic& c = *static_cast<Elastic*>(data);
  double f = 0.0;
  for (unsigned k = static_cast<unsigned>(c.n); k < nx; ++k) f += x[k];
  if (grad) {
    std::fill(grad, grad + c.n, 0.0);
    std::fill(grad + c.n, grad + nx, 1.0);
  }
  if (!ok_at(c, x, grad != nullptr)) return f;
  const double v = worst(c, c.cache->eval(), false);
  if (v <= c.tolerance && !c.feasible) {
    c.feasible = true;
    std::copy(x, x + c.n, c.feasible_u.begin());
    if (c.stop_when_feasible) nlopt_force_stop(c.opt);
  }
  if (c.progress->enabled() && c.progress->due())
    c.progress->iteration(c.cache->evaluations() - c.evaluations0, f, v, true);
  return f;
}

// held rows: g_r(u) - s_k(r) <= 0
void elastic_rows(unsigned m, double* result, unsigned nx, const double* x, double* grad, void* data) {
  Elastic& c = *static_cast<Elastic*>(data);
  if (!ok_at(c, x, grad != nullptr)) {
    std::fill(result, result + m, HUGE_VAL);
    return;
  }
  const Evaluation& e = c.cache->eval();
  if (grad) std::fill(grad, grad + static_cast<std::size_t>(m) * nx, 0.0);
  for (unsigned i = 0; i < m; ++i) {
    const int r = c.rows[i], k = c.slack_of[i];
    result[i] = e.g(r) - (k >= 0 ? x[c.n + k] : 0.0);
    if (!grad) continue;
    double* row = grad + static_cast<std::size_t>(i) * nx;
    for (int j = 0; j < c.n; ++j) row[j] = e.jacobian(r, j);
    if (k >= 0) row[c.n + k] = -1.0;
  }
}

// closure A u = b
void elastic_closure(unsigned m, double* result, unsigned nx, const double* x, double* grad, void* data) {
  Elastic& c = *static_cast<Elastic*>(data);
  CamProblem& p = c.cache->problem();
  for (unsigned i = 0; i < m; ++i) {
    double v = -p.equality_rhs()(i);
    for (int j = 0; j < c.n; ++j) v += p.equality_matrix()(i, j) * x[j];
    result[i] = v;
    if (!grad) continue;
    for (unsigned j = 0; j < nx; ++j)
      grad[i * nx + j] = static_cast<int>(j) < c.n ? p.equality_matrix()(i, static_cast<Eigen::Index>(j)) : 0.0;
  }
}

// what one elastic solve found
struct ElasticResult {
  std::vector<double> u;      // the feasible point found, else SLSQP's final point
  bool feasible = false;      // u meets every held row
  bool hard_met = false;      // u meets every hard row (the elastic ones may be relaxed)
  std::vector<double> slack;  // per key: its rows' largest violation at u (0: met)
};

// the phase: the problem, its keys, the options, the clock and the tallies
struct Phase {
  CamProblem& problem;
  const SolverOptions& options;
  ProgressReporter& progress;
  CachedProblem cache;
  std::vector<KeyRows> keys;
  std::vector<int> base;
  double tolerance = 1e-6;
  double deadline = 0.0;  // [s] on the progress clock
  int solves = 0;
};

// the rows an elastic program holds: the base rows and those of every key not dropped, each
// elastic key's with its slack; returns the key of each slack
std::vector<int> hold_rows(const Phase& ph, const std::vector<Role>& roles, Elastic& c) {
  std::vector<int> slack_key;
  for (int r : ph.base) {
    c.rows.push_back(r);
    c.slack_of.push_back(-1);
  }
  for (std::size_t k = 0; k < ph.keys.size(); ++k) {
    if (roles[k] == Role::dropped) continue;
    const int s = roles[k] == Role::elastic ? static_cast<int>(slack_key.size()) : -1;
    if (s >= 0) slack_key.push_back(static_cast<int>(k));
    for (int r : ph.keys[k].rows) {
      c.rows.push_back(r);
      c.slack_of.push_back(s);
    }
  }
  return slack_key;
}

// what the solve found at u: feasibility, the hard rows, each elastic key's slack
void read_result(const Phase& ph, const Elastic& c, const std::vector<int>& slack_key, const Evaluation& e,
                 ElasticResult& out) {
  out.feasible = worst(c, e, false) <= ph.tolerance;
  out.hard_met = worst(c, e, true) <= ph.tolerance;
  out.slack.assign(ph.keys.size(), 0.0);
  for (int key : slack_key) {
    double& s = out.slack[static_cast<std::size_t>(key)];
    for (int r : ph.keys[static_cast<std::size_t>(key)].rows) s = std::max(s, e.g(r));
  }
}

// solves the elastic program of `roles` by SLSQP from u = start, every slack at its key's
// largest violation there; stop_when_feasible ends it at the first point that meets every
// held row
Status solve_elastic(Phase& ph, const std::vector<Role>& roles, const std::vector<double>& start,
                     bool stop_when_feasible, const std::string& phase, ElasticResult& out) {
  CamProblem& p = ph.problem;
  const double remaining = ph.deadline - ph.progress.elapsed();
  const Status out_of_time = {StatusCode::no_convergence,
                              "the feasibility phase ran out of time (" + format_value(ph.options.time_limit_s, 4) + " s)",
                              ""};
  if (!(remaining > 0.0)) return out_of_time;
  Elastic c;
  c.cache = &ph.cache;
  c.progress = &ph.progress;
  c.n = p.variables();
  c.tolerance = ph.tolerance;
  c.stop_when_feasible = stop_when_feasible;
  c.feasible_u.resize(static_cast<std::size_t>(c.n));
  const std::vector<int> slack_key = hold_rows(ph, roles, c);
  if (!ph.cache.at(start.data(), false)) return ph.cache.status();
  std::vector<double> x(start.begin(), start.end());
  std::vector<double> lo(p.lower().begin(), p.lower().end()), hi(p.upper().begin(), p.upper().end());
  for (int key : slack_key) {
    double s = 0.0;
    for (int r : ph.keys[static_cast<std::size_t>(key)].rows) s = std::max(s, ph.cache.eval().g(r));
    x.push_back(s);
    lo.push_back(0.0);
    hi.push_back(HUGE_VAL);
  }
  const auto m = static_cast<unsigned>(c.rows.size());
  const auto neq = static_cast<unsigned>(p.equality_matrix().rows());
  nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, static_cast<unsigned>(x.size()));
  c.opt = opt;
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_min_objective(opt, elastic_objective, &c);
  const std::vector<double> tol_g(m, ph.options.constraint_tolerance), tol_h(neq, 1e-12);
  if (m > 0) nlopt_add_inequality_mconstraint(opt, m, elastic_rows, &c, tol_g.data());
  if (neq > 0) nlopt_add_equality_mconstraint(opt, neq, elastic_closure, &c, tol_h.data());
  nlopt_set_ftol_rel(opt, 1e-3 * ph.options.tolerance);
  nlopt_set_ftol_abs(opt, 1e-14);
  nlopt_set_xtol_rel(opt, ph.options.tolerance);
  nlopt_set_maxeval(opt, std::max(ph.options.max_iterations, kPhaseEvaluations));
  nlopt_set_maxtime(opt, remaining);
  ph.progress.begin(phase);
  double f = 0.0;
  c.evaluations0 = ph.cache.evaluations();
  const nlopt_result result = nlopt_optimize(opt, x.data(), &f);
  nlopt_destroy(opt);
  ++ph.solves;
  const int evaluations = ph.cache.evaluations() - c.evaluations0;
  // a solve cut short proves nothing, nor one whose evaluation failed: the phase fails
  // rather than call the keys conflicting
  const bool cut = result == NLOPT_MAXTIME_REACHED || result == NLOPT_MAXEVAL_REACHED;
  if ((cut || c.failed) && !(stop_when_feasible && c.feasible)) {
    ph.progress.end(evaluations, f, HUGE_VAL);
    if (c.failed) return ph.cache.status();
    if (result == NLOPT_MAXTIME_REACHED) return out_of_time;
    return {StatusCode::no_convergence, "the feasibility phase's solve '" + phase + "' reached its evaluation limit", ""};
  }
  out.u = c.feasible && stop_when_feasible ? c.feasible_u : std::vector<double>(x.begin(), x.begin() + c.n);
  if (!ph.cache.at(out.u.data(), false)) return ph.cache.status();
  read_result(ph, c, slack_key, ph.cache.eval(), out);
  ph.progress.end(evaluations, std::accumulate(out.slack.begin(), out.slack.end(), 0.0),
                  worst(c, ph.cache.eval(), false));
  return Status::success();
}

// a kept key's witness: a design that meets every other key of the candidates the filter had
// when it tried the key, and whether those were all the keys
struct Witness {
  std::vector<double> u;
  bool whole_set = false;
};

// the deletion filter: every key in turn, from the ones the elastic program left unrelaxed to
// the most relaxed, is left out for good when the candidates without it still conflict; a
// key kept gets the design that met the others
Status deletion_filter(Phase& ph, const ElasticResult& all, std::vector<int>& candidates,
                       std::vector<Witness>& witness) {
  candidates.resize(ph.keys.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  witness.assign(ph.keys.size(), Witness{});
  std::vector<int> order = candidates;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const double sa = all.slack[static_cast<std::size_t>(a)], sb = all.slack[static_cast<std::size_t>(b)];
    const bool za = sa <= ph.tolerance, zb = sb <= ph.tolerance;
    if (za != zb) return za;
    return !za && sa < sb;
  });
  for (int k : order) {
    std::vector<Role> roles(ph.keys.size(), Role::dropped);
    for (int c : candidates)
      if (c != k) roles[static_cast<std::size_t>(c)] = Role::elastic;
    ElasticResult r;
    if (Status st = solve_elastic(ph, roles, all.u, true, "feasibility: without " + ph.keys[static_cast<std::size_t>(k)].key, r);
        !st.ok())
      return st;
    if (r.feasible) witness[static_cast<std::size_t>(k)] = {r.u, candidates.size() == ph.keys.size()};
    else candidates.erase(std::find(candidates.begin(), candidates.end(), k));
  }
  return Status::success();
}

// the value of a key's quantity that its rows reach at the cached evaluation, in the user's
// terms: the largest over the rows for a maximum, the smallest for a minimum; for the two
// radius keys the binding row's (largest g): their rows give the cam radius on both sides,
// convex and concave (grinding_wheel_radius_mm: the smallest concave radius, positive)
double reached(const CamProblem& p, const Evaluation& e, const KeyRows& k) {
  if (k.kind == ConstraintKind::radius_min || k.kind == ConstraintKind::concave_radius) {
    int binding = k.rows.front();
    for (int r : k.rows)
      if (e.g(r) > e.g(binding)) binding = r;
    return k.kind == ConstraintKind::concave_radius ? -e.physical(binding) : e.physical(binding);
  }
  const bool upper = p.is_upper_limit(k.kind);
  double v = e.physical(k.rows.front());
  for (int r : k.rows) v = upper ? std::max(v, e.physical(r)) : std::min(v, e.physical(r));
  return v;
}

// a conflicting key's limit and its best achievable value: the least relaxation of that key
// alone, every other key of the set held (else, when they conflict among themselves, the other
// keys of the conflict), solved from a design that meets the held keys
Status best_achievable(Phase& ph, const ElasticResult& all, const std::vector<int>& conflict, int k,
                       const Witness& witness, ConflictingConstraint& out) {
  const KeyRows& key = ph.keys[static_cast<std::size_t>(k)];
  CamProblem& p = ph.problem;
  out.key = key.key;
  out.unit = p.unit_of(key.kind);
  const bool concave = key.kind == ConstraintKind::concave_radius;  // the wheel radius: -limit_of
  out.limit = concave ? -p.limit_of(key.kind) : p.limit_of(key.kind);
  out.limit_is_max = concave ? false : p.is_upper_limit(key.kind);
  out.nearest = !(key.kind == ConstraintKind::separation || key.kind == ConstraintKind::spring_margin ||
                  (key.kind == ConstraintKind::hertz_stress && !p.is_swing() &&
                   p.contact().follower_shape() == FollowerShape::flat));
  // can every other key be met? (known when the filter tried this key first)
  std::vector<double> start = witness.u;
  out.alone_suffices = witness.whole_set;
  if (!out.alone_suffices) {
    std::vector<Role> others(ph.keys.size(), Role::elastic);
    others[static_cast<std::size_t>(k)] = Role::dropped;
    ElasticResult r;
    if (Status st = solve_elastic(ph, others, all.u, true, "feasibility: every limit but " + key.key, r); !st.ok())
      return st;
    out.alone_suffices = r.feasible;
    if (r.feasible) start = r.u;
  }
  std::vector<Role> roles(ph.keys.size(), out.alone_suffices ? Role::hard : Role::dropped);
  for (int c : conflict) roles[static_cast<std::size_t>(c)] = Role::hard;
  roles[static_cast<std::size_t>(k)] = Role::elastic;
  ElasticResult r;
  if (Status st = solve_elastic(ph, roles, start, false, "feasibility: best " + key.key, r); !st.ok()) return st;
  // slsqp keeps the held rows from a start that meets them; should it lose them, the start
  // itself still shows a value that can be achieved
  if (!ph.cache.at((r.hard_met ? r.u : start).data(), false)) return ph.cache.status();
  out.best_achievable = reached(p, ph.cache.eval(), key);
  return Status::success();
}

}  // namespace

Status diagnose(CamProblem& problem, const SolverOptions& options, ProgressReporter& progress, InfeasibilityReport& out) {
  out = InfeasibilityReport{};
  const double t0 = progress.elapsed();
  Phase ph{problem, options, progress, CachedProblem(problem), {}, {}, std::max(options.constraint_tolerance, 1e-6),
           t0 + options.time_limit_s, 0};
  ph.keys = group_rows(problem, ph.base);
  auto finish = [&](Status st) {
    out.solves = ph.solves;
    out.evaluations = ph.cache.evaluations();
    out.seconds = progress.elapsed() - t0;
    return st;
  };
  // every key elastic: a design meeting every row ends the phase, else the least relaxation
  ElasticResult all;
  const std::vector<Role> every(ph.keys.size(), Role::elastic);
  if (Status st = solve_elastic(ph, every, problem.start(), true, "feasibility: every limit elastic", all); !st.ok())
    return finish(st);
  out.diagnosed = true;
  if (all.feasible) {
    out.feasible_u = all.u;
    return finish(Status::success());
  }
  out.infeasible = true;
  out.elastic_slack = std::accumulate(all.slack.begin(), all.slack.end(), 0.0);
  std::vector<int> conflict;
  std::vector<Witness> witness;
  if (Status st = deletion_filter(ph, all, conflict, witness); !st.ok()) {
    out.diagnosed = false;
    return finish(st);
  }
  for (int k : conflict) {
    ConflictingConstraint c;
    if (Status st = best_achievable(ph, all, conflict, k, witness[static_cast<std::size_t>(k)], c); !st.ok()) {
      out.diagnosed = false;
      return finish(st);
    }
    out.conflicts.push_back(std::move(c));
  }
  return finish(Status::success());
}

}  // namespace detail

Status diagnose_infeasibility(CamProblem& problem, const SolverOptions& options, InfeasibilityReport& out) {
  detail::ProgressReporter progress(options);
  return detail::diagnose(problem, options, progress, out);
}

}  // namespace camopt::opt
