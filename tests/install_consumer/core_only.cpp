// links camopt::core only: a periodic quintic spline through a cosine, checked at a midpoint
#include <cmath>
#include <cstdio>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/core/units.hpp"

int main() {
  std::vector<double> u, y;
  for (int i = 0; i < 72; ++i) u.push_back(i * 5.0 * camopt::rad_per_deg), y.push_back(std::cos(u.back()));
  const camopt::PeriodicSpline s = camopt::PeriodicSpline::interpolate(u, y, 2.0 * camopt::pi);
  const double x = 2.5 * camopt::rad_per_deg, error = std::abs(s(x) - std::cos(x));
  std::printf("spline error at 2.5 deg: %.3g\n", error);
  return error < 1e-9 ? 0 : 1;
}
