// envelope synthesis: the cam of the bundled roller finger follower for the bundled target lift,
// checked by running the new cam through the forward kinematics (the round trip)
#include <cstdio>

#include "camopt/camopt.hpp"

int main() {
  using namespace camopt;
  const DesignSpec design = io::load_design("designs/roller_finger_follower.toml");
  const io::AngleTable table = io::read_angle_table(io::read_csv("designs/targets/rff_intake_lift.csv"), {"lift_mm"});
  synthesis::TargetLift target;
  if (const Status st = synthesis::fit_target_lift(table.angle_deg, table.value, table.lines, {}, target); !st.ok())
    return std::fprintf(stderr, "%s\n", st.str().c_str()), 4;
  synthesis::SynthesisResult cam;
  if (const Status st = synthesis::synthesize(design, target.lift, {}, cam); !st.ok())
    return std::fprintf(stderr, "%s\n", st.str().c_str()), 4;
  synthesis::RoundTrip check;
  const DesignSpec made = synthesis::with_profile(design, cam.profile);
  if (const Status st = synthesis::round_trip(made, target.lift, {}, cam.connection, check); !st.ok())
    return std::fprintf(stderr, "%s\n", st.str().c_str()), 4;
  std::printf("%zu profile points, base circle %.4f mm, min radius of curvature %.4f mm; round trip max error %.3g mm\n",
              cam.radius_mm.size(), cam.base_radius_mm, cam.min_radius_of_curvature_mm, check.max_error_mm);
}
