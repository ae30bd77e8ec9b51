#pragma once
// solver backends behind opt::optimize (solve.cpp); not public
#include <chrono>

#include "camopt/opt/solve.hpp"

namespace camopt::opt::detail {

// SolverOptions::progress for one optimize() run: the phase under way, its clock, and the
// nlopt throttle. every call is noexcept: it runs inside the solvers' C callbacks; a callback
// that throws is not called again
class ProgressReporter {
 public:
  explicit ProgressReporter(const SolverOptions& options)
      : callback_(options.progress ? &options.progress : nullptr),
        stop_(options.stop_requested ? &options.stop_requested : nullptr),
        t0_(std::chrono::steady_clock::now()) {}
  bool enabled() const noexcept { return callback_ != nullptr; }
  void begin(const std::string& phase) noexcept;
  // every call (ipopt), or throttled to kProgressInterval (nlopt: throttled = true)
  void iteration(int iteration, double objective, double violation, bool throttled) noexcept;
  void end(int iteration, double objective, double violation) noexcept;
  // an nlopt report is due (the phase's first, or kProgressInterval after the last)
  bool due() const noexcept;
  double elapsed() const noexcept;
  // SolverOptions::stop_requested asked (once it says stop, stopped without asking again)
  bool stopped() noexcept;

 private:
  void send(SolverProgress::Event event, int iteration, double objective, double violation) noexcept;
  const std::function<void(const SolverProgress&)>* callback_;
  const std::function<bool()>* stop_;
  bool stopped_ = false;
  std::chrono::steady_clock::time_point t0_;
  std::string phase_;
  double last_ = -1.0;  // elapsed time of the phase's last iteration report (-1: none yet)
};

// evaluation cache shared by the backends: solvers ask for f, g and their derivatives in
// separate calls at the same point
class CachedProblem {
 public:
  explicit CachedProblem(CamProblem& p) : problem_(p) {}
  // evaluates at x unless it is the cached point (with gradients if asked); false on a
  // failed evaluation (status() says why, an exception's message included: nothing is thrown
  // into the solvers' callbacks)
  bool at(const double* x, bool gradients) noexcept;
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

// largest normalised violation of an evaluation: inequalities and closure
double violation(const Evaluation& e);

// fill result.u / iterations / solver_message and a status for a backend run from start;
// `phase` names the run in the progress reports. run_ipopt ends its phases itself; after
// run_nlopt the caller ends the phase with the values of its own evaluation of the result
void run_ipopt(CamProblem& problem, const SolverOptions& options, const std::vector<double>& start, SolveResult& result,
               ProgressReporter& progress);
void run_nlopt(CamProblem& problem, const SolverOptions& options, SolverKind algorithm, const std::vector<double>& start,
               SolveResult& result, ProgressReporter& progress, const std::string& phase);

// the feasibility phase (feasibility.cpp) reporting to `progress`
Status diagnose(CamProblem& problem, const SolverOptions& options, ProgressReporter& progress, InfeasibilityReport& out);

}  // namespace camopt::opt::detail
