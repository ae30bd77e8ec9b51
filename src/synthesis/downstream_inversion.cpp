// step 2 of envelope synthesis (envelope.hpp): the inversion. The follower's variables are
// functions F(L) of the target motion alone, so the downstream half, driven by the target
// node, is solved at levels across L's range (F and three derivatives, by implicit
// differentiation in the solver) and interpolated by septic hermite pieces in L; the trace
// (follower_path.cpp) composes them with L(theta) (Faa di Bruno). A floating follower is
// inverted through its cam roller's travel instead (floating_inversion.hpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"

namespace camopt::synthesis::detail {

namespace {

// levels of the target motion at which the downstream chain is solved for the inversion
// (septic hermite between them). On the bundled designs 16 and 32 levels give profiles
// within 8e-13 mm of each other (conventional cams; swing cams 2.7e-10 mm, whose far side
// magnifies it), so 32 levels leave hermite error far below round-off. More levels add
// noise: the derivatives of a hermite piece divide the solves' round-off by powers of the
// level spacing (64 levels moved the rocker arm's profile by 5.8e-10 mm). The round trips
// are the same to 4 digits at 16, 32 and 64 levels
constexpr int kInversionLevels = 32;

// the follower through a floating lever, with notes on how it was bridged
Status invert_through_lever(const DesignSpec& spec, const Halves& halves, const TargetSamples& target,
                            FloatingInversion& through_lever, SynthesisResult& result) {
  const Status st = invert_floating_follower(spec, halves.cut, halves.target_node, halves.controls, target.theta,
                                             target.motion, through_lever);
  if (!st.ok()) return st;
  result.notes.push_back("follower '" + halves.cut.follower_node + "' is a floating lever, inverted through its cam "
                         "roller's travel: " + through_lever.fill_span + "; the bridged lever misses the target by "
                         "up to " + fmt(through_lever.fill_error_mm) + " mm (at cam " +
                         fmt(through_lever.fill_error_at_rad * 180 / pi) + " deg)");
  if (through_lever.rest_travel_mm != 0.0)
    result.notes.push_back("the target's base circle is not the lever's rest lift (" +
                           fmt(through_lever.rest_lift) + " mm): on the base circle the lever rests " +
                           fmt(through_lever.rest_travel_mm) + " mm of cam-roller travel from its drawing rest, "
                           "beyond its idle travel");
  return Status::success();
}

// the downstream half solved at every level, its fields (F and three derivatives) into
// `inverse` [level][field][derivative]. One continuous path: from the rest level (L nearest
// 0, the drawing) down to the lowest level, then up through all of them (warm starts from
// the neighbour)
Status solve_levels(Halves& halves, const TargetSamples& target, const FollowerInverse& out,
                    std::vector<double>& inverse) {
  const int levels = out.levels;
  const double level_step = out.level_step, motion_lo = out.motion_lo;
  const int rest = std::clamp(static_cast<int>(std::lround(-motion_lo / level_step)), 0, levels);
  std::vector<int> order;
  for (int q = rest; q >= 0; --q) order.push_back(q);
  for (int q = 1; q <= levels; ++q) order.push_back(q);
  const SurfaceSpec& follower_surface = *halves.follower_surface;
  for (int q : order) {
    const double level = motion_lo + q * level_step;
    Status st = kin::solve(halves.down, halves.down_ws, level, {3, false});
    if (!st.ok()) {
      int at = 0;  // the first cam angle whose target motion reaches this level
      for (int i = 0; i < target.n; ++i)
        if (std::abs(target.motion[i].value() - level) < std::abs(target.motion[at].value() - level)) at = i;
      st.message = "inverting the valve lift " + fmt(level) + " mm through '" + halves.cut.follower_node +
                   "': " + st.message + "; if a dwell arc or idle curve lies between this cam and the valve, the "
                   "valve lift does not determine the follower there";
      st.where = "cam " + fmt(target.theta[at] * 180 / pi) + " deg";
      return st;
    }
    double* at_level = &inverse[static_cast<std::size_t>(q * out.fields * 4)];
    if (out.invert_centre) {
      const auto centre =
          kin::node_pose(halves.down, halves.follower, halves.down_ws.vars.data(), halves.down_ws.pivots().data())
              .apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]);
      for (int d = 0; d < 4; ++d) at_level[d] = centre.x.derivative(d), at_level[4 + d] = centre.y.derivative(d);
    } else {
      for (int k = 0; k < out.fields; ++k)
        for (int d = 0; d < 4; ++d)
          at_level[k * 4 + d] = halves.down_ws.vars[out.first_variable + k].derivative(d);
    }
  }
  return Status::success();
}

}  // namespace

Status invert_downstream(const DesignSpec& spec, Halves& halves, const TargetSamples& target, FollowerInverse& out,
                         SynthesisResult& result) {
  out = {};
  out.floating = halves.floating_follower;
  const kin::Node* fn = out.floating ? nullptr : &halves.down.nodes[halves.follower];
  const int dof = out.floating ? 0 : fn->dof;
  out.first_variable = out.floating ? -1 : fn->first_variable;
  // a roller's centre (global x, y) is as much a function of L: interpolated in place of the
  // variables, it spares the pose (sin and cos of the follower's angle) at every sample
  out.invert_centre = !out.floating && halves.roller;
  out.fields = out.invert_centre ? 2 : dof;
  double motion_hi = target.hi;
  out.motion_lo = target.lo;
  if (motion_hi - out.motion_lo < 1e-9) motion_hi = out.motion_lo + 1e-3;  // no motion: any small bracket
  out.levels = kInversionLevels;
  out.level_step = (motion_hi - out.motion_lo) / out.levels;
  out.pieces = SepticPieces(std::max(out.fields, 1));
  if (out.floating) return invert_through_lever(spec, halves, target, out.through_lever, result);
  std::vector<double> inverse((out.levels + 1) * out.fields * 4);  // [level][field][derivative]
  if (Status st = solve_levels(halves, target, out, inverse); !st.ok()) return st;
  for (int q = 0; q < out.levels; ++q)
    out.pieces.add_interval(&inverse[static_cast<std::size_t>(q * out.fields * 4)],
                            &inverse[static_cast<std::size_t>((q + 1) * out.fields * 4)], out.level_step);
  return Status::success();
}

}  // namespace camopt::synthesis::detail
