#include "camopt/synthesis/undercut_windows.hpp"

#include <algorithm>
#include <cmath>

#include "camopt/core/error.hpp"

namespace camopt::synthesis {

namespace {

// angle [deg] wrapped into [0, 360)
double wrap_deg(double a) {
  double w = std::fmod(a, 360.0);
  if (w < 0) w += 360.0;
  return w >= 360.0 ? 0.0 : w;
}

// the fraction t in [0, 1] of the interval from sample a (margin m0, slope d0 per unit t) to
// sample b (m1, d1) where the margin crosses zero: bisection on the cubic hermite (the ends
// bracket a root: m0 and m1 differ in sign), or the straight line without slopes
double crossing(double m0, double m1, const double* d0, const double* d1) {
  if (!d0) return m0 / (m0 - m1);
  auto at = [&](double t) {
    const double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * m0 + (t3 - 2 * t2 + t) * *d0 + (-2 * t3 + 3 * t2) * m1 + (t3 - t2) * *d1;
  };
  double lo = 0.0, hi = 1.0;
  const bool rising = m1 > m0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    ((at(mid) < 0) == rising ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::vector<FailureWindow> failing_windows(std::span<const double> angle_deg, std::span<const double> margin,
                                           std::span<const double> slope, std::span<const double> value,
                                           bool lower_is_worse, bool periodic) {
  const std::size_t n = angle_deg.size();
  CAMOPT_ASSERT(margin.size() == n && value.size() == n && (slope.empty() || slope.size() == n));
  auto fails = [&](std::size_t i) { return !(margin[i] > 0); };
  // the angle between passing sample a and failing sample b (or the reverse), a and b neighbours
  auto refine = [&](std::size_t a, std::size_t b) {
    double span = angle_deg[b] - angle_deg[a];
    if (periodic && b == 0 && a == n - 1) span += 360.0;  // across the seam
    if (periodic && a == 0 && b == n - 1) span -= 360.0;
    const double da = slope.empty() ? 0.0 : slope[a] * span, db = slope.empty() ? 0.0 : slope[b] * span;
    const double t = crossing(margin[a], margin[b], slope.empty() ? nullptr : &da, slope.empty() ? nullptr : &db);
    return wrap_deg(angle_deg[a] + t * span);
  };
  std::vector<FailureWindow> out;
  std::size_t failing = 0;
  for (std::size_t i = 0; i < n; ++i) failing += fails(i) ? 1 : 0;
  if (failing == 0) return out;
  if (failing == n) {  // the check fails everywhere: one window over the whole range
    FailureWindow w;
    w.start_deg = wrap_deg(angle_deg[0]), w.end_deg = wrap_deg(angle_deg[n - 1]);
    w.first = 0, w.last = static_cast<int>(n - 1);
    w.worst = value[0], w.worst_at_deg = wrap_deg(angle_deg[0]);
    for (std::size_t i = 1; i < n; ++i)
      if (lower_is_worse ? value[i] < w.worst : value[i] > w.worst) w.worst = value[i], w.worst_at_deg = wrap_deg(angle_deg[i]);
    return out = {w};
  }
  // runs start at a failing sample after a passing one; a periodic run may start before the
  // seam and end after it
  for (std::size_t i = 0; i < n; ++i) {
    const bool starts = fails(i) && (i == 0 ? (periodic ? !fails(n - 1) : true) : !fails(i - 1));
    if (!starts) continue;
    FailureWindow w;
    w.first = static_cast<int>(i);
    w.worst = value[i], w.worst_at_deg = wrap_deg(angle_deg[i]);
    std::size_t j = i;
    for (;;) {
      const std::size_t next = j + 1 == n ? (periodic ? 0 : n) : j + 1;
      if (next == n || !fails(next)) break;
      j = next;
      if (lower_is_worse ? value[j] < w.worst : value[j] > w.worst) w.worst = value[j], w.worst_at_deg = wrap_deg(angle_deg[j]);
    }
    w.last = static_cast<int>(j);
    const bool open_start = i == 0 && !periodic, open_end = j + 1 == n && !periodic;
    w.start_deg = open_start ? wrap_deg(angle_deg[i]) : refine(i == 0 ? n - 1 : i - 1, i);
    w.end_deg = open_end ? wrap_deg(angle_deg[j]) : refine(j + 1 == n ? 0 : j + 1, j);
    out.push_back(w);
  }
  return out;
}

std::string describe_windows(const std::vector<FailureWindow>& windows,
                             const std::function<std::string(const FailureWindow&)>& detail) {
  std::string s = std::to_string(windows.size()) + (windows.size() == 1 ? " window: " : " windows: ");
  for (std::size_t k = 0; k < windows.size(); ++k) {
    const FailureWindow& w = windows[k];
    if (k > 0) s += ", ";
    s += format_value(w.start_deg, 5) + "-" + format_value(w.end_deg, 5) + " deg";
    const std::string d = detail ? detail(w) : std::string();
    if (!d.empty()) s += " (" + d + ")";
  }
  return s;
}

std::vector<FailureWindow> radius_windows(const std::vector<double>& angle_deg, const std::vector<double>& roc,
                                          double limit, bool concave_only) {
  if (!(limit > 0) || angle_deg.empty()) return {};
  // the margin in curvature, continuous through an inflection (flat: curvature 0)
  std::vector<double> margin, size;
  for (double r : roc) {
    const double kappa = r != 0.0 ? 1.0 / r : 0.0;
    margin.push_back(1.0 / limit - (concave_only ? -kappa : std::abs(kappa)));
    size.push_back(std::abs(r));
  }
  return failing_windows(angle_deg, margin, {}, size, true, true);
}

namespace {

// how far the polar angle runs back over a window and one sample either side [deg]: the
// largest drop from an earlier sample to a later one (a periodic profile winds once, so a
// sample past the seam is one turn on)
double fold_back_deg(const FoldSamples& s, const FailureWindow& w) {
  const int n = static_cast<int>(s.polar_deg.size());
  const int last = w.last >= w.first ? w.last : w.last + n;
  const int from = s.periodic ? w.first - 1 : std::max(0, w.first - 1);
  const int to = s.periodic ? last + 1 : std::min(n - 1, last + 1);
  double highest = -1e300, fold = 0.0;
  for (int k = from; k <= to; ++k) {
    const int turns = k < 0 ? -1 : k / n;
    const double polar = s.polar_deg[static_cast<std::size_t>(k - turns * n)] + 360.0 * turns;
    highest = std::max(highest, polar);
    fold = std::max(fold, highest - polar);
  }
  return fold;
}

}  // namespace

FoldReport fold_report(const FoldSamples& s) {
  FoldReport out;
  const std::size_t n = s.cam_deg.size();
  std::vector<char> in_cusp(n, 0);
  std::string cusp_text, turn_text;
  auto more = [&](const FailureWindow& w) {
    const std::string e = s.extra ? s.extra(w) : std::string();
    return e.empty() ? e : "; " + e;
  };
  // the cusps first: there the polar angle turns back as well
  if (!s.cusp.empty()) {
    out.cusp = failing_windows(s.cam_deg, s.cusp, s.cusp_slope, s.centre_radius_mm, true, s.periodic);
    for (const FailureWindow& w : out.cusp)
      for (std::size_t k = static_cast<std::size_t>(w.first);; k = (k + 1) % n) {
        in_cusp[k] = 1;
        if (k == static_cast<std::size_t>(w.last)) break;
      }
    if (!out.cusp.empty())
      cusp_text = "the roller's centre path curves tighter than the " + format_value(s.roller_mm, 6) +
                  " mm roller (the cam would need a negative radius of curvature) in " +
                  describe_windows(out.cusp, [&](const FailureWindow& w) {
                    return "centre path radius of curvature down to " + format_value(w.worst, 3) + " mm at " +
                           format_value(w.worst_at_deg, 5) + " deg" + more(w);
                  });
  }
  for (FailureWindow w : failing_windows(s.cam_deg, s.turn, s.turn_slope, s.turn, true, s.periodic)) {
    bool overlaps = false;
    for (std::size_t k = static_cast<std::size_t>(w.first);; k = (k + 1) % n) {
      overlaps = overlaps || in_cusp[k];
      if (k == static_cast<std::size_t>(w.last)) break;
    }
    if (overlaps) continue;
    w.worst = fold_back_deg(s, w);
    out.turn_back.push_back(w);
  }
  if (!out.turn_back.empty())
    turn_text = "the profile's polar angle turns back (it is not star-shaped about the profile origin) in " +
                describe_windows(out.turn_back, [&](const FailureWindow& w) {
                  return "folds back by " + format_value(w.worst, 3) + " deg of profile" + more(w);
                });
  out.message = cusp_text + (!cusp_text.empty() && !turn_text.empty() ? "; " : "") + turn_text;
  return out;
}

}  // namespace camopt::synthesis
