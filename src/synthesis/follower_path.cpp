// the follower in the cam's profile frame for envelope synthesis (envelope.hpp): at every
// sample the inverse F(L) composed with the target L(theta) gives the follower, the cam's
// motion gives the cam's pose, and the follower's surface (a roller's centre, or a flat
// face's point and normal) is taken into the frame of the profile on the cam.
#include <algorithm>
#include <cmath>
#include <vector>

#include "camopt/core/trig_cache.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"

namespace camopt::synthesis::detail {

namespace {

// the follower at target motion L from the inverse pieces (follower(theta) = F(L(theta))):
// a roller's centre into `centre`, else the follower's variables into `vars`
void follower_at(const FollowerInverse& inverse, const Jet3& L, std::vector<Jet3>& centre, std::vector<Jet3>& vars) {
  const double u = std::clamp((L.value() - inverse.motion_lo) / inverse.level_step, 0.0,
                              static_cast<double>(inverse.levels));
  for (int k = 0; k < inverse.fields; ++k) {
    double d[4];
    inverse.pieces.eval_at(u, k, d);
    (inverse.invert_centre ? centre[k] : vars[inverse.first_variable + k]) = compose(d, L);
  }
}

// the upstream variables at sample i: the driver itself (its angle is theta; its sine and
// cosine go into the trig memo), or the cam's variables interpolated from the upstream
// solves (a swing cam's angle as already found)
const Jet3* cam_vars_at(CamMotion& cam, int angle_dof, int i, double theta, Jet3& driver_alone,
                        std::vector<Jet3>& up_vars) {
  driver_alone = Jet3::variable(theta);
  if (cam.lone_driver) {
    memo_sin_cos_insert(theta, cam.driver_sin[i], cam.driver_cos[i]);
    return &driver_alone;
  }
  for (int k = 0; k < cam.dof; ++k)
    up_vars[cam.first_variable + k] = k == angle_dof && !cam.angle_at.empty() ? cam.angle_at[i] : cam.at(i, k);
  return up_vars.data();
}

}  // namespace

void trace_follower(Halves& halves, const TargetSamples& target, const FollowerInverse& inverse, CamMotion& cam,
                    const std::vector<char>& needed, FollowerPath& out) {
  const SurfaceSpec& follower_surface = *halves.follower_surface;
  const int angle_dof = halves.cam_angle_variable - cam.first_variable;
  std::vector<Jet3> vars(halves.down.variables.size(), Jet3(0.0));  // the follower's, from the inverse
  std::vector<Jet3> centre(inverse.invert_centre ? 2 : 0, Jet3(0.0));  // a roller's centre at a sample
  std::vector<Jet3> up_vars(halves.up.variables.size(), Jet3(0.0));
  Jet3 driver_alone;
  for (int i = 0; i < target.n; ++i) {
    const Jet3& L = target.motion[i];
    out.valve_rate[i] = L.derivative(1);
    if (!needed[i]) continue;  // a swing cam's dwell (cam_rate is set)
    follower_at(inverse, L, centre, vars);
    // the cam's pose: the driver itself, or interpolated from upstream
    const Jet3* cam_vars = cam_vars_at(cam, angle_dof, i, target.theta[i], driver_alone, up_vars);
    const auto cpose = kin::node_pose(halves.up, halves.cam, cam_vars, halves.up_ws.pivots().data());
    out.cam_rate[i] = cam_vars[halves.cam_angle_variable].derivative(1);  // [rad per rad of driver]
    // the follower's surface in the profile frame
    if (inverse.floating) {  // a roller (invert_floating_follower requires one)
      out.path[i] = halves.frame.point(
          cpose, kin::V2<Jet3>{inverse.through_lever.centre_x[i], inverse.through_lever.centre_y[i]});
      continue;
    }
    if (inverse.invert_centre) {  // a roller: no face normal
      out.path[i] = halves.frame.point(cpose, kin::V2<Jet3>{centre[0], centre[1]});
      continue;
    }
    const auto fpose = kin::node_pose(halves.down, halves.follower, vars.data(), halves.down_ws.pivots().data());
    out.path[i] = halves.frame.point(cpose, fpose.apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]));
    if (!halves.roller) {
      const Vec2 nn = follower_surface.normal;
      const double len = std::hypot(nn[0], nn[1]);
      out.normal[i] = halves.frame.direction(cpose, fpose.rotate(nn[0] / len, nn[1] / len));
    }
  }
}

}  // namespace camopt::synthesis::detail
