// step 4 of envelope synthesis (envelope.hpp): resampling. The envelope, sampled every h of
// the cam angle theta with its first two derivatives, is resampled by quintic hermite
// interpolation in theta at polar angles no further apart than the resolution in polar
// angle, cam angle or tangent turn, giving the polar table of the profile.
#include <algorithm>
#include <cmath>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/undercut_windows.hpp"

namespace camopt::synthesis::detail {

namespace {

// smallest (which < 0) or largest (which > 0) distance from the origin of a closed
// envelope sampled every h of theta: the extreme sample, refined by newton on
// d(x^2 + y^2)/dt = 0 over the quintic hermite pieces on both sides of it [mm]
double extreme_radius(const std::vector<P2<Jet2>>& env, double h, int which) {
  const int n = static_cast<int>(env.size());
  auto radius2 = [&](int i) { return env[i].x.value() * env[i].x.value() + env[i].y.value() * env[i].y.value(); };
  int best = 0;
  double best2 = radius2(0);
  for (int i = 1; i < n; ++i) {
    const double r2 = radius2(i);
    if ((r2 - best2) * which > 0) best = i, best2 = r2;
  }
  double out = std::sqrt(best2);
  for (int a : {(best + n - 1) % n, best}) {
    const int b = (a + 1) % n;
    auto hermite = [&](const Jet2& pa, const Jet2& pb) {
      return Quintic(pa.value(), pa.derivative(1) * h, pa.derivative(2) * h * h, pb.value(), pb.derivative(1) * h,
                     pb.derivative(2) * h * h);
    };
    const Quintic qx = hermite(env[a].x, env[b].x), qy = hermite(env[a].y, env[b].y);
    double t = 0.5, x, y, x1, y1, x2, y2;
    for (int it = 0; it < 30; ++it) {
      qx.eval(t, x, x1, x2);
      qy.eval(t, y, y1, y2);
      const double g = x * x1 + y * y1, g1 = x1 * x1 + y1 * y1 + x * x2 + y * y2;
      if (g1 == 0.0) break;
      const double next = std::clamp(t - g / g1, 0.0, 1.0);
      if (std::abs(next - t) < 1e-15) break;
      t = next;
    }
    qx.eval(t, x, x1, x2);
    qy.eval(t, y, y1, y2);
    if ((std::hypot(x, y) - out) * which > 0) out = std::hypot(x, y);
  }
  return out;
}

// the sample interval [lo, lo + 1] of a closed envelope (unwrapped polar angle phi, n + 1
// entries, monotone in the sense `sign`) that brackets polar angle `target`, brought into the
// traced range; the targets ascend about as densely as the samples, so the previous bracket
// (hint) and its neighbours are tried first, else bisection
int closed_bracket(const std::vector<double>& phi, double sign, double& target, int& hint) {
  const int n = static_cast<int>(phi.size()) - 1;
  // bring the target into the traced range
  const double target0 = target;
  target = target0 + 2 * pi * std::floor((std::min(phi[0], phi[n]) - target0) / (2 * pi) + 1.0);
  if (target > std::max(phi[0], phi[n])) target -= 2 * pi;
  auto holds = [&](int l) { return (phi[l] - target) * sign <= 0 && (phi[l + 1] - target) * sign > 0; };
  int lo = -1;
  for (int l : {hint, hint + 1, hint - 1})
    if (l >= 0 && l < n && holds(l)) {
      lo = l;
      break;
    }
  if (lo < 0) {
    lo = 0;
    for (int hi = n; hi - lo > 1;) {
      const int mid = (lo + hi) / 2;
      ((phi[mid] - target) * sign <= 0 ? lo : hi) = mid;
    }
  }
  hint = lo;
  return lo;
}

// the smallest convex and concave radii of curvature of the table, windows below the
// grinding wheel's and the smallest allowed radius
void summarize_curvature(const SynthesisOptions& options, SynthesisResult& result) {
  if (!result.has_concave) result.min_concave_radius_mm = 0.0;
  if (result.min_radius_of_curvature_mm == 1e300) result.min_radius_of_curvature_mm = 0.0;
  result.concave_narrower_than_wheel =
      result.has_concave && options.wheel_radius_mm > 0 && result.min_concave_radius_mm < options.wheel_radius_mm;
  result.concave_below_wheel =
      radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.wheel_radius_mm, true);
  result.below_min_radius = radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.min_radius_mm, false);
}

}  // namespace

