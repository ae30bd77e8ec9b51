// the workspace of kin::solve: per-variable buffers, warm starts and trust radii, and one
// block per plan step (kernel.hpp)
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "kernel.hpp"

namespace camopt::kin {

namespace detail {

namespace {

// the one-equation form of a block (see WorkspaceState::Block::OffsetContact): one contact, no
// lash opening, a profile curve on a known body, a circle on the one unknown body, which
// rotates or translates; its two unknowns are that body's displacement and the curve parameter
WorkspaceState::Block::OffsetContact offset_contact(const Mechanism& m, const SolveStep& step) {
  WorkspaceState::Block::OffsetContact oc;
  if (step.method != StepMethod::implicit || step.connections.size() != 1 || step.one_sided || step.output_node < 0 ||
      step.unknowns.size() != 2)
    return oc;
  const Connection& c = m.connections[step.connections[0]];
  if (c.kind != ConnectionKind::contact) return oc;
  const int u = step.output_node;
  const Node& node = m.nodes[u];
  if (node.kind == NodeKind::floating || (c.node_a != u && c.node_b != u) || c.node_a == c.node_b) return oc;
  const bool circle_on_a = c.node_a == u;
  const Surface& circle = circle_on_a ? c.surface_a : c.surface_b;
  const Surface& curve = circle_on_a ? c.surface_b : c.surface_a;
  if (circle.kind != SurfaceKind::point || curve.kind != SurfaceKind::curve || curve.variable < 0) return oc;
  oc.connection = step.connections[0];
  oc.unknown_node = u;
  oc.known_node = circle_on_a ? c.node_b : c.node_a;
  oc.curve_variable = curve.variable;
  oc.node_variable = node.first_variable;
  oc.curve_on_a = !circle_on_a;
  oc.centre_offset = circle.offset - c.lash;
  oc.centre = circle.origin;
  if (node.kind == NodeKind::rotational) {
    const Eigen::Vector2d arm = circle.origin - node.pivot;
    oc.arm = arm.norm();
    oc.arm_angle = std::atan2(arm.y(), arm.x());
    oc.cos_arm = std::cos(oc.arm_angle);
    oc.sin_arm = std::sin(oc.arm_angle);
    // a circle centred on the pivot does not move its body: leave the block to the general solver
    if (!(oc.arm > 1e-9 * m.length_scale)) return oc;
  }
  oc.active = true;
  return oc;
}

}  // namespace

WorkspaceState::Block make_block(const Mechanism& m, const SolveStep& step, bool tangency_only) {
  WorkspaceState::Block b;
  b.connections = step.connections;
  for (int ci : step.connections) {
    const Connection& c = m.connections[ci];
    const int count = tangency_only ? c.equation_count - 1 : c.equation_count;
    for (int k = 0; k < count; ++k) b.equations.push_back({ci, k});
  }
  for (int v : step.unknowns)
    if (!tangency_only || m.variables[v].node < 0) b.unknowns.push_back(v);
  const int n = static_cast<int>(b.unknowns.size());
  b.solving.assign(m.nodes.size(), 0);
  for (int v : b.unknowns)
    if (m.variables[v].node >= 0) b.solving[m.variables[v].node] = 1;
  b.inverse.setZero(n, n);
  b.jacobian.setZero(n, n);
  b.last_jacobian.setZero(n, n);
  b.prev_jacobian.setZero(n, n);
  b.x.setZero(n);
  b.f.setZero(n);
  b.dx.setZero(n);
  b.f_new.setZero(n);
  b.u.setZero(n);
  b.row.setZero(n);
  b.r1.setZero(n);
  if (!tangency_only) b.offset = offset_contact(m, step);
  return b;
}

void drop_block_warm_starts(Workspace& ws) {
  WorkspaceState& st = state(ws);
  for (auto* blocks : {&st.full_blocks, &st.tangency_blocks})
    for (auto& b : *blocks) {
      b.have_inverse = b.jacobian_at_x = false;
      b.contraction = 0.0;
      b.jacobians = 0;
    }
}

WorkspaceStateHandle::WorkspaceStateHandle() : state_(std::make_unique<WorkspaceState>()) {}
WorkspaceStateHandle::WorkspaceStateHandle(const WorkspaceStateHandle& other)
    : state_(std::make_unique<WorkspaceState>(*other.state_)) {}
WorkspaceStateHandle::WorkspaceStateHandle(WorkspaceStateHandle&& other) noexcept = default;
WorkspaceStateHandle& WorkspaceStateHandle::operator=(const WorkspaceStateHandle& other) {
  if (this == &other) return *this;
  if (state_) *state_ = *other.state_;  // the buffers keep their storage
  else state_ = std::make_unique<WorkspaceState>(*other.state_);  // assigned to after a move
  return *this;
}
WorkspaceStateHandle& WorkspaceStateHandle::operator=(WorkspaceStateHandle&& other) noexcept = default;
WorkspaceStateHandle::~WorkspaceStateHandle() = default;

}  // namespace detail

using detail::drop_block_warm_starts;
using detail::make_block;
using detail::trust_angle_rad;
using detail::trust_length_fraction;

Workspace::Workspace(const Mechanism& mech) {
  detail::WorkspaceState& st = detail::state(*this);
  const std::size_t nv = mech.variables.size();
  vars.assign(nv, Jet3(0.0));
  st.values.assign(nv, 0.0);
  st.prev_values.assign(nv, 0.0);
  st.prev2_values.assign(nv, 0.0);
  st.prev_jets.assign(nv, Jet3(0.0));
  st.prev2_jets.assign(nv, Jet3(0.0));
  st.vars1.assign(nv, Jet<1>(0.0));
  st.vars2.assign(nv, Jet<2>(0.0));
  std::apply([nv](auto&... v) { (v.assign(nv, {}), ...); }, st.dual_vars);
  contacts.assign(mech.connections.size(), ContactState{});
  st.open.assign(mech.plan.size(), false);
  st.prev_open.assign(mech.plan.size(), false);
  st.residual_buffer.assign(4, 0.0);
  st.residual_buffer2.assign(4, Jet<2>(0.0));
  st.residual_buffer3.assign(4, Jet3(0.0));
  for (const auto& step : mech.plan) {
    CAMOPT_ASSERT(static_cast<int>(step.unknowns.size()) <= detail::WorkspaceState::max_block);  // compile() checks it
    st.full_blocks.push_back(make_block(mech, step, false));
    st.tangency_blocks.push_back(make_block(mech, step, true));
  }
  controls_.resize(mech.controls.size());
  for (std::size_t i = 0; i < mech.controls.size(); ++i) controls_[i] = mech.controls[i].default_value;
  st.pivots.resize(mech.nodes.size());
  st.poses0.resize(mech.nodes.size());
  st.poses2.resize(mech.nodes.size());
  st.poses3.resize(mech.nodes.size());
  st.poses1.resize(mech.nodes.size());
  st.no_node_solving.assign(mech.nodes.size(), 0);
  st.predicted.assign(nv, 0.0);
  st.predicted_error.assign(nv, 0.0);
  std::vector<double>& trust_radius = st.trust_radius;
  trust_radius.assign(nv, INFINITY);
  for (int s = 0; s < 2 * static_cast<int>(mech.connections.size()); ++s) {
    // surface parameters: a curve's is an angle, a flat face's a length
    const Connection& c = mech.connections[s / 2];
    const Surface& f = s % 2 ? c.surface_b : c.surface_a;
    if (c.kind == ConnectionKind::contact && f.variable >= 0)
      trust_radius[f.variable] =
          f.kind == SurfaceKind::curve ? trust_angle_rad : trust_length_fraction * mech.length_scale;
  }
  std::vector<double>& variable_scale = st.variable_scale;
  variable_scale.assign(nv, 1.0);
  for (std::size_t v = 0; v < nv; ++v)
    if (mech.variables[v].is_angle) variable_scale[v] = 1.0 / mech.length_scale;
  for (int s = 0; s < 2 * static_cast<int>(mech.connections.size()); ++s) {
    const Connection& c = mech.connections[s / 2];
    const Surface& f = s % 2 ? c.surface_b : c.surface_a;
    if (c.kind == ConnectionKind::contact && f.variable >= 0 && f.kind != SurfaceKind::curve)
      variable_scale[f.variable] = 1.0;  // a flat face's parameter is a length
  }
  for (std::size_t v = 0; v < nv; ++v) {
    const int node = mech.variables[v].node;
    if (node < 0) continue;
    const bool known = node == mech.driver_node || mech.nodes[node].control >= 0;
    trust_radius[v] = known                       ? INFINITY
                      : mech.variables[v].is_angle ? trust_angle_rad
                                                   : trust_length_fraction * mech.length_scale;
  }
  set_controls(controls_);
}

void Workspace::reset() {
  detail::WorkspaceState& st = detail::state(*this);
  st.history = 0;
  std::fill(st.values.begin(), st.values.end(), 0.0);
  drop_block_warm_starts(*this);
  for (auto& b : st.full_blocks) b.accepted_sign = 0;
}

void Workspace::set_controls(std::span<const double> values_in, bool keep_warm_start) {
  CAMOPT_THROW_UNLESS(values_in.size() == controls_.size(),
                      "control position: " + std::to_string(values_in.size()) + " value(s) given, the mechanism has " +
                          std::to_string(controls_.size()) + " control(s) (one value per control, in its order)");
  std::copy(values_in.begin(), values_in.end(), controls_.begin());
  detail::WorkspaceState& st = detail::state(*this);
  st.pivots_stale = true;
  st.controls_moved = true;
  if (!keep_warm_start) reset();
}

const std::vector<Eigen::Vector2d>& Workspace::pivots() const noexcept { return detail::state(*this).pivots; }
const std::vector<double>& Workspace::values() const noexcept { return detail::state(*this).values; }
const std::vector<bool>& Workspace::lash_open() const noexcept { return detail::state(*this).open; }

}  // namespace camopt::kin
