#include "camopt/synthesis/swing_remedy.hpp"

#include <algorithm>
#include <vector>

#include "camopt/core/error.hpp"

namespace camopt::synthesis {

namespace {

// s x lift: the periodic quintic interpolant is linear in its data, so the spline through
// the scaled values at the same knots is the scaled spline (to rounding)
PeriodicSpline scaled(const PeriodicSpline& lift, double s) {
  const auto knots = lift.knots();
  std::vector<double> x(knots.begin(), knots.end()), y;
  y.reserve(x.size());
  for (double k : x) y.push_back(s * lift(k));
  return PeriodicSpline::interpolate(x, y, lift.period());
}

}  // namespace

LiftScaleBound largest_synthesizable_scale(const DesignSpec& spec, const PeriodicSpline& lift,
                                           const SynthesisOptions& options, double smallest_scale, int steps) {
  LiftScaleBound out;
  for (double k : lift.knots()) out.peak_mm = std::max(out.peak_mm, lift(k));
  SynthesisOptions probe = options;
  probe.remedies = false;  // no bisection inside the bisection
  auto synthesizes = [&](double s) {
    SynthesisResult res;
    ++out.syntheses;
    return synthesize(spec, scaled(lift, s), probe, res).ok();
  };
  if (!synthesizes(smallest_scale)) {
    out.failing_scale = smallest_scale;
    return out;
  }
  out.found = true;
  double lo = smallest_scale, hi = 1.0;
  for (int k = 0; k < steps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (synthesizes(mid) ? lo : hi) = mid;
  }
  out.scale = lo;
  out.failing_scale = hi;
  return out;
}

std::string swing_remedy_text(const LiftScaleBound& bound, double smallest_scale) {
  std::string s;
  if (bound.found)
    s = "The same lift shape scaled to a peak of " + format_value(bound.scale * bound.peak_mm, 3) +
        " mm synthesizes (at " + format_value(bound.failing_scale * bound.peak_mm, 3) +
        " mm it still fails): lower the peak lift below " + format_value(bound.failing_scale * bound.peak_mm, 3) +
        " mm";
  else
    s = "The same lift shape scaled down to " + format_value(smallest_scale * bound.peak_mm, 3) +
        " mm of peak lift still fails: its timing against the swing cam's motion, not its height, is the cause";
  return s + "; or let `camopt optimize --cam swing` find the nearest lift this mechanism can give (it designs the "
             "swing cam's pitch curve against the swing angle, so the lift is one by construction)";
}

}  // namespace camopt::synthesis