// the envelope point at polar angle `target` [rad] between two samples a (at polar angle
// phi_a) and b (phi_b), theta spacing h: quintic hermite in theta from p, p', p'' at both
// ends, then newton on atan2(y, x) = target. Derivatives are per unit of the local
// parameter t in [0, 1].
PolarHit envelope_at_polar_angle(const P2<Jet2>& a, const P2<Jet2>& b, double phi_a, double phi_b, double h,
                                 double target) {
  auto hermite = [&](const Jet2& pa, const Jet2& pb) {
    return Quintic(pa.value(), pa.derivative(1) * h, pa.derivative(2) * h * h, pb.value(), pb.derivative(1) * h,
                   pb.derivative(2) * h * h);
  };
  const Quintic qx = hermite(a.x, b.x), qy = hermite(a.y, b.y);
  PolarHit p{};
  double t = (target - phi_a) / (phi_b - phi_a);
  // newton on the signed distance from the ray at `target`: f = (x, y) x (cos, sin) = 0
  // (the samples bracket the target within a fraction of a turn, so the ray is the right one)
  const double c = std::cos(target), s = std::sin(target);
  for (int it = 0; it < 30; ++it) {
    qx.eval(t, p.x, p.x1);
    qy.eval(t, p.y, p.y1);
    const double f = c * p.y - s * p.x, df = c * p.y1 - s * p.x1;
    const double step = f / df;
    t -= step;
    // [fraction of a sample interval] newton converges quadratically: after a step below
    // 1e-8 the next one would be below ~1e-16 times |f'' / f'|, so it is not taken
    if (std::abs(step) < 1e-8) break;
  }
  qx.eval(t, p.x, p.x1, p.x2);
  qy.eval(t, p.y, p.y1, p.y2);
  return p;
}

// radius of an envelope point and its first two derivatives in polar angle phi (out[0..2]),
// from the point's derivatives in its local parameter t: r_t = (x x' + y y') / r,
// phi_t = (x y' - y x') / r^2, then dr/dphi = r_t / phi_t and
// d2r/dphi2 = (r_tt - dr/dphi phi_tt) / phi_t^2
void polar_derivatives(const PolarHit& p, double out[3]) {
  const double r = std::sqrt(p.x * p.x + p.y * p.y);  // [mm], no overflow at cam sizes
  const double r_t = (p.x * p.x1 + p.y * p.y1) / r;
  const double phi_t = (p.x * p.y1 - p.y * p.x1) / (r * r);
  const double r_tt = (p.x1 * p.x1 + p.y1 * p.y1 + p.x * p.x2 + p.y * p.y2 - r_t * r_t) / r;
  const double phi_tt = (p.x * p.y2 - p.y * p.x2) / (r * r) - 2 * phi_t * r_t / r;
  out[0] = r;
  out[1] = r_t / phi_t;
  out[2] = (r_tt - out[1] * phi_tt) / (phi_t * phi_t);
}

// samples of the envelope per revolution: at least `requested`; when the target's knots
// are uniform from 0 (a table or a periodic_motion grid), a multiple of their count, so
// every sample interval lies inside one piece of the target and the hermite resampling in
// theta never straddles a jump in its 5th derivative
int envelope_samples(const PeriodicSpline& target, int requested) {
  const auto knots = target.knots();
  const int count = static_cast<int>(knots.size());
  if (count < 2 || std::abs(knots[0]) > 1e-12) return requested;
  const double step = target.period() / count;
  for (int i = 1; i < count; ++i)
    if (std::abs(knots[i] - i * step) > 1e-9 * step) return requested;
  return count * ((requested + count - 1) / count);
}

