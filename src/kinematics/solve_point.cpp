// one driver point (Kernel::run): the warm start predicted from the last points, the known
// variables set, the plan walked step by step (closed forms, lash, the one-equation contact
// form, blocks solved simultaneously), then the trust check and branch guard, and the
// bookkeeping of an accepted point.
#include <cmath>

#include "kernel.hpp"

namespace camopt::kin::detail {

Status Kernel::run(double driver) {
  const bool fresh = st_.history == 0;
  ++st_.point_id;  // every cached pose is stale
  const bool check = trust_ != nullptr && st_.history >= 1;
  // predictor for the warm start; a step beyond its reach is rejected before any solve
  if (st_.history >= 1 && !predict(driver, check)) return Status::success();
  // known variables: driver and control-set nodes
  set_known_variables(driver);
  // the plan, from the driver outward
  ws_.max_condition = 0.0;
  ws_.toggle_margin = 1.0;
  for (std::size_t si = 0; si < m_.plan.size(); ++si)
    if (Status st = solve_step(static_cast<int>(si), driver, fresh); !st.ok()) return st;
  // every variable finite
  if (Status st = check_finite(driver); !st.ok()) return st;
  // a converged point off the predicted branch is rejected: the step is halved
  if (check && !guard(driver)) return Status::success();
  // the requested outputs and the history for the next predictor
  accept(driver);
  return Status::success();
}

// the warm start: the taylor series (continuation_order) from the last point, with a quartic
// term from the change of the cubic coefficient over the last two; its highest terms
// estimate its error (Workspace::predicted_error). false: rejected (check) because that
// error exceeds a trust radius
bool Kernel::predict(double driver, bool check) {
  const int nv = static_cast<int>(m_.variables.size());
  const double h = driver - st_.prev_driver, step = st_.prev_driver - st_.prev2_driver;
  const bool two = st_.history >= 2 && step != 0.0;
  // quartic term from the change of the cubic coefficient: d c_3 / dt = 4 c_4
  const double quartic = two ? h * h * h * h / (4.0 * step) : 0.0;
  const double cubic = h * h * h;
  const Jet3* jets = st_.prev_jets.data();
  const Jet3* jets2 = st_.prev2_jets.data();
  const double* prev = st_.prev_values.data();
  const double* radius = st_.trust_radius.data();
  double* x = st_.values.data();
  double* predicted = st_.predicted.data();
  double* error = st_.predicted_error.data();
  bool beyond = false;
  for (int v = 0; v < nv; ++v) {
    const Jet3& j = jets[v];
    const double q = (j.c[3] - jets2[v].c[3]) * quartic;
    const double xv = prev[v] + h * (j.c[1] + h * (j.c[2] + h * j.c[3])) + q;
    // the highest terms taken, cubic and quartic, estimate the predictor's error
    error[v] = std::abs(cubic * j.c[3] + q);
    beyond |= error[v] > radius[v];
    x[v] = xv;
    predicted[v] = xv;
  }
  // a step beyond the predictor's reach is halved before any solve
  if (check && beyond) {
    for (int v = 0; v < nv && !trust_->rejected; ++v)
      if (error[v] > radius[v]) trust_->reject(TrustOutcome::Kind::predicted, v, error[v], radius[v]);
    return false;
  }
  return true;
}

// the driver [rad or mm] and every node set by a control [deg -> rad, or mm]
void Kernel::set_known_variables(double driver) {
  st_.values[m_.driver_variable()] = driver;
  ws_.vars[m_.driver_variable()] = Jet3::variable(driver, 1.0);
  for (const auto& n : m_.nodes)
    if (n.control >= 0) {
      const double cv = ws_.controls()[n.control];
      set_constant(n.first_variable, m_.controls[n.control].is_angle ? cv * pi / 180.0 : cv);
    }
}

// one plan step: prescribed, closed form, or implicit
Status Kernel::solve_step(int step_index, double driver, bool fresh) {
  const SolveStep& step = m_.plan[step_index];
  st_.full_blocks[step_index].solved = false;
  if (step_index == prescribed_step_) {
    take_prescribed(step);
    return Status::success();
  }
  if (step.method != StepMethod::implicit) return closed_form(step, step_index, driver);
  return solve_implicit(step_index, driver, fresh);
}

// the prescribed node as given; the step's contact parameters stay where they were last solved
void Kernel::take_prescribed(const SolveStep& step) {
  const Node& node = m_.nodes[static_cast<std::size_t>(prescribed_node_)];
  for (int v : step.unknowns) ws_.vars[v] = Jet3(st_.values[v] = st_.predicted[v] = st_.prev_values[v]);
  for (int k = 0; k < node.dof; ++k) {
    const int v = node.first_variable + k;
    ws_.vars[v] = prescribed_vars_[k];
    st_.values[v] = ws_.vars[v].value();
  }
  st_.invalidate_pose(prescribed_node_);
}

// a block solved simultaneously: a lash gap held open, else the one-equation contact form
// where it applies, else broyden/newton and the taylor coefficients
Status Kernel::solve_implicit(int step_index, double driver, bool fresh) {
  const SolveStep& step = m_.plan[step_index];
  auto& b = st_.full_blocks[step_index];
  if (fresh) scan_contact_parameters(b);
  st_.open[step_index] = false;
  if (step.one_sided) {
    bool open = false;
    if (Status st = hold_open_lash(step_index, driver, open); !st.ok() || open) return st;
  }
  if (b.offset.active && !fresh && st_.offset_contacts) {
    bool solved = false;
    // the derivatives need the centre's series to order 4 in u (see there)
    Status st = solve_offset_contact<4>(b, driver, solved);
    if (!st.ok()) return st;
    if (solved) {
      b.solved = true;
      finish_block(b);
      return Status::success();
    }
    // the general solver takes over from the prediction: no stale warm start
    b.have_inverse = false;
    b.jacobians = 0;
  }
  Status st = solve_values(b, driver);
  if (!st.ok()) return st;
  Status dst = differentiate(b, driver);
  if (!dst.ok()) return dst;
  b.solved = true;
  finish_block(b);
  return Status::success();
}

// lash: with the follower at rest, is the closure residual (= the physical gap) open? open:
// the follower is held at rest and the contact's parameters solved for tangency alone
Status Kernel::hold_open_lash(int step_index, double driver, bool& open) {
  const SolveStep& step = m_.plan[step_index];
  open = false;
  const int var = m_.nodes[step.output_node].first_variable;
  auto& t = st_.tangency_blocks[step_index];
  const double saved = st_.values[var];
  st_.values[var] = m_.nodes[step.output_node].rest;
  double gap = 0.0;
  Status st = Status::success();
  if (!t.unknowns.empty()) {
    st = solve_values(t, driver);
  }
  if (st.ok()) {
    const Connection& c = m_.connections[step.connections[0]];
    double r[3];
    connection_residual(m_, c, st_.values.data(), DirectPoses<double>{m_, st_.values.data(), st_.pivots.data()}, r);
    gap = r[c.equation_count - 1];
  }
  if (st.ok() && gap > 0.0) {
    open = true;
    st_.open[step_index] = true;
    set_constant(var, m_.nodes[step.output_node].rest);
    if (!t.unknowns.empty()) {
      Status dst = differentiate(t, driver);
      if (!dst.ok()) return dst;
    }
    ws_.contacts[step.connections[0]].gap = gap;
    st_.invalidate_pose(step.output_node);
    return Status::success();
  }
  st_.values[var] = saved;
  st_.invalidate_pose(step.output_node);
  ws_.contacts[step.connections[0]].gap = 0.0;
  return Status::success();
}

Status Kernel::check_finite(double driver) const {
  const int nv = static_cast<int>(m_.variables.size());
  for (int v = 0; v < nv; ++v) {
    if (!std::isfinite(st_.values[v]))
      return {StatusCode::no_convergence, "variable '" + m_.variables[v].name + "' is not finite",
              driver_text(m_, driver)};
  }
  return Status::success();
}

// the trust radius, then the branch guard (detail/branch_guard.hpp); false: rejected
bool Kernel::guard(double driver) {
  const int nv = static_cast<int>(m_.variables.size());
  // a converged point outside the trust region may be another assembly branch
  const double* x = st_.values.data();
  const double* predicted = st_.predicted.data();
  const double* radius = st_.trust_radius.data();
  bool outside = false;
  for (int v = 0; v < nv; ++v) outside |= std::abs(x[v] - predicted[v]) > radius[v];
  if (outside) {
    for (int v = 0; v < nv && !trust_->rejected; ++v)
      if (std::abs(x[v] - predicted[v]) > radius[v])
        trust_->reject(TrustOutcome::Kind::moved, v, std::abs(x[v] - predicted[v]), radius[v]);
    return false;
  }
  guard_branch(m_, st_, driver != st_.prev_driver && !st_.controls_moved, smallest_step_, *trust_);
  return !trust_->rejected;
}

// an accepted point: the requested outputs, then the history for the next predictor
void Kernel::accept(double driver) {
  const int nv = static_cast<int>(m_.variables.size());
  if (rq_.contacts) {
    // contact quantities need values and first-order rates only (curvature is taken
    // from values of d1 and d2): first-order jets suffice
    for (int v = 0; v < nv; ++v) st_.vars1[v] = truncate<1>(ws_.vars[v]);
    for (std::size_t si = 0; si < m_.plan.size(); ++si) contact_outputs(static_cast<int>(si));
  }
  st_.prev2_values.swap(st_.prev_values);
  st_.prev_values = st_.values;
  st_.prev2_jets.swap(st_.prev_jets);
  st_.prev_jets = ws_.vars;
  st_.prev2_driver = st_.prev_driver;
  st_.prev_driver = driver;
  st_.history = std::min(st_.history + 1, 2);
  // (element by element: std::vector<bool>'s assignment costs more than these few bits)
  for (std::size_t si = 0; si < st_.open.size(); ++si) st_.prev_open[si] = st_.open[si];
  st_.controls_moved = false;
  accept_branch(st_);
  if (ws_.toggle_margin < ws_.path_margin) {
    ws_.path_margin = ws_.toggle_margin;
    ws_.path_margin_at = driver;
  }
  ++ws_.stats.points;
  // the orders not requested are not returned
  if (rq_.derivative_order < continuation_order)
    for (Jet3& j : ws_.vars)
      for (int k = rq_.derivative_order + 1; k <= continuation_order; ++k) j.c[k] = 0.0;
}

}  // namespace camopt::kin::detail
