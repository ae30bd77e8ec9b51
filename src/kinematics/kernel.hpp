#pragma once
// the kinematic kernel behind kin::solve (solver.hpp), shared by the files of its steps:
//   solve_point.cpp      one driver point: predictor, the plan step by step, guard, accept
//   closed_form.cpp      single connections solved in closed form (links, circle contacts,
//                        circle on a face, gears, racks)
//   implicit_block.cpp   blocks solved simultaneously: broyden, newton, the contact scan,
//                        and the taylor coefficients by implicit differentiation
//   offset_contact.cpp   a curve-circle contact as one equation in the curve parameter
//   contact_outputs.cpp  per-contact quantities of an accepted point
//   workspace.cpp        the workspace and its per-step blocks
//   solver.cpp           continuation from the drawing, step halving, the public entry points
// not installed: nothing outside src/kinematics includes it.
#include <algorithm>
#include <string>
#include <type_traits>

#include "camopt/core/units.hpp"
#include "branch_guard.hpp"
#include "workspace_state.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::kin::detail {

inline constexpr int max_newton_iterations = 40;
inline constexpr int max_broyden_iterations = 8;
inline constexpr double relative_tolerance = 1e-13;  // residual tolerance relative to the mechanism size
// step control (Workspace::trust_radius): a solved variable may move at most this far from
// its prediction. Distinct assembly branches are farther apart than this except next to a
// singular configuration (where the condition estimate grows), so a point within it is on
// the predicted branch; fine steps never come near it (their predictor error is < 1e-4 of it).
inline constexpr double trust_length_fraction = 0.02;  // [mm variables] of Mechanism::length_scale
inline constexpr double trust_angle_rad = 0.05;        // [rad variables] about 2.9 deg
inline constexpr double min_step_rad = 1e-6;  // smallest driver step of the halving [rad, or x length_scale mm]
inline constexpr double min_control_fraction = 1e-6;  // smallest control step, of the control move
// the taylor order every point is solved to, whatever is requested: the predictor and the
// step control depend on it (Request)
inline constexpr int continuation_order = 3;

inline double value_of(double x) { return x; }
template <int N>
double value_of(const Jet<N>& x) {
  return x.value();
}
template <int M>
double value_of(const Dual<M>& x) {
  return x.value();
}

// a number in a status message (6 significant digits)
inline std::string fmt(double v) { return format_value(v, 6); }

// "driver <angle> deg" or "driver <travel> mm" for a status's `where`
inline std::string driver_text(const Mechanism& m, double driver) {
  return m.driver_is_angle() ? "driver " + fmt(driver * 180.0 / pi) + " deg" : "driver " + fmt(driver) + " mm";
}

// "'a', 'b'": the names of a block's connections, for a status message
inline std::string connection_names(const Mechanism& m, const std::vector<int>& connections) {
  std::string names;
  for (int ci : connections) names += (names.empty() ? "'" : ", '") + m.connections[ci].name + "'";
  return names;
}

// the pose's values (its Taylor coefficients dropped)
template <int N>
Pose<double> pose_values(const Pose<Jet<N>>& p) {
  Pose<double> out;
  out.tx = p.tx.value();
  out.ty = p.ty.value();
  out.c = p.c.value();
  out.s = p.s.value();
  out.rx = p.rx;
  out.ry = p.ry;
  return out;
}

// residuals of a block at scalar type T; vars must hold every variable
template <class T, class Poses>
void block_residual(const Mechanism& m, const WorkspaceState::Block& b, const T* vars, const Poses& poses, T* scratch,
                    T* out) {
  int i = 0;
  for (int ci : b.connections) {
    const Connection& c = m.connections[ci];
    connection_residual(m, c, vars, poses, scratch);
    for (const auto& [eci, k] : b.equations)
      if (eci == ci) out[i++] = scratch[k];
  }
}
template <class T>
void block_residual(const Mechanism& m, const WorkspaceState::Block& b, const T* vars, const Eigen::Vector2d* pivots,
                    PoseCache<T>& cache, long point, T* scratch, T* out) {
  block_residual(m, b, vars, CachedPoses<T>{m, vars, pivots, cache, point, b.solving}, scratch, out);
}

// a plan step's block: its equations and unknowns (tangency_only: the contact parameters of
// a lash contact with the follower held at rest) and buffers (workspace.cpp)
WorkspaceState::Block make_block(const Mechanism& m, const SolveStep& step, bool tangency_only);

// forget every block's broyden inverse and jacobian history (workspace.cpp)
void drop_block_warm_starts(Workspace& ws);

