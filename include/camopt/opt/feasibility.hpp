#pragma once
// the feasibility phase: why a constraint set has no feasible design, told in the user's keys
// and independent of the solver that failed. the rows of CamProblem are grouped by the
// constraint-set key that sets their limit (limit_key); an elastic program
//   minimise sum_k s_k  subject to  g_r(u) <= s_k(r) (every row r of key k),  s_k >= 0,
//   closure A u = b, lower <= u <= upper, lift_nonnegative rows hard
// finds the least relaxation of every key at once; a deletion filter then keeps an
// irreducible infeasible subset of the keys (each key of it is needed for the conflict), and
// for each of its keys the least relaxation of that key alone (the others held) gives its best
// achievable value. every solve is NLopt SLSQP on exact gradients, from the initial design,
// so the answer does not depend on the solver that reported the conflict.
// J. W. Chinneck, Feasibility and Infeasibility in Optimization, Springer 2008: elastic
// programs (ch. 6) and the deletion filter for irreducible infeasible subsets (ch. 7).
#include <string>
#include <vector>

#include "camopt/core/error.hpp"

namespace camopt::opt {

class CamProblem;
struct SolverOptions;

/// \brief one limit of a conflict: the set is feasible without it, infeasible with it
struct ConflictingConstraint {
  /// \brief the constraint-set key as the user wrote it ("limits.min_max_lift_mm")
  std::string key;
  /// \brief unit of limit and best_achievable ("mm")
  std::string unit;
  /// \brief the limit as set (grinding_wheel_radius_mm: the wheel radius, positive)
  double limit = 0.0;
  /// \brief the nearest value of this limit at which the other limits can all be met [unit]
  double best_achievable = 0.0;
  /// \brief the quantity must stay at or below the limit (false: at or above)
  bool limit_is_max = true;
  /// \brief best_achievable holds every other limit of the set; false: another conflict
  /// remains, and best_achievable only holds the other limits of this conflict set
  bool alone_suffices = true;
  /// \brief best_achievable is the nearest such value; false: a value that can be achieved,
  /// a nearer one may exist (the key's rows are normalised by different references: the
  /// separation speed and spring margin of several contacts and springs, a flat face's Hertz
  /// row scaled by its radius, so the least normalised slack need not be the nearest value)
  bool nearest = true;
};

/// \brief the feasibility phase's answer
struct InfeasibilityReport {
  /// \brief the phase ran to its end
  bool diagnosed = false;
  /// \brief no design meets every row (as far as SLSQP finds from the initial design)
  bool infeasible = false;
  /// \brief an irreducible infeasible subset of the keys, in the order of CamProblem::rows()
  std::vector<ConflictingConstraint> conflicts;
  /// \brief the least sum of normalised slacks with every key elastic (0: feasible)
  double elastic_slack = 0.0;
  /// \brief a design that meets every row, when one was found (variables, as CamProblem)
  std::vector<double> feasible_u;
  /// \brief SLSQP solves and problem evaluations spent
  int solves = 0, evaluations = 0;
  /// \brief wall time of the phase [s]
  double seconds = 0.0;
};

/// the feasibility phase on the rows of `problem` (its objective is ignored). ok with
/// out.diagnosed set when every solve ran; a failed evaluation or the time limit
/// (options.time_limit_s) returns its status
[[nodiscard]] Status diagnose_infeasibility(CamProblem& problem, const SolverOptions& options,
                                            InfeasibilityReport& out);

}  // namespace camopt::opt
