#pragma once
// where a synthesis check fails: every contiguous run of failing samples ("window") over the
// cam revolution or the profile's polar angle, its ends refined between the samples, and the
// worst value of the checked quantity inside it; and the message listing them all.
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace camopt::synthesis {

struct FailureWindow {
  double start_deg = 0, end_deg = 0;   // [deg] ends of the run, refined between samples, in [0, 360)
                                       // (end_deg < start_deg: the window wraps through 0/360 deg)
  double worst = 0, worst_at_deg = 0;  // the worst value of the checked quantity in the run, and where [deg]
  int first = 0, last = 0;             // indices of the run's first and last failing samples (last < first: wraps)
};

// the runs where margin <= 0 (margin > 0: the check passes), samples at ascending angle_deg
// (any range: the ends are wrapped into [0, 360)); periodic: the samples cover one period of
// 360 deg and a run through the last sample continues at the first. Each end lies between
// a passing and a failing sample: the root of the cubic hermite of margin and slope (d margin
// / d angle [per deg]) there, or of the straight line when slope is empty. worst: the lowest
// (lower_is_worse) or highest of value over the run's samples.
std::vector<FailureWindow> failing_windows(std::span<const double> angle_deg, std::span<const double> margin,
                                           std::span<const double> slope, std::span<const double> value,
                                           bool lower_is_worse, bool periodic);

// "1 window: 131.2-134.8 deg (detail)" or "2 windows: 131.2-134.8 deg (detail), 226-228.4 deg
// (detail)": angles to 4 significant digits, each window's detail from `detail` (none if empty)
std::string describe_windows(const std::vector<FailureWindow>& windows,
                             const std::function<std::string(const FailureWindow&)>& detail);

// the windows of a periodic polar table (angle_deg over one turn, radius of curvature roc
// [mm], convex > 0, 0 flat) where |roc| is below limit [mm]; concave_only: concave parts only
// (a grinding wheel). worst: the smallest |roc| in each [mm]
std::vector<FailureWindow> radius_windows(const std::vector<double>& angle_deg, const std::vector<double>& roc,
                                          double limit, bool concave_only);

// an envelope sampled along its tracing, for the report of where it folds back: its polar
// angle turns back (it is not star-shaped about the profile origin) or, under a roller, its
// centre path curves tighter than the roller (a cusp: the cam would need a negative radius)
struct FoldSamples {
  std::vector<double> cam_deg;     // [deg] driver angle of each sample, ascending (may run past 360)
  std::vector<double> polar_deg;   // [deg] polar angle of the profile point, unwrapped, + in the tracing sense
  std::vector<double> turn;        // d polar / d cam in the tracing sense [rad/rad] (<= 0: turns back)
  std::vector<double> turn_slope;  // d turn / d cam [per deg] (empty: window ends refined linearly)
  // roller only (else empty): 1 - roller radius x convex curvature of the centre path [-] (<= 0:
  // a cusp), its slope d/dcam [per deg] (or empty), and the centre path's radius of curvature
  // [mm] (convex > 0)
  std::vector<double> cusp, cusp_slope, centre_radius_mm;
  double roller_mm = 0;
  bool periodic = true;  // a whole revolution (else a traced stretch)
  // more about a window, appended to its detail (may be empty)
  std::function<std::string(const FailureWindow&)> extra;
};

struct FoldReport {
  std::vector<FailureWindow> cusp;       // where the centre path curves tighter than the roller (worst: radius [mm])
  std::vector<FailureWindow> turn_back;  // where the polar angle turns back, apart from the cusps (worst: fold [deg])
  // e.g. "the roller's centre path curves tighter than the 8 mm roller (the cam would need a
  // negative radius of curvature) in 2 windows: 131.2-134.8 deg (centre path radius of curvature
  // down to 3.1 mm), ..."; "the profile's polar angle turns back ... in 1 window: ... (folds
  // back by 0.2 deg of profile)"
  std::string message;
};

FoldReport fold_report(const FoldSamples& samples);

}  // namespace camopt::synthesis
