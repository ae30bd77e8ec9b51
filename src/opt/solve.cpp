#include "camopt/opt/solve.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "backends.hpp"

namespace camopt::opt {

namespace detail {

bool CachedProblem::at(const double* x, bool gradients) noexcept {
  const int n = problem_.variables();
  if (valid_ && (!gradients || eval_.have_gradients) && std::equal(x, x + n, x_.begin())) return status_.ok();
  ++evaluations_;
  // an exception is kept as the evaluation's status: the callers are C callbacks
  try {
    x_.assign(x, x + n);
    status_ = problem_.evaluate(x_, eval_, gradients);
  } catch (const NumericalError& e) {
    status_ = e.status();
  } catch (const std::exception& e) {
    status_ = {StatusCode::no_convergence, std::string("the evaluation failed: ") + e.what(), ""};
  } catch (...) {
    status_ = {StatusCode::no_convergence, "the evaluation failed with an unknown exception", ""};
  }
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

namespace detail {

void ProgressReporter::begin(const std::string& phase) noexcept {
  if (!callback_) return;
  try {
    phase_ = phase;
  } catch (...) {
    callback_ = nullptr;
    return;
  }
  last_ = -1.0;
  send(SolverProgress::Event::begin, 0, 0.0, 0.0);
}

void ProgressReporter::iteration(int iteration, double objective, double violation, bool throttled) noexcept {
  if (!callback_ || (throttled && !due())) return;
  last_ = elapsed();
  send(SolverProgress::Event::iteration, iteration, objective, violation);
}

void ProgressReporter::end(int iteration, double objective, double violation) noexcept {
  send(SolverProgress::Event::end, iteration, objective, violation);
}

bool ProgressReporter::stopped() noexcept {
  if (stopped_ || stop_ == nullptr) return stopped_;
  try {
    stopped_ = (*stop_)();
  } catch (...) {
    stopped_ = true;
  }
  return stopped_;
}

bool ProgressReporter::due() const noexcept { return last_ < 0.0 || elapsed() - last_ >= kProgressInterval; }

double ProgressReporter::elapsed() const noexcept {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
}

void ProgressReporter::send(SolverProgress::Event event, int iteration, double objective, double violation) noexcept {
  if (!callback_) return;
  try {
    SolverProgress p;
    p.event = event;
    p.phase = phase_;
    p.iteration = iteration;
    p.objective = objective;
    p.violation = std::max(0.0, violation);
    p.elapsed_s = elapsed();
    (*callback_)(p);
  } catch (...) {
    callback_ = nullptr;  // a callback that throws is not called again
  }
}

double violation(const Evaluation& e) {
  double v = 0.0;
  if (e.g.size() > 0) v = std::max(v, e.g.maxCoeff());
  if (e.equality.size() > 0) v = std::max(v, e.equality.cwiseAbs().maxCoeff());
  return v;
}

}  // namespace detail

namespace {

using detail::violation;
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

// the largest normalised violation a design may keep and still count as feasible
double feasibility_tolerance(const SolverOptions& options) { return std::max(options.constraint_tolerance, 1e-6); }

// the end of an nlopt phase, with the values finish() evaluated
void end_phase(detail::ProgressReporter& progress, const SolveResult& r) {
  if (r.evaluated) progress.end(r.evaluations, r.final.objective, r.max_violation);
  else progress.end(r.evaluations, HUGE_VAL, HUGE_VAL);
}

// multi-start slsqp: `start`, then halton points in the box about it; the best feasible
// result wins, else the least infeasible
void run_global(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start0,
                detail::ProgressReporter& progress, SolveResult& result) {
  const int n = problem.variables();
  const int starts = std::max(1, options.starts);
  const double tol = feasibility_tolerance(options);
  SolveResult best;
  bool have = false;
  int iterations = 0, evaluations = 0;
  for (int s = 0; s < starts && !progress.stopped(); ++s) {
    std::vector<double> start = start0;
    if (s > 0) {
      static constexpr int primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71,
                                       73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151};
      for (int j = 0; j < n; ++j) {
        const auto jj = static_cast<std::size_t>(j);
        const double h = halton(s, primes[j % 36]) - 0.5;
        const double span = 0.3 * (problem.upper()[jj] - problem.lower()[jj]);
        start[jj] = std::clamp(start[jj] + h * span, problem.lower()[jj], problem.upper()[jj]);
      }
    }
    SolveResult r;
    detail::run_nlopt(problem, options, SolverKind::slsqp, start, r, progress,
                      "global start " + std::to_string(s + 1) + " of " + std::to_string(starts) + " (slsqp)");
    iterations += r.iterations;
    evaluations += r.evaluations;
    if (r.u.empty()) {
      progress.end(r.evaluations, HUGE_VAL, HUGE_VAL);
      continue;
    }
    finish(problem, options, r);
    end_phase(progress, r);
    if (!r.evaluated) continue;
    const bool feasible = r.max_violation <= tol;
    const bool best_feasible = have && best.max_violation <= tol;
    if (!have || (feasible && !best_feasible) ||
        (feasible == best_feasible &&
         (feasible ? r.final.objective < best.final.objective : r.max_violation < best.max_violation))) {
      best = std::move(r);
      have = true;
    }
  }
  result = std::move(best);
  result.iterations = iterations;
  result.evaluations = evaluations;
  result.solver_message = "multi-start slsqp, " + std::to_string(starts) + " starts; best: " + result.solver_message;
}

// the chosen solver from `start`, its result evaluated and its status settled
void run_solver(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start,
                detail::ProgressReporter& progress, const std::string& note, SolveResult& result) {
  if (options.solver == SolverKind::ipopt) detail::run_ipopt(problem, options, start, result, progress);
  else if (options.solver != SolverKind::global)
    detail::run_nlopt(problem, options, options.solver, start, result, progress, to_string(options.solver) + note);
  else run_global(problem, options, start, progress, result);
  const bool nlopt_phase = options.solver != SolverKind::ipopt && options.solver != SolverKind::global;
  if (result.u.empty()) {
    if (result.status.ok()) result.status = {StatusCode::no_convergence, "the solver returned no design", ""};
    if (nlopt_phase) progress.end(result.evaluations, HUGE_VAL, HUGE_VAL);
    return;
  }
  const Status backend = result.status;
  result.status = Status::success();
  finish(problem, options, result);
  if (result.status.ok() && !backend.ok()) result.status = backend;
  if (nlopt_phase) end_phase(progress, result);
}

bool found_feasible(const SolveResult& r, const SolverOptions& options) {
  return !r.u.empty() && r.evaluated && r.max_violation <= feasibility_tolerance(options);
}

// "limits.acc_max_mm_per_deg2 = 0.02 mm/deg^2 (best achievable 0.0215)"
std::string describe(const ConflictingConstraint& c) {
  std::string s = c.key + " = " + format_value(c.limit, 6) + " " + c.unit;
  if (!std::isfinite(c.best_achievable)) return s + " (another conflict remains)";
  s += std::string(c.nearest ? " (best achievable " : " (achievable ") + format_value(c.best_achievable, 6);
  return s + (c.alone_suffices ? ")" : " with this conflict's other limits; another conflict remains)");
  return s;
}

// the infeasible status in the user's words: the conflicting keys, from the feasibility phase
Status conflict_status(const InfeasibilityReport& d, const SolveResult& r) {
  std::string keys, list;
  for (const ConflictingConstraint& c : d.conflicts) {
    keys += (keys.empty() ? "" : ", ") + c.key;
    list += (list.empty() ? "" : "; ") + describe(c);
  }
  std::ostringstream m;
  if (d.conflicts.empty()) {
    m << "no lift of [event] stays open between its ramps and returns to its closing ramp within the "
         "coefficient bound (set.coefficient_bound_mm_per_deg2), whatever the limits";
    keys = "[event]";
  } else {
    m << "no design meets these limits together: " << list
      << ". a best achievable value is the nearest setting of that limit alone at which every other limit can be met";
  }
  if (r.evaluated) m << "; the solver's design misses by " << format_value(r.max_violation * 100.0, 3) << " %";
  m << "; solver: " << r.solver_message;
  return {StatusCode::infeasible, m.str(), keys};
}

// a run without a feasible design: the feasibility phase names the conflict, or finds a
// feasible design to run the solver again from
void explain(CamProblem& problem, const SolverOptions& options, detail::ProgressReporter& progress,
             SolveResult& result) {
  InfeasibilityReport& d = result.infeasibility;
  if (Status st = detail::diagnose(problem, options, progress, d); !st.ok()) {
    result.status.message += "; the feasibility phase failed: " + st.str();
    return;
  }
  if (d.infeasible) {
    result.status = conflict_status(d, result);
    return;
  }
  // the limits do not conflict: the solver again, from the feasibility phase's design
  SolveResult again;
  run_solver(problem, options, d.feasible_u, progress, " (from the feasibility phase's design)", again);
  again.iterations += result.iterations;
  again.evaluations += result.evaluations + d.evaluations;
  again.infeasibility = d;
  const std::string first = result.solver_message;
  if (found_feasible(again, options)) {
    result = std::move(again);
    result.solver_message += "; from the feasibility phase's design (from the initial design: " + first + ")";
    return;
  }
  result.status = {StatusCode::no_convergence,
                   "the solver found no feasible design, though the limits do not conflict (the feasibility phase "
                   "found a design that meets every one); solver: " + first + "; from that design: " +
                       again.solver_message,
                   ""};
}

}  // namespace

SolveResult optimize(CamProblem& problem, const SolverOptions& options) {
  detail::ProgressReporter progress(options);
  SolveResult result;
  run_solver(problem, options, problem.start(), progress, "", result);
  if (options.feasibility_phase && !progress.stopped() && !found_feasible(result, options))
    explain(problem, options, progress, result);
  result.seconds = progress.elapsed();
  return result;
}

}  // namespace camopt::opt
