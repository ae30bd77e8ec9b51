// a design built in code: an eccentric disc (radius 20 mm, eccentricity 4 mm) on a flat-faced
// tappet. The tappet's lift is e (1 - cos theta): 8 mm at 180 deg, the closed form to compare.
#include <cmath>
#include <cstdio>

#include "camopt/camopt.hpp"

int main() {
  using namespace camopt;
  DesignSpec d = build::design("eccentric on a flat tappet", "cam", "tappet");
  d.nodes = {build::rotational("cam", {0, 0}), build::translational("tappet", {0, 0}, {0, 1})};
  d.profiles = {build::eccentric_profile("disc", 20.0, 4.0)};
  d.connections = {build::contact("cam_tappet", build::profile_surface("cam", "disc", {0, 0}, -90.0),
                                  build::line_surface("tappet", {0, 16.0}, {0, -1}))};
  const kin::Mechanism mech = kin::compile(d);
  kin::SweepSpec spec;
  spec.step = 10.0;
  const kin::SweepResult r = kin::sweep(mech, spec);
  double worst = 0;
  for (std::size_t i = 0; i < r.driver.size(); ++i)
    worst = std::max(worst, std::abs(kin::output_lift(mech, r.positions[0], i) -
                                     4.0 * (1.0 - std::cos(r.driver[i] * rad_per_deg))));
  std::printf("lift at 180 deg %.9f mm; largest difference from e (1 - cos theta) %.3g mm\n",
              kin::output_lift(mech, r.positions[0], 18), worst);
}
