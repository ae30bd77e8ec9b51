#pragma once
// the undercut Status of an envelope that folds back, listing every window where it does
// (undercut_windows.hpp), from the sampled envelope and follower centre path of envelope.cpp
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"

namespace camopt::synthesis::detail {

template <class T>
struct P2 {
  T x, y;
};

// a whole revolution of a rotational cam: env, path (the roller's centre, or the flat face's
// point) and phi (the envelope's unwrapped polar angle, n + 1 entries) at n samples of the
// cam angle 2 pi i / n; sign: the sense in which the profile winds; orient: that of the centre
// path; roller_mm < 0 for a flat face
Status revolution_fold_status(const std::vector<P2<Jet<2>>>& env, const std::vector<P2<Jet<3>>>& path,
                              const std::vector<double>& phi, double sign, double orient, double roller_mm);

// a swing cam's traced stretch: env and phi (unwrapped polar angle) along the run of sample
// indices `run` (into path, theta, cam_rate and valve_rate, all per sample of the revolution),
// traced in the polar sense dir; cam_rate: the swing cam's angular rate [rad/rad], peak
// max_rate; valve_rate: the target's dL/dtheta [mm/rad]. ripple: the first fold is where the
// swing and the valve barely move (the target's own interpolation ripple, not its shape)
Status swing_fold_status(const std::vector<P2<Jet<2>>>& env, const std::vector<double>& phi, double dir,
                         const std::vector<int>& run, const std::vector<P2<Jet<3>>>& path,
                         const std::vector<double>& theta, const std::vector<double>& cam_rate, double max_rate,
                         const std::vector<double>& valve_rate, double roller_mm, bool& ripple);

}  // namespace camopt::synthesis::detail
