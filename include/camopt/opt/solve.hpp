#pragma once
// run a CamProblem through a solver backend:
//   ipopt   interior point (Ipopt 3.11 TNLP): exact first derivatives, sparse jacobian,
//           the objective's hessian or a limited-memory quasi-newton one (IpoptHessian);
//           solved on a screened working set of the rows, grown until every row holds
//   slsqp   NLopt sequential quadratic programming (Kraft 1988), exact gradients
//   mma     NLopt method of moving asymptotes (Svanberg 2002); the closure equalities go
//           through NLopt's augmented lagrangian (AUGLAG_EQ) around MMA
//   cobyla  NLopt derivative-free linear approximations (Powell 1994)
//   global  multi-start: SLSQP from the initial design and from points of a Halton
//           sequence spread over the variable box about it; the best feasible result wins
// no exception crosses a solver callback: a failing evaluation rejects the step (Ipopt)
// or stops the run (NLopt) and is reported.
// a run that ends without a feasible design goes through the feasibility phase
// (feasibility.hpp): it names the conflicting limits, the same for every solver.
#include <functional>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/opt/feasibility.hpp"
#include "camopt/opt/problem.hpp"

namespace camopt::opt {

enum class SolverKind { ipopt, slsqp, mma, cobyla, global };
const char* to_string(SolverKind s);
// InputError "--solver: unknown solver 'x' (allowed: ...)"
SolverKind parse_solver(const std::string& name);

enum class IpoptHessian { automatic, limited_memory, objective };

/// \brief a solver's progress, reported to SolverOptions::progress
struct SolverProgress {
  enum class Event { begin, iteration, end };
  /// \brief a phase begins, goes on, or ends (its final values)
  Event event = Event::iteration;
  /// \brief "ipopt round 2 (812 of 2020 rows)", "slsqp", "global start 3 of 6",
  /// "feasibility: every limit elastic", ...
  std::string phase;
  /// \brief within the phase: ipopt iterations, nlopt evaluations
  int iteration = 0;
  /// \brief the phase's objective (feasibility phase: the sum of the slacks)
  double objective = 0.0;
  /// \brief largest normalised violation of the rows the phase holds (0: none)
  double violation = 0.0;
  /// \brief wall time since opt::optimize (or diagnose_infeasibility) began [s]
  double elapsed_s = 0.0;
};

struct SolverOptions {
  SolverKind solver = SolverKind::ipopt;
  int max_iterations = 3000;       // ipopt iterations / nlopt evaluations
  double tolerance = 1e-9;         // relative optimality tolerance
  double constraint_tolerance = 1e-8;  // on the normalised constraints (fraction of each limit)
  int starts = 6;                  // global: number of starts, the initial design included
  double time_limit_s = 300.0;
  // ipopt's hessian of the lagrangian: limited_memory = quasi-newton (L-BFGS); objective = the
  // objective's own (gauss-newton) hessian with the constraints' curvature left out
  // (CamProblem::objective_hessian); automatic = objective for a conventional cam (whose lift is
  // linear in u: faster, bench/README.md), limited_memory for a swing cam
  IpoptHessian ipopt_hessian = IpoptHessian::automatic;
  // ipopt: solve on a working set of the rows near their limits, re-solving with the rows
  // found violated at the end until every row holds (ipopt_backend.cpp); false: every row
  bool ipopt_screening = true;
  // called at the begin and end of every phase (ipopt working-set round, nlopt run, global
  // start, feasibility solve) and while it runs: every ipopt iteration, nlopt evaluations at
  // most every kProgressInterval s. called from inside the solvers' callbacks: an exception
  // it throws is caught there and ends the reports (never the solve)
  std::function<void(const SolverProgress&)> progress;
  // asked at every ipopt iteration, nlopt evaluation and between phases: true stops the run
  // (ipopt's user stop, nlopt's forced stop), no later phase starts and the feasibility phase
  // is skipped; the result is then the run's as it stood. an exception it throws counts as true
  std::function<bool()> stop_requested;
  // a run without a feasible design goes through the feasibility phase (feasibility.hpp)
  bool feasibility_phase = true;
};

// [s] least time between two nlopt progress reports within a phase
inline constexpr double kProgressInterval = 0.05;

struct SolveResult {
  Status status;                   // ok, no_convergence or infeasible (naming the conflicting keys)
  std::vector<double> u;           // final variables
  Evaluation final;                // f, g at u
  int iterations = 0;              // ipopt iterations, nlopt: evaluations
  int evaluations = 0;             // objective evaluations
  double seconds = 0.0;
  double max_violation = 0.0;      // largest normalised constraint violation (0: feasible)
  bool evaluated = false;          // `final` holds a successful evaluation at u
  std::string solver_message;      // the backend's own status
  int solver_rows = 0;             // ipopt: inequality rows in its last working set
  int rounds = 1;                  // ipopt: solves over a growing working set
  // the feasibility phase, when the solver found no feasible design (diagnosed = false: not run);
  // when it found one the solver ran again from it (solver_message says so)
  InfeasibilityReport infeasibility;
};

SolveResult optimize(CamProblem& problem, const SolverOptions& options);

}  // namespace camopt::opt
