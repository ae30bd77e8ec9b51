#include "camopt/synthesis/detail/fold_status.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "camopt/synthesis/undercut_windows.hpp"

namespace camopt::synthesis::detail {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double kPerDeg = pi / 180;  // [rad per deg]

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
    s.polar_deg.push_back(sign * phi[static_cast<std::size_t>(i)] / kPerDeg);
    double rate, slope;
    polar_rate(env[static_cast<std::size_t>(i)], rate, slope);
    s.turn.push_back(sign * rate);
    s.turn_slope.push_back(sign * slope * kPerDeg);
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
      s.cusp_slope.push_back(-roller_mm * kappa_slope * kPerDeg);
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
                         const std::vector<double>& valve_rate, double roller_mm) {
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
    s.polar_deg.push_back(dir * phi[j] / kPerDeg);
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
  // what the target asks of the swing over a window: the valve's travel against the swing
  // cam's turn (trapezoidal sums of their rates over the window's samples)
  s.extra = [&](const FailureWindow& w) {
    double lift = 0.0, swing = 0.0, slowest = 1e300;
    const int from = std::max(0, w.first - 1), to = std::min(static_cast<int>(m) - 1, w.last + 1);
    for (int j = from; j <= to; ++j) {
      const auto i = static_cast<std::size_t>(run[static_cast<std::size_t>(j)]);
      if (j > from) {
        const auto before = static_cast<std::size_t>(run[static_cast<std::size_t>(j - 1)]);
        lift += 0.5 * (valve_rate[before] + valve_rate[i]) * h;
        swing += 0.5 * (cam_rate[before] + cam_rate[i]) * h;
      }
      if (j >= w.first && j <= w.last) slowest = std::min(slowest, std::abs(cam_rate[i]) / max_rate);
    }
    return "the target moves the valve " + format_value(std::abs(lift), 3) + " mm while the swing cam turns " +
           format_value(std::abs(swing) / kPerDeg, 3) + " deg, at " + format_value(slowest, 3) +
           " of its peak rate or more";
  };
  const FoldReport report = fold_report(s);
  std::string message = "the synthesized swing profile folds back on itself (undercut or cusp): " + report.message;
  // a fold where the swing barely moves (next to the ends of its stroke) is the target's own ripple
  const std::size_t at = std::min(first_failing, m - 1);
  const double rate = std::abs(cam_rate[static_cast<std::size_t>(run[at])]) / max_rate;
  if (rate < 0.05)
    message += ". The swing cam moves at " + format_value(rate, 3) + " of its peak rate at cam " +
               format_value(theta[static_cast<std::size_t>(run[at])] * 180 / pi, 6) + " deg: so slow a swing is where its stroke starts or ends, and a "
               "fold there comes from ripple in the target lift; sample the target more finely, or smooth it (--smooth)";
  else if (!report.cusp.empty() && smallest_convex < roller_mm)
    message += ". The swing cam turns the target into a lift against the swing angle, and this one bends over "
               "faster than the " + format_value(roller_mm, 6) + " mm roller can follow: a roller of radius below " +
               format_value(smallest_convex, 3) + " mm would";
  return {StatusCode::undercut, message, "cam " + format_value(theta[static_cast<std::size_t>(run[at])] * 180 / pi, 6) + " deg"};
}

}  // namespace camopt::synthesis::detail
