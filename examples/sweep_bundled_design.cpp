// the kinematics of a bundled design: valve lift, velocity and acceleration over one cam turn
//   example_sweep_bundled_design designs/roller_finger_follower.toml
#include <cstdio>

#include "camopt/camopt.hpp"

int main(int argc, char** argv) {
  using namespace camopt;
  const kin::Mechanism mech = kin::compile(io::load_design(argc > 1 ? argv[1] : "designs/bucket_tappet.toml"));
  kin::SweepSpec spec;  // 0..360 cam deg, 1 deg steps, lift to jerk
  spec.step = 1.0;
  const kin::SweepResult r = kin::sweep(mech, spec);
  const kin::PositionResult& at = r.positions.front();
  if (!at.status.ok()) return std::fprintf(stderr, "%s\n", at.status.str().c_str()), 4;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < r.driver.size(); ++i)
    if (kin::output_lift(mech, at, i) > kin::output_lift(mech, at, peak)) peak = i;
  std::printf("max lift %.4f mm at %g cam deg, acceleration there %.6f mm/deg^2\n", kin::output_lift(mech, at, peak),
              r.driver[peak], kin::output_lift(mech, at, peak, 2));
}
