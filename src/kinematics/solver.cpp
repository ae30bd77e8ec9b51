// kin::solve and its relatives: a point by continuation from the last accepted one, the
// step halved while the trust check or the branch guard rejects it; a fresh workspace
// assembled by continuation from the drawing. One point itself is Kernel::run
// (solve_point.cpp; kernel.hpp lists the files of its steps).
#include "camopt/kinematics/solver.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernel.hpp"

namespace camopt::kin {

using detail::driver_text;
using detail::drop_block_warm_starts;
using detail::fmt;
using detail::Kernel;
using detail::state;
using detail::min_control_fraction;
using detail::min_step_rad;
using detail::TrustOutcome;
using detail::WorkspaceState;

namespace {

// pivots moved by controls (recomputed when the controls change)
void place_pivots(const Mechanism& mech, Workspace& ws) {
  WorkspaceState& st = state(ws);
  if (st.pivots_stale) {
    st.pivots_stale = false;
    for (std::size_t i = 0; i < mech.nodes.size(); ++i) {
      const Node& n = mech.nodes[i];
      st.pivots[i] = n.pivot;
      if (n.pivot_control >= 0) {
        const double a = n.pivot_gain * ws.controls()[n.pivot_control];
        const Eigen::Vector2d r = n.pivot - n.pivot_about;
        st.pivots[i] = n.pivot_about + Eigen::Vector2d(std::cos(a) * r.x() - std::sin(a) * r.y(),
                                                       std::sin(a) * r.x() + std::cos(a) * r.y());
      }
    }
  }
}

// one point with the trust check; on rejection the blocks' warm starts (jacobians of the
// rejected point) are dropped, the history of accepted points is kept. smallest: the step
// cannot be halved further (Kernel)
Status attempt(const Mechanism& m, Workspace& ws, double driver, const Request& rq, TrustOutcome& trust,
               bool smallest) {
  place_pivots(m, ws);
  trust = TrustOutcome{};
  Status st = Kernel(m, ws, rq, &trust, smallest).run(driver);
  if (trust.rejected) {
    ++ws.stats.rejected_steps;
    drop_block_warm_starts(ws);
  }
  return st;
}

// a point still rejected at the smallest step: names the variable's connection(s)
Status jump_status(const Mechanism& m, const TrustOutcome& t, double driver, const std::string& step_text) {
  std::string names;
  for (const SolveStep& step : m.plan)
    if (std::find(step.unknowns.begin(), step.unknowns.end(), t.variable) != step.unknowns.end())
      for (int ci : step.connections) names += (names.empty() ? "'" : ", '") + m.connections[ci].name + "'";
  const std::string unit = m.variables[t.variable].is_angle && m.variables[t.variable].node >= 0 ? " rad" : "";
  const std::string name = "'" + m.variables[t.variable].name + "' ";
  std::string what;
  switch (t.kind) {
    case TrustOutcome::Kind::predicted:
      what = name + "is predicted to change by " + fmt(t.distance) + unit + ", beyond the trust radius " +
             fmt(t.radius) + unit;
      break;
    case TrustOutcome::Kind::moved:
      what = name + "moved " + fmt(t.distance) + unit + " from its prediction, beyond the trust radius " +
             fmt(t.radius) + unit;
      break;
    case TrustOutcome::Kind::disagrees:
      what = name + "moved " + fmt(t.distance) + unit + " from its taylor prediction, beyond " +
             fmt(detail::taylor_agreement_factor) + " times the prediction's error estimate (" + fmt(t.radius) +
             unit + ")";
      break;
    case TrustOutcome::Kind::flipped:
      what = "the jacobian's determinant changed sign with the toggle margin at " + fmt(t.radius) +
             ", not near a singular configuration (" + name + "moved " + fmt(t.distance) + unit +
             " from its prediction)";
      break;
  }
  return {StatusCode::no_convergence,
          "connection(s) " + names + " jump: " + what + ", even at a step of " + step_text +
              " (another assembly branch, or the contact leaves the surface)",
          driver_text(m, driver) + ", residual " + fmt(t.distance)};
}

// the whole step was rejected: halved from the last accepted point (at `start`), the
// intermediate points solved with derivatives for the predictor, down to min_step_rad
Status subdivide(const Mechanism& m, Workspace& ws, double target, const Request& rq, const TrustOutcome& first,
                 double start) {
  const Request inner{3, false};
  const double min_step = m.driver_is_angle() ? min_step_rad : min_step_rad * m.length_scale;
  auto step_text = [&](double h) {
    return m.driver_is_angle() ? fmt(std::abs(h) * 180.0 / pi) + " deg" : fmt(std::abs(h)) + " mm";
  };
  if (std::abs(target - start) <= min_step) return jump_status(m, first, target, step_text(target - start));
  double h = 0.5 * (target - start);
  for (;;) {
    const double from = state(ws).prev_driver;
    const bool last = std::abs(target - from) <= std::abs(h);
    const double at = last ? target : from + h;
    TrustOutcome trust;
    Status st = attempt(m, ws, at, last ? rq : inner, trust, std::abs(at - from) <= min_step);
    if (!st.ok() && !last) {
      // the way to the target is blocked: reported at the target, with where it stopped
      const std::string at_text = driver_text(m, at);
      if (st.where.rfind(at_text, 0) == 0) st.where.replace(0, at_text.size(), driver_text(m, target));
      st.message += " (reached at " + at_text + ", continuing from " + driver_text(m, from) + ")";
    }
    if (!st.ok()) return st;
    if (!trust.rejected) {
      if (last) return st;
      h *= 2.0;
      continue;
    }
    if (std::abs(at - from) <= min_step) return jump_status(m, trust, at, step_text(at - from));
    h = 0.5 * (at - from);
  }
}

// the point at `target` by continuation from the last accepted one (the whole step first:
// the fine-step path is one attempt)
Status step_to(const Mechanism& m, Workspace& ws, double target, const Request& rq) {
  place_pivots(m, ws);
  if (state(ws).history == 0) return Kernel(m, ws, rq).run(target);
  const double start = state(ws).prev_driver;
  const double min_step = m.driver_is_angle() ? min_step_rad : min_step_rad * m.length_scale;
  TrustOutcome first;
  Status st = attempt(m, ws, target, rq, first, std::abs(target - start) <= min_step);
  if (st.ok() && first.rejected) st = subdivide(m, ws, target, rq, first, start);
  return st;
}

// from the solved drawing (driver 0, default controls, where every node is at its drawing
// position): the controls moved to `target` in steps, then the driver continued to
// `driver`, all under the trust check, so the first point is on the drawing's assembly
// branch rather than wherever Newton from the drawing lands
Status continue_from_drawing(const Mechanism& m, Workspace& ws, const std::vector<double>& target, double driver,
                             const Request& rq) {
  const std::vector<double> defaults = m.default_controls();
  std::vector<double> controls = defaults;
  const Request inner{3, false};
  double done = 0.0, step = 1.0;  // fraction of the control move
  while (done < 1.0) {
    const double next = std::min(1.0, done + step);
    for (std::size_t i = 0; i < target.size(); ++i)
      controls[i] = next == 1.0 ? target[i] : defaults[i] + next * (target[i] - defaults[i]);
    ws.set_controls(controls, true);
    TrustOutcome trust;
    Status st = attempt(m, ws, 0.0, inner, trust, next - done <= min_control_fraction);
    if (!st.ok()) return st;
    if (!trust.rejected) {
      done = next;
      step *= 2.0;
      continue;
    }
    if (next - done <= min_control_fraction)
      return jump_status(m, trust, 0.0, "1e-6 of the control move");
    step *= 0.5;
  }
  ws.path_margin = INFINITY;  // the path at the target controls starts here
  return step_to(m, ws, driver, rq);
}

// a fresh workspace away from the drawing: assembled by continuation from the drawing
// (solved here, or copied from `drawing`), else directly
Status solve_fresh(const Mechanism& mech, Workspace& ws, double driver, const Request& request,
                   const Workspace* drawing) {
  const std::vector<double> target = ws.controls();
  Status st = Status::success();
  if (drawing != nullptr)
    ws = *drawing;
  else
    st = solve_drawing(mech, ws);
  CamProfile::clear_thread_memo();  // the continuation does not depend on the thread's past
  if (st.ok()) st = continue_from_drawing(mech, ws, target, driver, request);
  if (st.ok()) return st;
  // the drawing does not assemble or continue: assemble at the point directly
  ws.set_controls(target);
  ws.path_margin = INFINITY;
  st = step_to(mech, ws, driver, request);
  if (!st.ok()) ws.reset();
  return st;
}
}  // namespace

namespace {
// the plan step that solves `node`, if it solves nothing else but contact parameters (else -1)
int prescribable_step(const Mechanism& mech, int node) {
  const Node& n = mech.nodes[static_cast<std::size_t>(node)];
  if (n.first_variable < 0 || n.control >= 0 || node == mech.driver_node) return -1;
  for (std::size_t si = 0; si < mech.plan.size(); ++si) {
    const auto& unknowns = mech.plan[si].unknowns;
    if (std::find(unknowns.begin(), unknowns.end(), n.first_variable) == unknowns.end()) continue;
    for (int v : unknowns)
      if (mech.variables[static_cast<std::size_t>(v)].node >= 0 && mech.variables[static_cast<std::size_t>(v)].node != node)
        return -1;
    return mech.plan[si].one_sided ? -1 : static_cast<int>(si);
  }
  return -1;
}
}  // namespace

bool can_prescribe(const Mechanism& mech, int node) {
  return node >= 0 && node < static_cast<int>(mech.nodes.size()) && prescribable_step(mech, node) >= 0;
}

void Request::validate() const {
  CAMOPT_THROW_UNLESS(derivative_order >= 0 && derivative_order <= 3,
                      "request.derivative_order = " + std::to_string(derivative_order) + " must be in [0, 3]");
  CAMOPT_THROW_UNLESS(!contacts || derivative_order >= 1,
                      "request.contacts = true needs request.derivative_order >= 1 (it is " +
                          std::to_string(derivative_order) + "): contact speeds are first-order rates");
}

Status solve_prescribed(const Mechanism& mech, Workspace& ws, double driver, const Request& request, int node,
                        std::span<const Jet3> node_vars) {
  request.validate();
  CAMOPT_THROW_UNLESS(node >= 0 && node < static_cast<int>(mech.nodes.size()),
                      "solve_prescribed: node = " + std::to_string(node) + " must be a node index in [0, " +
                          std::to_string(mech.nodes.size()) + ")");
  const int step = prescribable_step(mech, node);
  const Node& n = mech.nodes[static_cast<std::size_t>(node)];
  CAMOPT_THROW_UNLESS(step >= 0, "solve_prescribed: node '" + n.name +
                                     "' cannot be prescribed: the plan step that solves it must solve nothing else "
                                     "but its contacts' parameters (can_prescribe)");
  CAMOPT_THROW_UNLESS(static_cast<int>(node_vars.size()) == n.dof,
                      "solve_prescribed: node_vars has " + std::to_string(node_vars.size()) + " jet(s), node '" +
                          n.name + "' has " + std::to_string(n.dof) + " variable(s)");
  CAMOPT_THROW_UNLESS(!request.contacts, "solve_prescribed: request.contacts = true: must be false (the contact "
                                         "parameters keep their last values)");
  CAMOPT_THROW_UNLESS(state(ws).history >= 1,
                      "solve_prescribed: the workspace has no solved point: solve() a point at these controls first");
  place_pivots(mech, ws);
  ws.path_margin = INFINITY;
  TrustOutcome trust;
  Kernel kernel(mech, ws, request, &trust);
  kernel.prescribe(step, node, node_vars.data());
  const Status st = kernel.run(driver);
  if (!st.ok() || !trust.rejected) return st;
  ++ws.stats.rejected_steps;
  drop_block_warm_starts(ws);
  return jump_status(mech, trust, driver, "one step");
}

Status solve_near(const Mechanism& mech, Workspace& ws, double near_driver, std::span<const Jet3> near,
                  double driver, const Request& request) {
  request.validate();
  const std::size_t nv = mech.variables.size();
  CAMOPT_THROW_UNLESS(near.size() == nv, "solve_near: near has " + std::to_string(near.size()) +
                                             " jet(s), the mechanism has " + std::to_string(nv) + " variable(s)");
  place_pivots(mech, ws);
  WorkspaceState& ss = state(ws);
  // the solved point as the only history: its taylor series is the prediction
  for (std::size_t v = 0; v < nv; ++v) {
    ss.prev_jets[v] = ss.prev2_jets[v] = near[v];
    ss.values[v] = ss.prev_values[v] = ss.prev2_values[v] = near[v].value();
  }
  ss.prev_driver = ss.prev2_driver = near_driver;
  ss.history = 1;
  ss.controls_moved = false;
  ws.path_margin = INFINITY;
  drop_block_warm_starts(ws);
  Status st = Kernel(mech, ws, request).run(driver);
  if (!st.ok()) return st;
  for (std::size_t v = 0; v < nv; ++v) {
    const double moved = std::abs(ss.values[v] - ss.predicted[v]);
    if (moved > ss.trust_radius[v])
      return {StatusCode::no_convergence,
              "solve_near: '" + mech.variables[v].name + "' moved " + fmt(moved) + " from its prediction, beyond the trust radius " +
                  fmt(ss.trust_radius[v]) + " (another assembly branch, or the contact leaves the surface)",
              driver_text(mech, driver) + ", residual " + fmt(moved)};
  }
  return st;
}

bool at_drawing(const Mechanism& mech, const std::vector<double>& controls, double driver) {
  return driver == 0.0 && controls == mech.default_controls();
}

Status solve_drawing(const Mechanism& mech, Workspace& ws) {
  CamProfile::clear_thread_memo();  // the drawing does not depend on the thread's past
  ws.set_controls(mech.default_controls());
  place_pivots(mech, ws);
  ws.path_margin = INFINITY;
  Status st = Kernel(mech, ws, Request{3, false}).run(0.0);
  if (!st.ok()) ws.reset();
  return st;
}

Status solve(const Mechanism& mech, Workspace& ws, double driver, const Request& request, const Workspace* drawing) {
  request.validate();
  ws.path_margin = INFINITY;
  if (state(ws).history == 0 && !at_drawing(mech, ws.controls(), driver))
    return solve_fresh(mech, ws, driver, request, drawing);
  if (state(ws).history == 0) CamProfile::clear_thread_memo();  // the drawing does not depend on the thread's past
  Status st = step_to(mech, ws, driver, request);
  if (!st.ok()) ws.reset();
  return st;
}

}  // namespace camopt::kin
