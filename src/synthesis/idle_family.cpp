// a swing cam's idle family for envelope synthesis (envelope.hpp): where the follower rests
// at the other positions of the first control. At the driver angle in the middle of the
// longest stretch where the cam rests, both halves are solved across the control's range
// (and 10 % beyond each end); the follower's centre in the cam's profile frame is
// interpolated between those solves and given 4 times as densely with its tangent in the
// control. swing_profile takes the envelope of the resting roller over this family.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "camopt/synthesis/detail/envelope_steps.hpp"

namespace camopt::synthesis::detail {

namespace {

// control positions solved across the family; the centres are interpolated between them
// (quintic splines in the control) and the envelope taken 4 times as densely
constexpr int kIdleControls = 32;

// the sample in the middle of the longest stretch where the cam rests (its rate at most
// 1e-3 of the peak), or -1 when it never rests
int middle_of_longest_rest(const std::vector<double>& cam_rate) {
  const int n = static_cast<int>(cam_rate.size());
  double max_rate = 0.0;
  for (double r : cam_rate) max_rate = std::max(max_rate, std::abs(r));
  int best_start = -1, best_len = 0;
  for (int i = 0; i < n; ++i) {
    auto still = [&](int k) { return std::abs(cam_rate[(k + n) % n]) <= 1e-3 * max_rate; };
    if (!still(i) || still(i - 1)) continue;
    int len = 0;
    while (len < n && still(i + len)) ++len;
    if (len > best_len) best_len = len, best_start = i;
  }
  return best_start < 0 ? -1 : (best_start + best_len / 2) % n;
}

// solve at controls ctl, continuing from the last solved point (the control moves by one
// family step under the solver's trust check); a point the continuation cannot reach is
// assembled afresh from the drawing, as a lone point would be
bool solve_at_control(const kin::Mechanism& mech, kin::Workspace& w, const std::vector<double>& ctl, double at) {
  w.set_controls(ctl, true);
  if (kin::solve(mech, w, at, {0, false}).ok()) return true;
  w.set_controls(ctl);
  return kin::solve(mech, w, at, {0, false}).ok();
}

// the resting follower's centre in the profile frame (control, x, y) over one side of the
// family from the synthesized position outwards (side 0 up, side 1 down), so each solve
// starts next to the last; the family ends where the mechanism no longer assembles
std::vector<std::array<double, 3>> solve_family_side(const Halves& halves, kin::Workspace& up_w,
                                                     kin::Workspace& down_w, const std::vector<double>& family,
                                                     std::ptrdiff_t split, int side, double rest_theta,
                                                     double rest_level) {
  // a downstream that no control moves rests the same at every position: solved once
  const bool down_follows_control = std::any_of(halves.down.nodes.begin(), halves.down.nodes.end(),
                                                [](const kin::Node& nd) { return nd.control >= 0 || nd.pivot_control >= 0; });
  const SurfaceSpec& follower_surface = *halves.follower_surface;
  std::vector<std::array<double, 3>> out;
  std::vector<double> ctl = halves.controls;
  bool down_at_rest = false;
  for (std::ptrdiff_t j = side == 0 ? split : split - 1; side == 0 ? j <= kIdleControls : j >= 0;
       j += side == 0 ? 1 : -1) {
    ctl[0] = family[static_cast<std::size_t>(j)];
    if (!solve_at_control(halves.up, up_w, ctl, rest_theta)) break;
    if (down_follows_control || !down_at_rest) {
      if (!solve_at_control(halves.down, down_w, ctl, rest_level)) break;
      down_at_rest = true;
    }
    const auto cpose = kin::node_pose(halves.up, halves.cam, up_w.vars.data(), up_w.pivots().data());
    const auto fpose = kin::node_pose(halves.down, halves.follower, down_w.vars.data(), down_w.pivots().data());
    const P2<Jet3> c =
        halves.frame.point(cpose, fpose.apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]));
    out.push_back({ctl[0], c.x.value(), c.y.value()});
  }
  return out;
}

// the solved centres (ascending control) interpolated by splines in the control, with their
// tangents, 4 times as densely; none from fewer than 6 solves
std::vector<IdleCentre> dense_centres(const std::vector<std::array<double, 3>>& solved) {
  std::vector<IdleCentre> out;
  if (solved.size() < 6) return out;
  std::vector<double> cs, xs, ys;
  for (const auto& q : solved) cs.push_back(q[0]), xs.push_back(q[1]), ys.push_back(q[2]);
  const Spline sx = Spline::interpolate(cs, xs), sy = Spline::interpolate(cs, ys);
  const int dense = 4 * (static_cast<int>(cs.size()) - 1);
  for (int j = 0; j <= dense; ++j) {
    const double cv = cs.front() + (cs.back() - cs.front()) * j / dense;
    double dx[2], dy[2];
    sx.evaluate(cv, 1, dx);
    sy.evaluate(cv, 1, dy);
    out.push_back({dx[0], dy[0], dx[1], dy[1]});
  }
  return out;
}

}  // namespace

std::vector<IdleCentre> idle_family(Halves& halves, const PeriodicSpline& lift, const TargetSamples& target,
                                    const std::vector<double>& cam_rate) {
  if (halves.up.controls.empty() || !halves.roller) return {};
  const int rest = middle_of_longest_rest(cam_rate);
  if (rest < 0) return {};
  const double rest_theta = target.theta[rest];
  const double rest_level = lift(rest_theta);
  // the first control's range and 10 % beyond each end; split: the synthesized position
  const auto& c0 = halves.up.controls[0];
  const double lo = c0.min - 0.1 * (c0.max - c0.min), hi = c0.max + 0.1 * (c0.max - c0.min);
  std::vector<double> family;
  for (int j = 0; j <= kIdleControls; ++j) family.push_back(lo + (hi - lo) * j / kIdleControls);
  const auto split = std::lower_bound(family.begin(), family.end(), halves.controls[0]) - family.begin();
  // both sides start from the synthesized position's workspaces (their last use: the
  // second side takes them over)
  std::vector<std::array<double, 3>> upper, lower;
  {
    kin::Workspace up_w = halves.up_ws, down_w = halves.down_ws;
    upper = solve_family_side(halves, up_w, down_w, family, split, 0, rest_theta, rest_level);
  }
  {
    kin::Workspace up_w = std::move(halves.up_ws), down_w = std::move(halves.down_ws);
    lower = solve_family_side(halves, up_w, down_w, family, split, 1, rest_theta, rest_level);
  }
  std::vector<std::array<double, 3>> solved(lower.rbegin(), lower.rend());
  solved.insert(solved.end(), upper.begin(), upper.end());
  return dense_centres(solved);
}

}  // namespace camopt::synthesis::detail