// polar angles of the profile table [rad] for a resolution of `step` [rad]. The target
// lift carries detail on the scale of the cam angle theta, and the kernel interpolates the
// table in polar angle phi: where the contact moves slowly in phi (a sharp nose under a
// flat face, a swing cam's short working stretch) a table uniform in phi would skip over
// several target knots. So the points are uniform in the measure
//   dw = max(|dphi|, |dtheta|, |dpsi|)   (psi: tangent direction of the envelope)
// i.e. no two neighbours are further apart than `step` in polar angle, in cam angle or in
// turn of the tangent. env / phi: the envelope sampled every h of theta and its unwrapped
// polar angle (phi.size() == env.size() + 1 when closed: the last entry is sample 0 one
// turn later). Closed: angles in [0, 2 pi), ascending, one point at polar angle 0.
// Open (a traced stretch): the stretch's own unwrapped angles, both ends included, in
// tracing order.
std::vector<double> resolution_angles(const std::vector<P2<Jet2>>& env, const std::vector<double>& phi, double h,
                                      double step, bool closed) {
  const std::size_t intervals = phi.size() - 1;
  // |dpsi / dtheta| = |x' y'' - y' x''| / (x'^2 + y'^2), trapezoidal over a sample interval
  auto turn_rate = [&](std::size_t i) {
    const P2<Jet2>& e = env[i % env.size()];
    const double x1 = e.x.derivative(1), y1 = e.y.derivative(1);
    return std::abs(x1 * e.y.derivative(2) - y1 * e.x.derivative(2)) / (x1 * x1 + y1 * y1);
  };
  std::vector<double> w(phi.size(), 0.0);
  double rate_prev = turn_rate(0);
  for (std::size_t i = 0; i < intervals; ++i) {
    const double rate = turn_rate(i + 1);
    const double turn = 0.5 * h * (rate_prev + rate);
    rate_prev = rate;
    w[i + 1] = w[i] + std::max({std::abs(phi[i + 1] - phi[i]), h, turn});
  }
  const double total = w.back();
  const int count = std::max(closed ? 6 : 2, static_cast<int>(std::ceil(total / step - 1e-9)));
  // phi at measure v (linear within a sample interval; newton on the envelope refines it);
  // the measures asked for ascend (once round, wrapping at most once), so a cursor walks w
  std::size_t cursor = 0;
  auto phi_at = [&](double v) {
    if (v < w[cursor]) cursor = 0;
    while (cursor + 1 < intervals && w[cursor + 1] <= v) ++cursor;
    const double t = (v - w[cursor]) / (w[cursor + 1] - w[cursor]);
    return phi[cursor] + t * (phi[cursor + 1] - phi[cursor]);
  };
  std::vector<double> out;
  if (!closed) {
    for (int k = 0; k <= count; ++k) out.push_back(k == count ? phi.back() : phi_at(total * k / count));
    return out;
  }
  // start where the envelope crosses polar angle 0 (mod 2 pi)
  const double dir = phi.back() > phi.front() ? 1.0 : -1.0;
  const double zero = phi.front() + dir * std::fmod(std::fmod(-dir * phi.front(), 2 * pi) + 2 * pi, 2 * pi);
  std::size_t i0 = 0;
  while (i0 + 1 < intervals && (phi[i0 + 1] - zero) * dir <= 0) ++i0;
  const double w0 = w[i0] + (w[i0 + 1] - w[i0]) * (zero - phi[i0]) / (phi[i0 + 1] - phi[i0]);
  // k = 0 .. count - 1 run once round from polar angle 0 in the tracing sense: wrapped into
  // [0, 2 pi) they ascend (counter-clockwise tracing) or, after k = 0, descend
  out.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    double v = w0 + total * k / count;
    if (v >= total) v -= total;
    if (k == 0) {
      out.push_back(0.0);
      continue;
    }
    // polar angle travelled from the start, in (0, 2 pi) for a profile winding once
    double a = (phi_at(v) - zero) * dir;
    a -= 2 * pi * std::floor(a / (2 * pi));
    out.push_back(dir > 0 ? a : 2 * pi - a);
  }
  if (dir < 0) std::reverse(out.begin() + 1, out.end());
  // guard against rounding at the ends of the turn (neighbours must stay strictly increasing)
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return !(b > a); }), out.end());
  return out;
}

