#pragma once
// the one definition of pi and of the degree/radian factors. Angles are radians inside
// every kernel; degrees appear only at the edges (files, CLI, reports), converted with these.
#include <numbers>

namespace camopt {

inline constexpr double pi = std::numbers::pi;
inline constexpr double rad_per_deg = pi / 180.0;  // multiply degrees by this to get radians
inline constexpr double deg_per_rad = 180.0 / pi;  // multiply radians by this to get degrees

}  // namespace camopt
