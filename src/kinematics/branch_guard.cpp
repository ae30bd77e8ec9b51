#include "branch_guard.hpp"

#include <algorithm>
#include <cmath>

namespace camopt::kin::detail {

namespace {

// the block's solved variables against their taylor prediction
void check_prediction(const Mechanism& m, const WorkspaceState& ws, std::size_t step, TrustOutcome& trust) {
  const WorkspaceState::Block& b = ws.full_blocks[step];
  // a lash contact that was open at the last point has a kink in its motion
  if (m.plan[step].one_sided && ws.prev_open[step]) return;
  for (int v : b.unknowns) {
    if (m.variables[v].node < 0) continue;  // contact parameters: kinks where profile data has them
    const double distance = std::abs(ws.values[v] - ws.predicted[v]);
    const double bound =
        taylor_agreement_factor * ws.predicted_error[v] + taylor_agreement_floor * ws.trust_radius[v];
    if (distance > bound) trust.reject(TrustOutcome::Kind::disagrees, v, distance, bound);
  }
}

// the block's determinant sign against the last accepted point's
void check_sign(const WorkspaceState& ws, std::size_t step, bool smallest_step, TrustOutcome& trust) {
  const WorkspaceState::Block& b = ws.full_blocks[step];
  if (b.sign == 0 || b.accepted_sign == 0 || std::abs(b.sign) != std::abs(b.accepted_sign)) return;
  if (b.sign == b.accepted_sign) return;
  const double closest = std::min(b.margin, b.accepted_margin);
  if (smallest_step && closest < near_singular_margin) return;
  int worst = b.unknowns.front();
  for (int v : b.unknowns)
    if (std::abs(ws.values[v] - ws.predicted[v]) > std::abs(ws.values[worst] - ws.predicted[worst])) worst = v;
  trust.reject(TrustOutcome::Kind::flipped, worst, std::abs(ws.values[worst] - ws.predicted[worst]), closest);
}

}  // namespace

void guard_branch(const Mechanism& m, const WorkspaceState& ws, bool compare_prediction, bool smallest_step,
                  TrustOutcome& trust) {
  for (std::size_t si = 0; si < ws.full_blocks.size() && !trust.rejected; ++si) {
    if (!ws.full_blocks[si].solved) continue;
    if (compare_prediction) check_prediction(m, ws, si, trust);
    check_sign(ws, si, smallest_step, trust);
  }
}

void accept_branch(WorkspaceState& ws) {
  for (auto& b : ws.full_blocks) {
    b.accepted_sign = b.solved ? b.sign : 0;
    b.accepted_margin = b.margin;
  }
}

}  // namespace camopt::kin::detail