// profile quantities from a polar table r(phi) with its derivatives dr/dphi, d2r/dphi2 at
// every point (those of the synthesized curve itself): point, curvature radius (convex > 0,
// 0 flat)
void finish_from_polar(SynthesisResult& result, double wheel_radius, const std::vector<double>& dr,
                       const std::vector<double>& ddr) {
  const int m = static_cast<int>(result.angle_deg.size());
  result.x_mm.resize(m);
  result.y_mm.resize(m);
  result.radius_of_curvature_mm.resize(m);
  result.min_radius_of_curvature_mm = 1e300;
  result.min_concave_radius_mm = 1e300;
  result.has_concave = false;
  for (int k = 0; k < m; ++k) {
    const double u = result.angle_deg[k] * pi / 180, r = result.radius_mm[k];
    result.x_mm[k] = r * std::cos(u);
    result.y_mm[k] = r * std::sin(u);
    // polar curvature (r^2 + 2 r'^2 - r r'') / (r^2 + r'^2)^1.5, + convex
    const double kappa = (r * r + 2 * dr[k] * dr[k] - r * ddr[k]) / curvature_denominator(r * r + dr[k] * dr[k]);
    const double roc = std::abs(kappa) > 1e-12 ? 1.0 / kappa : 0.0;
    result.radius_of_curvature_mm[k] = roc;
    if (kappa > 0 && roc < result.min_radius_of_curvature_mm)
      result.min_radius_of_curvature_mm = roc, result.min_radius_of_curvature_at_deg = result.angle_deg[k];
    if (kappa < -1e-12 && -roc < result.min_concave_radius_mm)
      result.has_concave = true, result.min_concave_radius_mm = -roc, result.min_concave_radius_at_deg = result.angle_deg[k];
  }
  if (!result.has_concave) result.min_concave_radius_mm = 0.0;
  if (result.min_radius_of_curvature_mm == 1e300) result.min_radius_of_curvature_mm = 0.0;
  result.concave_narrower_than_wheel = result.has_concave && wheel_radius > 0 && result.min_concave_radius_mm < wheel_radius;
  result.concave_below_wheel = radius_windows(result.angle_deg, result.radius_of_curvature_mm, wheel_radius, true);
  result.base_radius_mm = *std::min_element(result.radius_mm.begin(), result.radius_mm.end());
  result.max_radius_mm = *std::max_element(result.radius_mm.begin(), result.radius_mm.end());
}

void resample_polar(const std::vector<P2<Jet2>>& env, const std::vector<double>& phi, double sign,
                    const SynthesisOptions& options, const std::string& profile_name, SynthesisResult& result) {
  const int n = static_cast<int>(env.size());
  // resample at polar angles chosen by resolution_angles, each point by quintic hermite
  // interpolation in theta and newton on its polar angle
  const double h = 2 * pi / n;
  const std::vector<double> targets = resolution_angles(env, phi, h, 2 * pi / options.points, true);
  const int m = static_cast<int>(targets.size());
  result.angle_deg.resize(m);
  result.radius_mm.resize(m);
  result.x_mm.resize(m);
  result.y_mm.resize(m);
  result.radius_of_curvature_mm.resize(m);
  result.min_radius_of_curvature_mm = 1e300;
  result.min_concave_radius_mm = 1e300;
  int hint = 0;
  for (int k = 0; k < m; ++k) {
    const double target0 = targets[k];
    double target = target0;
    const int lo = closed_bracket(phi, sign, target, hint), hi = lo + 1;
    const PolarHit p = envelope_at_polar_angle(env[lo], env[hi % n], phi[lo], phi[hi], h, target);
    const double x = p.x, y = p.y, x1 = p.x1, y1 = p.y1, x2 = p.x2, y2 = p.y2;
    const double r = std::hypot(x, y);
    // curvature, convex positive: the profile runs counter-clockwise when sign > 0
    const double kappa = sign * (x1 * y2 - y1 * x2) / curvature_denominator(x1 * x1 + y1 * y1);
    const double roc = std::abs(kappa) > 1e-12 ? 1.0 / kappa : 0.0;  // 0: flat
    result.angle_deg[k] = target0 * 180 / pi;
    result.radius_mm[k] = r;
    result.x_mm[k] = x;
    result.y_mm[k] = y;
    result.radius_of_curvature_mm[k] = roc;
    if (kappa > 0 && roc < result.min_radius_of_curvature_mm) {
      result.min_radius_of_curvature_mm = roc;
      result.min_radius_of_curvature_at_deg = target0 * 180 / pi;
    }
    if (kappa < -1e-12 && -roc < result.min_concave_radius_mm) {
      result.has_concave = true;
      result.min_concave_radius_mm = -roc;
      result.min_concave_radius_at_deg = target0 * 180 / pi;
    }
  }
  summarize_curvature(options, result);
  result.base_radius_mm = extreme_radius(env, h, -1);
  result.max_radius_mm = extreme_radius(env, h, +1);
  result.profile.name = profile_name;
  result.profile.form = ProfileForm::polar;
  result.profile.angle_deg = result.angle_deg;
  result.profile.radius_mm = result.radius_mm;
}

}  // namespace camopt::synthesis::detail
