#include "camopt/synthesis/detail/fold_status.hpp"

#include <algorithm>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/undercut_windows.hpp"

namespace camopt::synthesis::detail {

namespace {

// rate of the polar angle of a point (x, y) along its parameter, and its derivative
// [rad per unit, per unit^2]: (x y' - y x') / r^2
void polar_rate(const P2<Jet<2>>& e, double& rate, double& slope) {
  const double x = e.x.value(), y = e.y.value(), x1 = e.x.derivative(1), y1 = e.y.derivative(1);
  const double r2 = x * x + y * y;
  rate = (x * y1 - y * x1) / r2;
  slope = (x * e.y.derivative(2) - y * e.x.derivative(2)) / r2 - rate * 2 * (x * x1 + y * y1) / r2;
}

// curvature of a path (convex > 0 when it runs in the polar sense `sense` about the origin)
// [1/mm] and its derivative along the path parameter [1/mm per unit]
void path_curvature(const P2<Jet<3>>& c, double sense, double& kappa, double& slope) {
  const double x1 = c.x.derivative(1), y1 = c.y.derivative(1), x2 = c.x.derivative(2), y2 = c.y.derivative(2);
  const double speed2 = x1 * x1 + y1 * y1, speed = std::sqrt(speed2);
  kappa = sense * (x1 * y2 - y1 * x2) / (speed2 * speed);
  slope = sense * (x1 * c.y.derivative(3) - y1 * c.x.derivative(3)) / (speed2 * speed) -
          3 * kappa * (x1 * x2 + y1 * y2) / speed2;
}

// [mm] valve travel over a fold window below which a fold at a slow swing is taken for ripple
// in the target (a table's interpolation ripple, ~1e-6 mm; a ramp that lifts the valve before
// the swing cam moves: 0.1 mm)
constexpr double kRippleLift = 1e-3;

// [deg] a target that peaks this far from where the swing cam turns back is named as mistimed
constexpr double kPeakMismatchDeg = 0.05;

// where the swing cam turns back after the opening stroke `run` (its rate changes sign) and
// where the target peaks (its rate turns from rising to falling, the nearest such point):
// "; it turns back at cam X deg, the target peaks at cam Z deg: in between the lift is no
// function of the swing angle, at any scale", or empty when they are within kPeakMismatchDeg
std::string swing_timing_text(const std::vector<int>& run, const std::vector<double>& theta,
                              const std::vector<double>& cam_rate, const std::vector<double>& valve_rate) {
  const int n = static_cast<int>(theta.size());
  const double open = cam_rate[static_cast<std::size_t>(run.front())] > 0 ? 1.0 : -1.0;
  // the zero of rate between samples i and i + 1 [sample units]
  auto zero = [&](const std::vector<double>& rate, int i) {
    const double a = rate[static_cast<std::size_t>(i)], b = rate[static_cast<std::size_t>((i + 1) % n)];
    return i + (a != b ? a / (a - b) : 0.0);
  };
  int i = run.back();
  for (int k = 0; k < n && cam_rate[static_cast<std::size_t>((i + 1) % n)] * open > 0; ++k) i = (i + 1) % n;
  const double turn = zero(cam_rate, i);
  double peak = turn;
  for (int k = 0; k < n / 2; ++k) {
    auto peaks = [&](int j) {
      return valve_rate[static_cast<std::size_t>(j)] > 0 && valve_rate[static_cast<std::size_t>((j + 1) % n)] <= 0;
    };
    if (peaks((i + k) % n)) { peak = zero(valve_rate, (i + k) % n) + (i + k >= n ? n : 0); break; }
    if (peaks((i - k + n) % n)) { peak = zero(valve_rate, (i - k + n) % n) - (i - k < 0 ? n : 0); break; }
  }
  const double step_deg = 360.0 / n;
  if (!(std::abs(peak - turn) * step_deg > kPeakMismatchDeg)) return "";
  auto deg = [&](double samples) { return format_value(std::fmod(samples * step_deg + 360.0, 360.0), 5); };
  return "; it turns back at cam " + deg(turn) + " deg, but the target peaks at cam " + deg(peak) +
         " deg: in between the lift is no function of the swing angle, at any scale (a lift must peak where the "
         "swing cam turns back)";
}

}  // namespace

Status revolution_fold_status(const std::vector<P2<Jet<2>>>& env, const std::vector<P2<Jet<3>>>& path,
                              const std::vector<double>& phi, double sign, double orient, double roller_mm) {
  const int n = static_cast<int>(env.size());
  const bool roller = roller_mm >= 0;
  FoldSamples s;
  s.periodic = true;
  s.roller_mm = roller_mm;
  int first_failing = -1;
  for (int i = 0; i < n; ++i) {
    s.cam_deg.push_back(360.0 * i / n);
    s.polar_deg.push_back(sign * phi[static_cast<std::size_t>(i)] / rad_per_deg);
    double rate, slope;
    polar_rate(env[static_cast<std::size_t>(i)], rate, slope);
    s.turn.push_back(sign * rate);
    s.turn_slope.push_back(sign * slope * rad_per_deg);
    bool fails = !(sign * rate > 0);
    if (roller) {
      // the envelope's speed along its centre path, e'.c' = |c'|^2 (1 - roller kappa)
      const auto& c = path[static_cast<std::size_t>(i)];
      const auto& e = env[static_cast<std::size_t>(i)];
      const double x1 = c.x.derivative(1), y1 = c.y.derivative(1);
      const double along = e.x.derivative(1) * x1 + e.y.derivative(1) * y1;
      double kappa, kappa_slope;
      path_curvature(c, orient, kappa, kappa_slope);
      s.cusp.push_back(along / (x1 * x1 + y1 * y1));
      s.cusp_slope.push_back(-roller_mm * kappa_slope * rad_per_deg);
      s.centre_radius_mm.push_back(kappa != 0.0 ? 1.0 / kappa : 0.0);
      fails = fails || along <= 0.0;
    }
    if (fails && first_failing < 0) first_failing = i;
  }
  const FoldReport report = fold_report(s);
  return {StatusCode::undercut, "the synthesized profile folds back on itself (undercut or cusp): " + report.message,
          "cam " + format_value(s.cam_deg[static_cast<std::size_t>(std::max(first_failing, 0))], 6) + " deg"};
}

Status swing_fold_status(const std::vector<P2<Jet<2>>>& env, const std::vector<double>& phi, double dir,
                         const std::vector<int>& run, const std::vector<P2<Jet<3>>>& path,
                         const std::vector<double>& theta, const std::vector<double>& cam_rate, double max_rate,
                         const std::vector<double>& valve_rate, double roller_mm, bool& ripple) {
  const std::size_t m = run.size();
  const double h = 2 * pi / static_cast<double>(theta.size());  // [rad] sample spacing
  FoldSamples s;
  s.periodic = false;
  s.roller_mm = roller_mm;
  double smallest_convex = 1e300;  // [mm] the centre path's smallest convex radius over the stretch
  std::size_t first_failing = m;
  for (std::size_t j = 0; j < m; ++j) {
    const int i = run[j];
    // cam angle along the run (it may pass 360 deg)
    s.cam_deg.push_back(360.0 * static_cast<double>(run[0] + static_cast<int>(j)) / static_cast<double>(theta.size()));
    s.polar_deg.push_back(dir * phi[j] / rad_per_deg);
    // the polar rate of the envelope point, or of its step from the last sample if that turns back
    double rate, slope;
    polar_rate(env[j], rate, slope);
    double turn = dir * rate;
    if (j > 0) turn = std::min(turn, dir * (phi[j] - phi[j - 1]) / h);
    s.turn.push_back(turn);
    double kappa, kappa_slope;
    path_curvature(path[static_cast<std::size_t>(i)], dir, kappa, kappa_slope);
    s.cusp.push_back(1.0 - roller_mm * kappa);
    s.centre_radius_mm.push_back(kappa != 0.0 ? 1.0 / kappa : 0.0);
    if (kappa > 0) smallest_convex = std::min(smallest_convex, 1.0 / kappa);
    if (j > 0 && (phi[j] - phi[j - 1]) * dir <= 0 && first_failing == m) first_failing = j;
  }
  // what the target asks of the swing over a window and a sample either side: the valve's
  // travel against the swing cam's turn (trapezoidal sums of their rates), and the slowest
  // swing inside it (a fraction of the peak rate)
  struct Travel {
    double lift_mm = 0, swing_deg = 0, slowest = 1e300;
  };
  auto travel = [&](const FailureWindow& w) {
    Travel t;
    const int from = std::max(0, w.first - 1), to = std::min(static_cast<int>(m) - 1, w.last + 1);
    for (int j = from; j <= to; ++j) {
      const auto i = static_cast<std::size_t>(run[static_cast<std::size_t>(j)]);
      if (j > from) {
        const auto before = static_cast<std::size_t>(run[static_cast<std::size_t>(j - 1)]);
        t.lift_mm += 0.5 * (valve_rate[before] + valve_rate[i]) * h;
        t.swing_deg += 0.5 * (cam_rate[before] + cam_rate[i]) * h / rad_per_deg;
      }
      if (j >= w.first && j <= w.last) t.slowest = std::min(t.slowest, std::abs(cam_rate[i]) / max_rate);
    }
    t.lift_mm = std::abs(t.lift_mm), t.swing_deg = std::abs(t.swing_deg);
    return t;
  };
  s.extra = [&](const FailureWindow& w) {
    const Travel t = travel(w);
    return "the target moves the valve " + format_value(t.lift_mm, 3) + " mm while the swing cam turns " +
           format_value(t.swing_deg, 3) + " deg, at " + format_value(t.slowest, 3) + " of its peak rate or more";
  };
  const FoldReport report = fold_report(s);
  std::string message = "the synthesized swing profile folds back on itself (undercut or cusp): " + report.message +
                        ". The swing cam makes the valve lift a function of its swing angle";
  message += swing_timing_text(run, theta, cam_rate, valve_rate);
  // a fold where the swing barely moves (next to the ends of its stroke) and the valve hardly
  // either is the target's own ripple
  const std::size_t at = std::min(first_failing, m - 1);
  const double rate = std::abs(cam_rate[static_cast<std::size_t>(run[at])]) / max_rate;
  const std::vector<FailureWindow>& windows = report.cusp.empty() ? report.turn_back : report.cusp;
  ripple = rate < 0.05 && (windows.empty() || travel(windows.front()).lift_mm < kRippleLift);
  if (!ripple && !report.cusp.empty() && smallest_convex < roller_mm)
    message += "; this one bends faster than the " + format_value(roller_mm, 6) + " mm roller can follow (a roller " +
               "of radius below " + format_value(smallest_convex, 3) + " mm would)";
  if (ripple)
    message += ". The swing cam moves at " + format_value(rate, 3) + " of its peak rate at cam " +
               format_value(theta[static_cast<std::size_t>(run[at])] * 180 / pi, 6) + " deg: so slow a swing is where "
               "its stroke starts or ends, and a fold there comes from ripple in the target lift; sample the target "
               "more finely, or smooth it (--smooth)";
  return {StatusCode::undercut, message, "cam " + format_value(theta[static_cast<std::size_t>(run[at])] * 180 / pi, 6) + " deg"};
}

}  // namespace camopt::synthesis::detail
