#pragma once
// the branch guard of the continuation: a converged point is accepted only if it is the
// continuation of the last accepted one. Besides the trust radius (WorkspaceState::trust_radius),
//  - every variable solved simultaneously must agree with its taylor prediction within a
//    bound tied to the prediction's own error estimate (WorkspaceState::predicted_error): a
//    point on another assembly branch is farther from the prediction than the truncated
//    terms can explain, even next to a toggle where the branches are close together;
//  - the sign of each simultaneously solved block's jacobian determinant must not change:
//    two assembly branches meeting at a toggle have determinants of opposite sign. A change
//    is taken only at the smallest step, and only with the block near singular
//    (WorkspaceState::Block::margin below near_singular_margin) at one of the two points: the
//    path then passes through the singular configuration.
// A point that fails is rejected like one outside the trust radius: the step is halved.
// private to src/kinematics
#include "workspace_state.hpp"

namespace camopt::kin::detail {

// a converged point may differ from its prediction by this many times the prediction's
// error estimate (the cubic and quartic terms) plus taylor_agreement_floor x the trust radius
inline constexpr double taylor_agreement_factor = 16.0;
inline constexpr double taylor_agreement_floor = 1e-3;

// the outcome of the trust check and the branch guard of one point
struct TrustOutcome {
  enum class Kind {
    moved,      // the solved variable moved beyond the trust radius from its prediction
    predicted,  // rejected before solving: the predictor's highest terms exceed the radius
    disagrees,  // beyond the taylor agreement bound
    flipped     // a block's determinant changed sign away from a singular point
  };
  bool rejected = false;
  Kind kind = Kind::moved;
  int variable = -1;
  // the variable's distance from its prediction (predicted: the predicted change) and the
  // bound it broke (the trust radius, or the agreement bound) [rad or mm]; flipped: the
  // block's largest distance from the prediction, and its toggle margin in `radius`
  double distance = 0.0, radius = 0.0;
  void reject(Kind k, int v, double d, double r) {
    if (rejected) return;
    rejected = true;
    kind = k;
    variable = v;
    distance = d;
    radius = r;
  }
};

// toggle margin of a block's n x n jacobian j with inverse inv (Workspace::toggle_margin):
// 1 / (|W J D|_1 |(W J D)^-1|_1). D measures every angle as arc length at
// Mechanism::length_scale (WorkspaceState::variable_scale on the unknowns' columns); W scales each
// equation by its whole gradient, over the unknowns (J D) and the driver (rates, r_1 =
// d r / d driver with the unknowns held, an angle driver likewise as arc length), so that an
// equation that is stiff in every variable alike does not count as ill-conditioned
template <class Matrix>
double scaled_margin(const Mechanism& m, const WorkspaceState& ws, int n, const int* unknowns, const Matrix& j,
                     const Matrix& inv, const double* rates) {
  auto column_scale = [&](int c) { return ws.variable_scale[static_cast<std::size_t>(unknowns[c])]; };
  const double driver_scale = m.driver_is_angle() ? 1.0 / m.length_scale : 1.0;
  double row_scale[WorkspaceState::max_block];
  for (int r = 0; r < n; ++r) {
    double gradient = std::abs(rates[r]) * driver_scale;
    for (int c = 0; c < n; ++c) gradient += std::abs(j(r, c)) * column_scale(c);
    row_scale[r] = gradient > 0.0 ? 1.0 / gradient : 0.0;
  }
  double norm = 0.0, inverse_norm = 0.0;
  for (int c = 0; c < n; ++c) {
    double col = 0.0, inv_col = 0.0;
    for (int r = 0; r < n; ++r) {
      col += row_scale[r] * std::abs(j(r, c));
      inv_col += std::abs(inv(r, c)) / column_scale(r);
    }
    norm = std::max(norm, col * column_scale(c));
    inverse_norm = std::max(inverse_norm, row_scale[c] > 0.0 ? inv_col / row_scale[c] : INFINITY);
  }
  const double margin = 1.0 / (norm * inverse_norm);
  return std::isfinite(margin) ? margin : 0.0;
}

// the branch guard of a converged point: rejects it in `trust` (see above).
// compare_prediction: the driver moved and the controls did not since the last accepted
// point (the taylor prediction is then in the driver alone); smallest_step: the step from
// it cannot be halved further
void guard_branch(const Mechanism& m, const WorkspaceState& ws, bool compare_prediction, bool smallest_step,
                  TrustOutcome& trust);

// the accepted point's block determinant signs and margins become the reference
void accept_branch(WorkspaceState& ws);

}  // namespace camopt::kin::detail