// one driver point through the plan (solve_point.cpp is its top level)
class Kernel {
 public:
  // trust: check the point against the prediction (nullptr: accept any converged point);
  // smallest_step: the step from the last accepted point cannot be halved further
  Kernel(const Mechanism& m, Workspace& ws, const Request& rq, TrustOutcome* trust = nullptr,
         bool smallest_step = false)
      : m_(m), ws_(ws), st_(state(ws)), rq_(rq), trust_(trust), smallest_step_(smallest_step) {}

  // the plan step `step` is not solved: `node`'s variables are set from `vars` (see
  // solve_prescribed), the step's contact parameters keep their values
  void prescribe(int step, int node, const Jet3* vars) {
    prescribed_step_ = step;
    prescribed_node_ = node;
    prescribed_vars_ = vars;
  }

  // solve every variable at `driver` [rad or mm]; a rejected point (trust) returns success
  // with trust->rejected set
  Status run(double driver);

 private:
  // ---- solve_point.cpp: the steps of run() ----
  bool predict(double driver, bool check);
  void set_known_variables(double driver);
  Status solve_step(int step_index, double driver, bool fresh);
  void take_prescribed(const SolveStep& step);
  Status solve_implicit(int step_index, double driver, bool fresh);
  Status hold_open_lash(int step_index, double driver, bool& open);
  Status check_finite(double driver) const;
  bool guard(double driver);
  void accept(double driver);

  // ---- implicit_block.cpp ----
  double evaluate(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f);
  double jacobian(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f);
  template <int M>
  void jacobian_columns(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f, int first);
  bool broyden(WorkspaceState::Block& b, double tol);
  Status newton(WorkspaceState::Block& b, double tol, double driver);
  Status solve_values(WorkspaceState::Block& b, double driver);
  Status differentiate(WorkspaceState::Block& b, double driver);
  void scan_contact_parameters(const WorkspaceState::Block& b);
  void scan_two_curves(const Connection& c, const Pose<double>& pa, const Pose<double>& pb);
  void scan_curve_circle(const Connection& c, const Pose<double>& pa, const Pose<double>& pb);
  static void remember_jacobian(WorkspaceState::Block& b, double driver) {
    const int n = static_cast<int>(b.unknowns.size());
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        b.prev_jacobian(i, j) = b.last_jacobian(i, j);
        b.last_jacobian(i, j) = b.jacobian(i, j);
      }
    b.prev_driver = b.last_driver;
    b.last_driver = driver;
    b.jacobians = std::min(b.jacobians + 1, 2);
  }

  // ---- offset_contact.cpp ----
  template <int M>
  Status solve_offset_contact(WorkspaceState::Block& b, double driver, bool& solved);

  // ---- closed_form.cpp ----
  Status closed_form(const SolveStep& step, int step_index, double driver);
  Status distance_step(const SolveStep& step, int step_index, double driver, Jet3& q, bool& held);
  Status line_step(const SolveStep& step, int step_index, double driver, Jet3& q, bool& held);
  template <class T>
  Status distance_closed_form(const SolveStep& step, const T* vars, T& q, double driver, const Eigen::Vector2d& pin_u,
                              int k, const Eigen::Vector2d& pin_k, double L);
  template <class T>
  Status line_closed_form(const SolveStep& step, const T* vars, T& s_out, T& u_out, double& gap_at_rest,
                          double driver);
  // an open lash gap: the step's output node held at its rest
  void hold_at_rest(const SolveStep& step, int step_index, double gap);

  // ---- contact_outputs.cpp ----
  void contact_outputs(int step_index);

  // ---- shared ----
  void finish_block(const WorkspaceState::Block& b) {
    for (int v : b.unknowns)
      if (m_.variables[v].node >= 0) st_.invalidate_pose(m_.variables[v].node);
  }
  void set_constant(int var, double v) {
    st_.values[var] = v;
    ws_.vars[var] = Jet3(v);
  }
  void note_margin(double margin) { ws_.toggle_margin = std::min(ws_.toggle_margin, margin); }
  // the pose of a node solved before this step: on jets through the point's jet-3 pose
  // cache (the contact outputs then truncate it instead of computing it again)
  template <class T>
  Pose<T> known_pose(int n, const T* vars) const {
    if constexpr (std::is_same_v<T, Jet3>) {
      if (vars == ws_.vars.data())
        return CachedPoses<Jet3>{m_, vars, st_.pivots.data(), st_.poses3, st_.point_id, st_.no_node_solving}.get(n);
    }
    return node_pose(m_, n, vars, st_.pivots.data());
  }
  double tolerance() const { return relative_tolerance * m_.length_scale; }

  const Mechanism& m_;
  Workspace& ws_;       // the results
  WorkspaceState& st_;  // the buffers behind them
  const Request& rq_;
  TrustOutcome* trust_;
  bool smallest_step_;
  int prescribed_step_ = -1, prescribed_node_ = -1;
  const Jet3* prescribed_vars_ = nullptr;
};

}  // namespace camopt::kin::detail
