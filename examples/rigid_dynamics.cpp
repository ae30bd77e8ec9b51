// rigid-body dynamics of the bundled bucket tappet at 6000 rpm: the cam-tappet contact force
// over one cam turn, its minimum, and the engine speed at which the tappet would separate
#include <algorithm>
#include <cstdio>

#include "camopt/camopt.hpp"

int main() {
  using namespace camopt;
  const DesignSpec design = io::load_design("designs/bucket_tappet.toml");
  const kin::Mechanism mech = kin::compile(design);
  const dynamics::Model model = dynamics::compile_dynamics(design, mech);
  dynamics::RigidSweep sweep;
  if (const Status st = dynamics::rigid_sweep(mech, model, mech.default_controls(), 0.0, 360.0, 0.5, sweep); !st.ok())
    return std::fprintf(stderr, "%s\n", st.str().c_str()), 4;
  const int contact = 0;  // the design's first connection: the cam on the tappet
  const double omega = dynamics::cam_speed_rad_per_s(6000.0, model.crank_per_cam);
  double min_force = sweep.force_at(0, contact, omega);
  for (std::size_t i = 1; i < sweep.points(); ++i) min_force = std::min(min_force, sweep.force_at(i, contact, omega));
  const dynamics::Separation sep = dynamics::separation_speed(sweep, model, contact);
  std::printf("6000 rpm: min contact force %.2f N; separation at %.0f rpm (cam %.1f deg)\n", min_force,
              sep.engine_rpm, sep.cam_deg);
}
