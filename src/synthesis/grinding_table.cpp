// the grinding table of a profile (envelope.hpp): the lift of a master roller (or a flat
// master) translating through the cam centre as the cam turns, from a sweep of a two-body
// mechanism built for it.
#include <algorithm>
#include <cmath>

#include "camopt/kinematics/cam_profile.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::synthesis {

Status grinding_table(const ProfileSpec& profile, double master_radius, double step_deg, std::vector<double>& cam_deg,
                      std::vector<double>& lift_mm) {
  CAMOPT_THROW_UNLESS(std::isfinite(master_radius) && master_radius >= 0,
                      "grinding table master_radius_mm = " + format_value(master_radius) + " mm must be finite and >= 0");
  CAMOPT_THROW_UNLESS(step_deg > 0 && step_deg < 360,
                      "grinding table step_deg = " + format_value(step_deg) + " cam deg must be > 0 and < 360");
  DesignSpec d;
  d.name = "grinding";
  d.output_node = "master";
  d.driver.node = "cam";
  const kin::CamProfile cam = kin::CamProfile::build(profile);
  const double base = cam.base_radius_mm();
  NodeSpec c;
  c.name = "cam";
  c.kind = NodeKind::rotational;
  NodeSpec m;
  m.name = "master";
  m.kind = NodeKind::translational;
  m.origin_mm = {base + master_radius, 0.0};
  m.direction = {1.0, 0.0};
  d.nodes = {c, m};
  d.profiles = {profile};
  ConnectionSpec k;
  k.name = "grind";
  k.kind = ConnectionKind::contact;
  k.surface_a.node = "cam";
  k.surface_a.shape = SurfaceShape::profile;
  k.surface_a.profile = profile.name;
  k.surface_b.node = "master";
  if (master_radius > 0) {
    k.surface_b.shape = SurfaceShape::circle;
    k.surface_b.origin_mm = {base + master_radius, 0.0};
    k.surface_b.radius_mm = master_radius;
  } else {
    k.surface_b.shape = SurfaceShape::line;
    k.surface_b.origin_mm = {base, 0.0};
    k.surface_b.normal = {-1.0, 0.0};
  }
  d.connections = {k};
  const kin::Mechanism mech = kin::compile(d);
  kin::SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0 - step_deg;
  s.step = step_deg;
  s.request = {0, false};
  const kin::SweepResult r = kin::sweep(mech, s);
  if (!r.positions[0].status.ok()) return r.positions[0].status;
  cam_deg = r.driver;
  lift_mm.resize(r.driver.size());
  const int v = mech.nodes[mech.output_node].first_variable;
  double low = 1e300;
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    lift_mm[i] = r.positions[0].value(i, v, 0);
    low = std::min(low, lift_mm[i]);
  }
  for (auto& l : lift_mm) l -= low;  // measured from the base circle
  return Status::success();
}

}  // namespace camopt::synthesis
