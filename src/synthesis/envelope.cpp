#include "camopt/synthesis/envelope.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <type_traits>

#include "camopt/core/jet.hpp"
#include "camopt/kinematics/detail/geometry.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/detail/fold_status.hpp"
#include "camopt/synthesis/detail/hermite.hpp"
#include "camopt/synthesis/floating_inversion.hpp"
#include "camopt/synthesis/lever_path.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"
#include "camopt/synthesis/swing_remedy.hpp"

namespace camopt::synthesis {

namespace {

using detail::Quintic;
using detail::Septic;
constexpr double pi = std::numbers::pi;
// levels of the target motion at which the downstream chain is solved for the inversion
// (septic hermite between them). On the bundled designs 16 and 32 levels give profiles
// within 8e-13 mm of each other (conventional cams; swing cams 2.7e-10 mm, whose far side
// magnifies it), so 32 levels leave hermite error far below round-off. More levels add
// noise: the derivatives of a hermite piece divide the solves' round-off by powers of the
// level spacing (64 levels moved the rocker arm's profile by 5.8e-10 mm). The round trips
// are the same to 4 digits at 16, 32 and 64 levels
constexpr int kInversionLevels = 32;
// [rad] spacing of the upstream solves for a cam that is not the driver (a swing cam, a
// floating lever); septic hermite in the driver angle between them. 1.5 deg would leave the
// bundled designs' round trips at their drawing controls unchanged, but at the
// Valvetronic's part-lift controls it raises them up to 12 times (7.6e-8 mm at 55 deg) and
// at 60 deg the interpolated lever motion folds the traced stretch (cam 91 deg)
constexpr double kUpstreamSpacing = 1.0 * pi / 180;
// where the cam rests at a solve (its taylor terms of order 1 to 3 over the stretch move it
// by less than kRestMotion rad or mm: the implicit derivatives on a dwell are round-off,
// ~1e-13, 1e-11 and 1e-9 for a floating lever), the next solve is tried kRestStride spacings
// on; a stretch that rests at both ends at the same pose (within kRestMotion) is taken as a
// dwell, else it is solved at every spacing. A motion shorter than the stretch and at rest
// to third order at both of its ends would be missed: no cam lobe or lever stroke is that short.
constexpr int kRestStride = 6;
constexpr double kRestMotion = 1e-12;
using Jet3 = Jet<3>;
using Jet2 = Jet<2>;

std::string fmt(double v) { return format_value(v, 6); }

// d/dt of a jet, one order lower
Jet2 derivative_of(const Jet3& x) {
  Jet2 d;
  for (int k = 0; k < 3; ++k) d.c[k] = (k + 1) * x.c[k + 1];
  return d;
}

using detail::P2;


// v^1.5 [mm^3]: the denominator of a curvature from a squared speed v
double curvature_denominator(double v) { return v * std::sqrt(v); }

// the envelope point at polar angle `target` [rad] between two samples a (at polar angle
// phi_a) and b (phi_b), theta spacing h: quintic hermite in theta from p, p', p'' at both
// ends, then newton on atan2(y, x) = target. Derivatives are per unit of the local
// parameter t in [0, 1].
struct PolarHit {
  double x, y, x1, y1, x2, y2;
};

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

}  // namespace

namespace {

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

// the resting follower's centre in the cam's profile frame at one control position, with
// its tangent d/dcontrol [mm, mm per control unit]
struct IdleCentre {
  double x, y, tx, ty;
};

// a swing cam is traced only while it moves, forth while the valve opens and back while it
// closes, over the same stretch of profile. The opening stroke gives the profile; the
// closing stroke must retrace it (else the target lift is not a function of the swing
// angle). Beyond the rest contact the profile continues as the dwell arc about the swing
// pivot (where other control positions rest); the untouched rest of the turn is bridged by
// a quintic in polar angle matching radius, slope and curvature at both ends.
Status swing_profile(const DesignSpec& spec, const kin::Mechanism& up, const MechanismCut& cut, const SurfaceSpec& cam_surface,
                     double radius, bool roller, const std::vector<P2<Jet3>>& path,
                     const std::vector<P2<Jet3>>& normal, const std::vector<double>& theta,
                     const std::vector<double>& cam_rate, const std::vector<double>& valve_rate,
                     const std::vector<IdleCentre>& idle_centres, const SynthesisOptions& options,
                     SynthesisResult& result, bool& folds) {
  // folds: the traced stretch folds back for the target's shape (not its ripple)
  (void)spec;
  if (!roller)
    throw InputError("synthesize --cam swing: the swing cam's follower must be a roller or pad (circle), not a flat face");
  (void)normal;
  const int n = static_cast<int>(theta.size());
  double max_rate = 0.0;
  for (double r : cam_rate) max_rate = std::max(max_rate, std::abs(r));
  if (!(max_rate > 0))
    return {StatusCode::undercut, "the swing cam does not move over the revolution", "whole revolution"};
  // opening stroke: the sense of swing motion while the valve opens fastest
  const int fastest = static_cast<int>(std::max_element(valve_rate.begin(), valve_rate.end()) - valve_rate.begin());
  const double open_sign = cam_rate[fastest] > 0 ? 1.0 : -1.0;
  // moving: faster than 1e-3 of the peak swing rate (table cams ripple at ~1e-5 on their ramps)
  auto opening = [&](int i) { return cam_rate[i] * open_sign > 1e-3 * max_rate; };
  // the opening stroke: the longest contiguous run of opening samples (cyclic); any other
  // run must be a negligible ripple
  std::vector<std::pair<int, int>> runs;  // (start, length)
  for (int i = 0; i < n; ++i)
    if (opening(i) && !opening((i + n - 1) % n)) {
      int len = 0;
      while (len < n && opening((i + len) % n)) ++len;
      runs.push_back({i, len});
    }
  if (runs.empty()) return {StatusCode::undercut, "no opening stroke of the swing cam found", "whole revolution"};
  std::sort(runs.begin(), runs.end(), [](auto a, auto b) { return a.second > b.second; });
  if (runs.size() > 1 && runs[1].second > n / 50)
    return {StatusCode::undercut, "the swing cam opens more than once per revolution",
            "cam " + fmt(theta[runs[1].first] * 180 / pi) + " deg"};
  std::vector<int> run;
  for (int j = 0; j < runs[0].second; ++j) run.push_back((runs[0].first + j) % n);
  // envelope of the roller along the run: p = c - r nu, nu the centre path normal pointing
  // away from the profile origin (the roller is outside the cam)
  auto envelope = [&](int i) {
    const P2<Jet2> d{derivative_of(path[i].x), derivative_of(path[i].y)};
    const Jet2 len = sqrt(d.x * d.x + d.y * d.y);
    P2<Jet2> nu{d.y / len, -d.x / len};
    if (nu.x.value() * path[i].x.value() + nu.y.value() * path[i].y.value() < 0) nu = {-1.0 * nu.x, -1.0 * nu.y};
    return P2<Jet2>{truncate<2>(path[i].x) - radius * nu.x, truncate<2>(path[i].y) - radius * nu.y};
  };
  std::vector<P2<Jet2>> env;
  std::vector<double> phi;
  for (int i : run) {
    env.push_back(envelope(i));
    double a = std::atan2(env.back().y.value(), env.back().x.value());
    if (!phi.empty()) a += 2 * pi * std::round((phi.back() - a) / (2 * pi));
    phi.push_back(a);
  }
  const double dir = phi.back() > phi.front() ? 1.0 : -1.0;
  // the stretch must run on in polar angle: else every window where it folds back
  for (std::size_t j = 1; j < phi.size(); ++j)
    if ((phi[j] - phi[j - 1]) * dir <= 0) {
      bool ripple = false;
      const Status st = detail::swing_fold_status(env, phi, dir, run, path, theta, cam_rate, max_rate, valve_rate,
                                                  radius, ripple);
      folds = !ripple;
      return st;
    }
  // radius on the traced stretch at polar angle a (quintic hermite in theta between
  // samples), with dr/da and d2r/da2 (out[0..2])
  const double h = 2 * pi / n;
  // the sample interval [lo, lo + 1] holding polar angle a (the first or last interval
  // beyond the ends): the last answer and its neighbours first (the lookups mostly walk
  // along the stretch), else bisection
  const int last_interval = static_cast<int>(phi.size()) - 2;
  int hint = 0;
  auto bracket = [&](double a) {
    auto holds = [&](int lo) {
      return (lo == 0 || (phi[lo] - a) * dir <= 0) && (lo == last_interval || (phi[lo + 1] - a) * dir > 0);
    };
    for (int lo : {hint, hint + 1, hint - 1})
      if (lo >= 0 && lo <= last_interval && holds(lo)) return hint = lo;
    int lo = 0, hi = last_interval + 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      ((phi[mid] - a) * dir <= 0 ? lo : hi) = mid;
    }
    return hint = lo;
  };
  auto traced_hit = [&](double a) {
    const int lo = bracket(a);
    return envelope_at_polar_angle(env[lo], env[lo + 1], phi[lo], phi[lo + 1], h, a);
  };
  auto traced_polar = [&](double a, double out[3]) { polar_derivatives(traced_hit(a), out); };
  auto traced_radius = [&](double a) {
    const PolarHit p = traced_hit(a);
    return std::sqrt(p.x * p.x + p.y * p.y);
  };
  // the closing stroke must retrace the opening one: radial distance of each closing
  // envelope point from the traced profile at its polar angle (or from the nearer end of
  // the stretch when it lies beyond it)
  double worst = 0.0, worst_at = 0.0;
  const double lo_phi = std::min(phi.front(), phi.back()), hi_phi = std::max(phi.front(), phi.back());
  for (int i = 0; i < n; ++i) {
    if (!(cam_rate[i] * open_sign < -1e-3 * max_rate)) continue;
    const P2<Jet2> q = envelope(i);
    const double qx = q.x.value(), qy = q.y.value();
    double a = std::atan2(qy, qx);
    a += 2 * pi * std::round((0.5 * (lo_phi + hi_phi) - a) / (2 * pi));
    double off = 0.0;
    if (a >= lo_phi && a <= hi_phi) {
      off = std::abs(std::hypot(qx, qy) - traced_radius(a));
    } else {
      const P2<Jet2>& end = std::abs(a - phi.front()) < std::abs(a - phi.back()) ? env.front() : env.back();
      off = std::hypot(qx - end.x.value(), qy - end.y.value());
    }
    if (off > worst) worst = off, worst_at = theta[i];
  }
  if (worst > 5e-3)  // [mm] grinding accuracy
    return {StatusCode::undercut,
            "the closing stroke of the swing cam does not retrace the opening stroke (off by " + fmt(worst) +
                " mm): the target lift is not a function of the swing angle",
            "cam " + fmt(worst_at * 180 / pi) + " deg"};
  result.notes.push_back("swing cam traced over " + fmt(std::abs(phi.back() - phi.front()) * 180 / pi) +
                         " deg of its profile; closing stroke retraces it within " + fmt(worst) + " mm (at cam " +
                         fmt(worst_at * 180 / pi) + " deg; the round trip on the closing stroke is limited by this)");

  // dwell arc about the swing pivot, in the profile frame (a floating lever has no pivot:
  // an arc about the profile origin)
  const kin::Node& swing = up.nodes[up.node_index(cut.cam_node)];
  const double ox = cam_surface.origin_mm[0], oy = cam_surface.origin_mm[1];
  const double co = std::cos(cam_surface.orientation_deg * pi / 180), so = std::sin(cam_surface.orientation_deg * pi / 180);
  const bool floating = swing.kind == NodeKind::floating;
  const double px = floating ? 0.0 : co * (swing.pivot.x() - ox) + so * (swing.pivot.y() - oy);
  const double py = floating ? 0.0 : -so * (swing.pivot.x() - ox) + co * (swing.pivot.y() - oy);
  const double rest_x = env.front().x.value(), rest_y = env.front().y.value();
  const double dwell = std::hypot(rest_x - px, rest_y - py);
  auto dwell_polar = [&](double a, double out[3]) {
    // ray from the origin at angle a meets the circle |x - P| = dwell: r = b + sqrt(D),
    // b = P.u(a), D = b^2 - |P|^2 + dwell^2 (b'' = -b)
    const double ux = std::cos(a), uy = std::sin(a);
    const double b = px * ux + py * uy, b1 = -px * uy + py * ux;
    const double disc = b * b - (px * px + py * py - dwell * dwell);
    const double root = std::sqrt(std::max(0.0, disc));
    out[0] = b + root;
    // D' = 2 b b', D'' = 2 (b'^2 - b^2)
    const double disc1 = 2 * b * b1, disc2 = 2 * (b1 * b1 - b * b);
    out[1] = root > 0 ? b1 + disc1 / (2 * root) : b1;
    out[2] = root > 0 ? -b + disc2 / (2 * root) - disc1 * disc1 / (4 * root * root * root) : -b;
  };
  // idle curve: where the follower rests at the other control positions. With controls,
  // the envelope of the resting roller over the control family (its centres in the profile
  // frame, idle_centres, in control order): a dwell arc about the pivot when the pivot stays
  // put (CVVL), the control arm's idle curve when it moves with the control (VVLD). It is
  // used on the far side of the rest contact, as a function of the polar distance
  // delta = (phi_start - a) * dir beyond it; empty: the dwell arc alone.
  const double phi_start = phi.front(), phi_end = phi.back();
  const double untouched = 2 * pi - std::abs(phi_end - phi_start);
  Spline idle;
  double idle_reach = 0.0;  // [rad] of polar distance covered by the idle curve
  if (idle_centres.size() >= 8) {
    const std::size_t nc = idle_centres.size();
    std::vector<std::pair<double, double>> beyond;  // (delta, radius)
    for (std::size_t j = 0; j < nc; ++j) {
      const double tx = idle_centres[j].tx, ty = idle_centres[j].ty;
      const double len = std::hypot(tx, ty);
      if (!(len > 1e-12)) continue;  // the centre stands still: no envelope point
      double nx = ty / len, ny = -tx / len;
      if (nx * idle_centres[j].x + ny * idle_centres[j].y < 0) nx = -nx, ny = -ny;  // away from the origin
      const double x = idle_centres[j].x - radius * nx, y = idle_centres[j].y - radius * ny;
      double delta = (phi_start - std::atan2(y, x)) * dir;
      delta -= 2 * pi * std::floor(delta / (2 * pi));
      if (delta > pi) continue;  // on the traced side of the rest contact
      beyond.push_back({delta, std::hypot(x, y)});
    }
    std::sort(beyond.begin(), beyond.end());
    // the idle curve starts at the rest contact itself (value continuity with the stretch)
    std::vector<double> dx{0.0}, dr{std::hypot(env.front().x.value(), env.front().y.value())};
    const double min_gap = 0.25 * (2 * pi / options.points);
    for (const auto& [delta, r] : beyond)
      if (delta - dx.back() > min_gap) dx.push_back(delta), dr.push_back(r);
    if (dx.size() >= 6) {
      // the first idle point must lie on the rest contact's side: its radius at the rest
      // contact (extrapolated from the family) against the traced stretch's
      const double gap = std::abs(dr[1] + (dr[1] - dr[2]) / (dx[2] - dx[1]) * dx[1] - dr[0]);
      if (gap > 5e-3)  // [mm] grinding accuracy
        return {StatusCode::undercut,
                "the synthesized stretch ends " + fmt(gap) + " mm off the idle curve (where the follower rests at "
                "the other control positions) at the rest contact: the target's idle travel does not follow the "
                "idle curve",
                "profile " + fmt(phi_start * 180 / pi) + " deg"};
      idle = Spline::interpolate(dx, dr);
      idle_reach = std::min(dx.back(), 0.25 * untouched);
      result.notes.push_back("idle curve (resting follower over the control range) continues the profile for " +
                             fmt(idle_reach * 180 / pi) + " deg beyond the rest contact");
    }
  }
  // beyond the idle curve's reach: a quintic over `settle` to a constant radius (slope and
  // curvature 0), so the bridge from the nose meets a plain arc about the profile origin
  double settle = 0.0, settled_radius = 0.0;
  std::optional<Quintic> to_arc;
  if (idle_reach > 0) {
    double d[3];
    idle.evaluate(idle_reach, 2, d);
    settle = std::min(20.0 * pi / 180, 0.5 * (0.5 * untouched - idle_reach));
    settled_radius = d[0] + 0.5 * d[1] * settle;
    to_arc.emplace(d[0], d[1] * settle, d[2] * settle * settle, settled_radius, 0.0, 0.0);
  }
  // radius beyond the rest contact with dr/da, d2r/da2 (delta runs against a: d/da = -dir d/ddelta)
  auto rest_side_polar = [&](double a, double out[3]) {
    if (idle_reach <= 0) return dwell_polar(a, out);
    double delta = (phi_start - a) * dir;
    delta -= 2 * pi * std::floor(delta / (2 * pi));
    if (delta <= idle_reach) {
      idle.evaluate(delta, 2, out);
      out[1] *= -dir;
    } else if (delta >= idle_reach + settle) {
      out[0] = settled_radius, out[1] = 0.0, out[2] = 0.0;
    } else {
      to_arc->eval((delta - idle_reach) / settle, out[0], out[1], out[2]);
      out[1] *= -dir / settle;
      out[2] /= settle * settle;
    }
  };
  // bridge between the nose end (phi_end) and the idle curve's far end (or the dwell arc at
  // the middle of the untouched range)
  const double rest_reach = 0.5 * untouched;
  const double join = phi_start - dir * rest_reach + dir * 2 * pi;  // where the rest side takes over
  // slopes on the traced stretch by differences of its radius over e = 1e-3 rad (central,
  // or one-sided second-order into the stretch at its ends). Near both ends the follower
  // turns back: the envelope's speed in cam angle falls to ~1e-3 of its peak, and the
  // polar derivatives of a point there divide the cam motion's interpolation error by that
  // speed squared (the Valvetronic lever at 60 deg of control: d2r/da2 672 mm/rad^2 at its
  // rest point against 4.7e-4 by differences, a 2 mm concave radius reported on its 36 mm
  // idle arc); shorter steps amplify it by 1 / e^2 (with 1e-4 rad the untouched far side
  // moved by up to 1.4e-3 mm between upstream spacings of 1/16 and 1.5 deg; with 1e-3 rad by
  // at most 9.4e-6 mm)
  const double e = 1e-3;
  const double traced = std::abs(phi_end - phi_start);
  auto traced_differences = [&](double a, double out[3]) {
    const double d = (a - phi_start) * dir;  // [rad] into the stretch
    const double f0 = traced_radius(a);
    out[0] = f0;
    if (d >= e && d <= traced - e) {
      const double fp = traced_radius(a + e), fm = traced_radius(a - e);
      out[1] = (fp - fm) / (2 * e);
      out[2] = (fp - 2 * f0 + fm) / (e * e);
      return;
    }
    const double s = d < e ? dir : -dir;  // towards the inside
    const double f1 = traced_radius(a + s * e), f2 = traced_radius(a + 2 * s * e);
    out[1] = s * (-3 * f0 + 4 * f1 - f2) / (2 * e);
    out[2] = (f0 - 2 * f1 + f2) / (e * e);
  };
  double end_d[3], rest_d[3], join_d[3];
  traced_differences(phi_end, end_d);
  traced_differences(phi_start, rest_d);
  rest_side_polar(join, join_d);
  const double span = join - phi_end;  // signed
  // the traced stretch at the resolution of resolution_angles, the bridge and the dwell arc
  // (smooth, no target detail) uniform in polar angle
  const double step = 2 * pi / options.points;
  std::vector<double> along;  // distance along the traced direction from the rest point [rad]
  for (double a : resolution_angles(env, phi, h, step, false)) along.push_back((a - phi_start) * dir);
  // (polar angle in [0, 2 pi), radius, dr/da, d2r/da2)
  std::vector<std::array<double, 4>> table;
  table.reserve(along.size() + 2 * static_cast<std::size_t>(options.points));
  auto put = [&](double a, const double r[3]) {
    double a0 = std::fmod(a, 2 * pi);
    if (a0 < 0) a0 += 2 * pi;
    if (a0 >= 2 * pi) a0 = 0.0;
    table.push_back({a0, r[0], r[1], r[2]});
  };
  std::vector<std::array<double, 3>> traced_rows;  // r, dr/da, d2r/da2 at each of `along`
  traced_rows.reserve(along.size());
  // where the envelope moves slower than 1/10 of its fastest (per sample, in polar angle)
  // its rows take their slopes from differences (see traced_differences): there the polar
  // derivatives' error, ~ 4e-10 / (speed per sample)^2 mm/rad^2 on the bundled designs, would
  // pass 4e-3 mm/rad^2 (3e-5 of the Valvetronic lever's d2r/da2 at its far end)
  double fastest_step = 0.0;  // [rad] of polar angle per sample
  for (std::size_t j = 1; j < phi.size(); ++j) fastest_step = std::max(fastest_step, std::abs(phi[j] - phi[j - 1]));
  for (double d : along) {
    double r[3];
    const double a = phi_start + dir * d;
    const int lo = bracket(a);
    if (std::abs(phi[lo + 1] - phi[lo]) < 0.1 * fastest_step) traced_differences(a, r);
    else traced_polar(a, r);
    put(a, r);
    traced_rows.push_back({r[0], r[1], r[2]});
  }
  const double sense = span > 0 ? 1.0 : -1.0, reach = std::abs(span);
  // the bridge, in the distance b = (a - phi_end) * sense from the nose end, is a cam lobe's
  // far flank: where the traced end still rises, a nose (nose_septic: c2 with the traced end,
  // c3 with its mirror image) turns it over to a maximum at b = L; the mirror image of the
  // nose and of the traced stretch comes back down to the rest radius at b = 2 L + traced;
  // a quintic settles from there onto the rest side. L: the shortest of kBridgeNoseDeg whose
  // nose and settling piece keep a convex radius >= the roller's and options.min_radius_mm.
  // Otherwise (the end does not rise, or no nose fits) one quintic spans the bridge: it can
  // bulge well past the traced end (57.9 mm on the bundled Valvetronic lever, whose nose
  // tops at 45.4 mm). Below: the traced end, the rest point and the join, per unit b.
  const double end_b[3] = {end_d[0], end_d[1] * sense, end_d[2]};
  const double rest_b[3] = {rest_d[0], rest_d[1] * sense, rest_d[2]};
  const double join_b[3] = {join_d[0], join_d[1] * sense, join_d[2]};
  auto hermite_over = [](const double* from, const double* to, double length) {
    return Quintic(from[0], from[1] * length, from[2] * length * length, to[0], to[1] * length,
                   to[2] * length * length);
  };
  // r, dr/db, d2r/db2 at the fraction t of a quintic or septic piece of `length`
  auto piece_at = [](const auto& q, double length, double t, double out[3]) {
    if constexpr (std::is_same_v<std::decay_t<decltype(q)>, Quintic>) {
      q.eval(t, out[0], out[1], out[2]);
    } else {
      double d[4];
      q.eval(t, d);
      out[0] = d[0], out[1] = d[1], out[2] = d[2];
    }
    out[1] /= length;
    out[2] /= length * length;
  };
  const double bound = 1.0 / std::max(radius, options.min_radius_mm);  // [1/mm]
  auto convex_ok = [&](const double r[3]) {
    return r[0] > 0 && detail::polar_curvature(r[0], r[1], r[2]) <= bound;
  };
  constexpr double kBridgeNoseDeg[] = {2, 3, 4, 6, 8, 10, 12, 16, 20, 24, 32, 40};
  double nose = 0.0, settle_from = 0.0;
  Quintic settle_piece = hermite_over(end_b, join_b, reach);  // the single quintic until a nose fits
  detail::Septic nose_piece = detail::nose_septic(end_b[0], end_b[1], end_b[2], 1.0);  // (unused while nose = 0)
  if (end_b[1] > 0) {
    for (double length_deg : kBridgeNoseDeg) {
      const double length = length_deg * pi / 180;
      const double from = 2 * length + traced, rest_length = reach - from;
      if (rest_length < traced) break;
      const detail::Septic rising = detail::nose_septic(end_b[0], end_b[1], end_b[2], length);
      bool fits = true;
      for (int k = 0; k <= 64 && fits; ++k) {
        double r[3];
        piece_at(rising, length, k / 64.0, r);
        fits = convex_ok(r);
      }
      // the settling piece c2 with the mirrored rest point, else c1, else c0 (the first that
      // keeps above the rest radius: a concave ramp foot's curvature, or a slope left over
      // from it, would swing the quintic under it; on the bundled VVLD the c0 kink is 2e-5 rad)
      for (const auto& [rest_slope, rest_curvature] :
           {std::pair{-rest_b[1], rest_b[2]}, std::pair{-rest_b[1], 0.0}, std::pair{0.0, 0.0}}) {
        const double mirrored_rest[3] = {rest_b[0], rest_slope, rest_curvature};
        const Quintic settling = hermite_over(mirrored_rest, join_b, rest_length);
        bool settles = fits;
        for (int k = 0; k <= 128 && settles; ++k) {
          double r[3];
          piece_at(settling, rest_length, k / 128.0, r);
          settles = convex_ok(r) && r[0] >= std::min(rest_b[0], join_b[0]) - 1e-6;  // [mm] no dip under the rest
        }
        if (settles) {
          nose = length, settle_from = from, nose_piece = rising, settle_piece = settling;
          break;
        }
      }
      if (nose > 0) break;
    }
  }
  auto bridge_polar = [&](double a, double out[3]) {
    const double b = (a - phi_end) * sense;
    if (nose == 0.0) {
      piece_at(settle_piece, reach, b / reach, out);
    } else if (b <= 2 * nose) {  // the nose and its mirror image
      piece_at(nose_piece, nose, (b <= nose ? b : 2 * nose - b) / nose, out);
      if (b > nose) out[1] = -out[1];
    } else {  // past the mirrored traced stretch (its rows are copied, see below)
      CAMOPT_ASSERT(b >= settle_from - 1e-9);
      piece_at(settle_piece, reach - settle_from, (b - settle_from) / (reach - settle_from), out);
    }
    out[1] *= sense;
  };
  if (nose > 0)
    result.notes.push_back("beyond the traced stretch (untouched) a " + fmt(nose * 180 / pi) +
                           " deg nose turns the profile over and its mirror image comes back to the rest radius");
  else if (end_b[1] > 0)
    result.notes.push_back("beyond the traced stretch (untouched) one quintic bridges to the rest side: no nose of " +
                           fmt(kBridgeNoseDeg[0]) + " to " + fmt(kBridgeNoseDeg[std::size(kBridgeNoseDeg) - 1]) +
                           " deg keeps a convex radius >= " + fmt(std::max(radius, options.min_radius_mm)) + " mm");
  // the bridge at the traced stretch's resolution rule (neighbours at most `step` apart in
  // polar angle and in turn of the tangent, dpsi/da = |kappa| sqrt(r^2 + r'^2)); its mirrored
  // stretch copies the traced rows; the rest side (smooth, no target detail) uniform in
  // polar angle. Distances d from the rest point along the traced direction [rad].
  const double bridge_end = 2 * pi - rest_reach;
  // the largest step from a point with r, dr/da, d2r/da2 under the rule
  auto local_step = [&](const double r[3]) {
    const double turn = std::abs(detail::polar_curvature(r[0], r[1], r[2])) * std::sqrt(r[0] * r[0] + r[1] * r[1]);
    return step / std::max(1.0, turn);
  };
  auto walk = [&](double from, double to) {  // points strictly between from and to
    double r[3];
    bridge_polar(phi_start + dir * from, r);
    for (double d = from;;) {
      const double local = local_step(r);
      if (d + 1.5 * local > to) break;
      d += local;
      bridge_polar(phi_start + dir * d, r);
      put(phi_start + dir * d, r);
    }
  };
  if (nose > 0) {
    walk(traced, traced + 2 * nose);
    // the traced stretch mirrored about the nose's maximum, d -> 2 (traced + nose) - d: its
    // rows (dense in cam angle, which the mirror does not need) thinned to the rule above
    double last = traced + 2 * nose;
    for (std::size_t k = along.size(); k-- > 0;) {
      const double r[3] = {traced_rows[k][0], -traced_rows[k][1], traced_rows[k][2]};
      const double d = 2 * (traced + nose) - along[k];
      if (k > 0 && k + 1 < along.size() && d - last < 0.999 * local_step(r)) continue;
      put(phi_start + dir * d, r);
      last = d;
    }
    walk(settle_from + traced, bridge_end);
  } else {
    walk(traced, bridge_end);
  }
  const int rest_count = std::max(2, static_cast<int>(std::ceil(rest_reach / step - 1e-9)));
  for (int j = 0; j < rest_count; ++j) {
    const double d = bridge_end + rest_reach * j / rest_count;
    double r[3];
    if (j == 0) bridge_polar(phi_start + dir * d, r);
    else rest_side_polar(phi_start + dir * d, r);
    put(phi_start + dir * d, r);
  }
  // the table runs once round in polar angle (either sense) from the rest point: reversed
  // and rotated it ascends (sorted only if rounding left it out of order)
  if (dir < 0) std::reverse(table.begin(), table.end());
  std::rotate(table.begin(), std::min_element(table.begin(), table.end()), table.end());
  if (!std::is_sorted(table.begin(), table.end())) std::sort(table.begin(), table.end());
  table.erase(std::unique(table.begin(), table.end(), [](const auto& a, const auto& b) { return a[0] == b[0]; }),
              table.end());
  const std::size_t rows = table.size();
  result.angle_deg.resize(rows);
  result.radius_mm.resize(rows);
  std::vector<double> dr(rows), ddr(rows);
  for (std::size_t k = 0; k < rows; ++k) {
    result.angle_deg[k] = table[k][0] * 180 / pi;
    result.radius_mm[k] = table[k][1];
    dr[k] = table[k][2];
    ddr[k] = table[k][3];
  }
  finish_from_polar(result, options.wheel_radius_mm, dr, ddr);
  result.below_min_radius = radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.min_radius_mm, false);
  result.profile.name = cut.profile;
  result.profile.form = ProfileForm::polar;
  result.profile.angle_deg = result.angle_deg;
  result.profile.radius_mm = result.radius_mm;
  return Status::success();
}

}  // namespace

DesignSpec with_profile(const DesignSpec& spec, const ProfileSpec& profile) {
  DesignSpec out = spec;
  bool replaced = false;
  for (auto& p : out.profiles)
    if (p.name == profile.name) {
      const SourceRef where = p.where;
      p = profile;
      p.where = where;
      replaced = true;
    }
  CAMOPT_ASSERT(replaced);
  for (auto& c : out.connections) c.lash_mm = 0.0;
  return out;
}

Status synthesize(const DesignSpec& spec, const PeriodicSpline& lift, const SynthesisOptions& options,
                  SynthesisResult& result) {
  CAMOPT_ASSERT(options.points >= 6 && options.samples >= options.points);
  const std::string target_node = options.target_node.empty() ? spec.output_node : options.target_node;
  const MechanismCut cut = cut_mechanism(spec, options.cam, target_node);
  const auto& conn = spec.connections[cut.connection];
  const SurfaceSpec& cam_surface = cut.profile_on_a ? conn.surface_a : conn.surface_b;
  const SurfaceSpec& follower_surface = cut.profile_on_a ? conn.surface_b : conn.surface_a;
  result = {};
  result.connection = conn.name;
  result.cam_node = cut.cam_node;
  result.follower_node = cut.follower_node;
  result.follower_shape = to_string(follower_surface.shape);
  for (const auto& c : spec.connections)
    if (c.lash_mm > 0)
      result.notes.push_back("lash of '" + c.name + "' (" + fmt(c.lash_mm) +
                             " mm) is ignored: the target lift's ramps are expected to take it up");

  // a floating follower (intermediate lever) is not fixed by the target motion during its
  // idle travel: inverted through its cam roller's travel instead (floating_inversion.hpp),
  // on a mechanism of its own, so the downstream half is compiled only where it is solved
  // (a conventional follower, or the idle family of a swing cam)
  const auto follower_spec = std::find_if(spec.nodes.begin(), spec.nodes.end(),
                                          [&](const NodeSpec& nd) { return nd.name == cut.follower_node; });
  CAMOPT_ASSERT(follower_spec != spec.nodes.end());
  const bool floating_follower = follower_spec->kind == NodeKind::floating;
  const bool needs_downstream = !floating_follower || options.cam == "swing";
  const kin::Mechanism up = kin::compile(cut.upstream);
  const kin::Mechanism down = needs_downstream ? kin::compile(cut.downstream) : kin::Mechanism{};
  kin::Workspace up_ws(up), down_ws(down);
  std::vector<double> controls = options.controls;
  if (controls.empty())
    for (const auto& c : spec.controls) controls.push_back(c.default_value);
  up_ws.set_controls(controls);
  if (needs_downstream) down_ws.set_controls(controls);
  const int cam = up.node_index(cut.cam_node);
  const int follower = needs_downstream ? down.node_index(cut.follower_node) : -1;
  // the cam's angle: its one variable, or the third (phi) of a floating lever
  const int cam_angle_variable = up.nodes[cam].first_variable + (up.nodes[cam].kind == NodeKind::floating ? 2 : 0);
  const bool angle_driver = up.driver_is_angle();
  if (!angle_driver) throw InputError("synthesize: the driver '" + spec.driver.node + "' must be rotational");

  // profile placement on the cam node (drawing) [mm], [rad]
  const double ox = cam_surface.origin_mm[0], oy = cam_surface.origin_mm[1];
  const double co = std::cos(cam_surface.orientation_deg * pi / 180), so = std::sin(cam_surface.orientation_deg * pi / 180);
  const bool roller = follower_surface.shape == SurfaceShape::circle;
  const double radius = follower_surface.radius_mm;

  // global -> cam drawing -> profile frame, for a cam pose and a point (jets)
  auto global_to_profile = [&](const auto& cpose, const kin::detail::V2<Jet3>& g) {
    const Jet3 dx = g.x - cpose.tx, dy = g.y - cpose.ty;
    const Jet3 lx = cpose.rx + cpose.c * dx + cpose.s * dy - ox;
    const Jet3 ly = cpose.ry - cpose.s * dx + cpose.c * dy - oy;
    return P2<Jet3>{co * lx + so * ly, -so * lx + co * ly};
  };
  const int n = envelope_samples(lift, options.samples);
  // follower centre / face point and (a flat face only) face normal in the profile frame
  std::vector<P2<Jet3>> path(n), normal(roller ? 0 : n);
  std::vector<double> theta(n), cam_rate(n), valve_rate(n);
  std::vector<Jet3> motion(n);  // target motion L(theta) as jets
  double motion_lo = 1e300, motion_hi = -1e300;
  for (int i = 0; i < n; ++i) {
    theta[i] = 2 * pi * i / n;
    double d[4];  // L and its derivatives at theta
    lift.evaluate(theta[i], 3, d);
    motion[i] = jet_from_derivatives<3>(d);
    motion_lo = std::min(motion_lo, motion[i].value());
    motion_hi = std::max(motion_hi, motion[i].value());
  }
  // inversion: the follower's variables are functions F(L) of the target motion alone, so
  // they are solved at levels across L's range (F and three derivatives, by implicit
  // differentiation in the solver) and interpolated by septic hermite pieces in L, then
  // composed with L(theta) (Faa di Bruno). levels run up from the rest (L = 0) for warm starts.
  // A roller's centre (global x, y) is as much a function of L: interpolated in place of the
  // variables, it spares the pose (sin and cos of the follower's angle) at every sample
  const kin::Node* fn = floating_follower ? nullptr : &down.nodes[follower];
  const int dof = floating_follower ? 0 : fn->dof;
  const bool invert_centre = !floating_follower && roller;
  const int fields = invert_centre ? 2 : dof;  // interpolated in L: centre x, y, or the variables
  if (motion_hi - motion_lo < 1e-9) motion_hi = motion_lo + 1e-3;  // no motion: any small bracket
  const int levels = kInversionLevels;
  const double level_step = (motion_hi - motion_lo) / levels;
  std::vector<double> inverse((levels + 1) * fields * 4);  // [level][field][derivative]
  FloatingInversion through_lever;
  if (floating_follower) {
    const Status st = invert_floating_follower(spec, cut, target_node, controls, theta, motion, through_lever);
    if (!st.ok()) return st;
    result.notes.push_back("follower '" + cut.follower_node + "' is a floating lever, inverted through its cam "
                           "roller's travel: " + through_lever.fill_span + "; the bridged lever misses the target by "
                           "up to " + fmt(through_lever.fill_error_mm) + " mm (at cam " +
                           fmt(through_lever.fill_error_at_rad * 180 / pi) + " deg)");
    if (through_lever.rest_travel_mm != 0.0)
      result.notes.push_back("the target's base circle is not the lever's rest lift (" +
                             fmt(through_lever.rest_lift) + " mm): on the base circle the lever rests " +
                             fmt(through_lever.rest_travel_mm) + " mm of cam-roller travel from its drawing rest, "
                             "beyond its idle travel");
  } else {
    // one continuous path: from the rest level (L nearest 0, the drawing) down to the
    // lowest level, then up through all of them (warm starts from the neighbour)
    const int rest = std::clamp(static_cast<int>(std::lround(-motion_lo / level_step)), 0, levels);
    std::vector<int> order;
    for (int q = rest; q >= 0; --q) order.push_back(q);
    for (int q = 1; q <= levels; ++q) order.push_back(q);
    for (int q : order) {
      const double level = motion_lo + q * level_step;
      Status st = kin::solve(down, down_ws, level, {3, false});
      if (!st.ok()) {
        int at = 0;  // the first cam angle whose target motion reaches this level
        for (int i = 0; i < n; ++i)
          if (std::abs(motion[i].value() - level) < std::abs(motion[at].value() - level)) at = i;
        st.message = "inverting the valve lift " + fmt(level) + " mm through '" + cut.follower_node +
                     "': " + st.message + "; if a dwell arc or idle curve lies between this cam and the valve, the "
                     "valve lift does not determine the follower there";
        st.where = "cam " + fmt(theta[at] * 180 / pi) + " deg";
        return st;
      }
      double* at_level = &inverse[static_cast<std::size_t>(q * fields * 4)];
      if (invert_centre) {
        const auto centre = kin::detail::node_pose(down, follower, down_ws.vars.data(), down_ws.pivots.data())
                                .apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]);
        for (int d = 0; d < 4; ++d) at_level[d] = centre.x.derivative(d), at_level[4 + d] = centre.y.derivative(d);
      } else {
        for (int k = 0; k < dof; ++k)
          for (int d = 0; d < 4; ++d) at_level[k * 4 + d] = down_ws.vars[fn->first_variable + k].derivative(d);
      }
    }
  }
  detail::SepticPieces inverse_pieces(std::max(fields, 1));  // the follower between levels
  for (int q = 0; q < levels && !floating_follower; ++q)
    inverse_pieces.add_interval(&inverse[static_cast<std::size_t>(q * fields * 4)],
                                &inverse[static_cast<std::size_t>((q + 1) * fields * 4)], level_step);
  // a rotational cam that is the only body upstream turns with the driver: no solve needed
  const bool cam_is_lone_driver = up.variables.size() == 1 && cam == up.driver_node && up.driver_variable() == 0;
  Jet3 driver_alone;
  std::vector<double> driver_sin, driver_cos;  // of every sample's cam angle (the lone driver's pose)
  if (cam_is_lone_driver) revolution_sin_cos(n, driver_sin, driver_cos);
  if (cam_is_lone_driver) {  // one solve fills the workspace's pivot positions for node_pose
    const Status st = kin::solve(up, up_ws, 0.0, {3, false});
    if (!st.ok()) return {st.code, st.message, "cam 0 deg"};
  }
  // the cam's motion depends on the driver alone (not on the target): solved upstream every
  // `stride` samples (and at 2 pi) with its jets, septic hermite in theta in between; across
  // a dwell (the cam at rest) every kRestStride strides
  const kin::Node& cn = up.nodes[cam];
  const int stride = cam_is_lone_driver ? 1 : std::max(1, static_cast<int>(std::lround(kUpstreamSpacing * n / (2 * pi))));
  std::vector<int> node_at;           // sample index of each upstream solve, ascending, the last n
  std::vector<double> cam_motion;     // [node][dof][derivative]
  // a floating cam that the driver moves through one roller: its motion from the lever
  // path (lever_path.hpp) instead of a solve of its whole contact cluster at every node;
  // the first node is solved whole (the path's start, and the workspace's state)
  LeverPath lever_path;
  LeverState path_state;  // where the lever path last found the lever
  if (!cam_is_lone_driver && cn.kind == NodeKind::floating)
    if (!build_lever_path(cut.upstream, up, cam, controls, lever_path).ok()) lever_path = {};  // solved whole
  auto solve_upstream = [&](int sample) -> Status {
    const double at = 2 * pi * sample / n;
    if (lever_path.contact >= 0 && !node_at.empty()) {
      Jet3 lever[3];
      if (lever_at(lever_path, up, up_ws, at, path_state, lever).ok()) {
        node_at.push_back(sample);
        for (const Jet3& v : lever)
          for (int d = 0; d < 4; ++d) cam_motion.push_back(v.derivative(d));
        return Status::success();
      }
      lever_path = {};  // from here on solved whole
    }
    const Status st = kin::solve(up, up_ws, at, {3, false});
    if (!st.ok()) return {st.code, st.message, "cam " + fmt(at * 180 / pi) + " deg"};
    node_at.push_back(sample);
    for (int k = 0; k < cn.dof; ++k)
      for (int d = 0; d < 4; ++d) cam_motion.push_back(up_ws.vars[cn.first_variable + k].derivative(d));
    if (lever_path.contact >= 0) lever_path_state(lever_path, up, up_ws, at, path_state);
    return Status::success();
  };
  const double rest_span = kRestStride * stride * 2 * pi / n;  // [rad] of driver
  auto at_rest = [&](std::size_t j) {
    for (int k = 0; k < cn.dof; ++k) {
      const double* d = &cam_motion[(j * cn.dof + k) * 4];
      const double h = rest_span;
      if (!(std::abs(d[1]) * h + std::abs(d[2]) * h * h / 2 + std::abs(d[3]) * h * h * h / 6 <= kRestMotion))
        return false;
    }
    return true;
  };
  if (!cam_is_lone_driver) {
    if (Status st = solve_upstream(0); !st.ok()) return st;
    // the state a refused dwell try returns to: the workspace where the upstream is solved
    // whole (assigned, not reallocated, after the first), the lever path's state where it
    // follows the path (which reads the workspace's pivots only)
    std::optional<kin::Workspace> before;
    while (node_at.back() < n) {
      const std::size_t j = node_at.size() - 1;
      const int next = std::min(n, node_at.back() + stride);
      if (at_rest(j) && next < n) {
        // try the dwell: one solve kRestStride strides on, kept when the cam rests there at
        // the same pose; else dropped and the stretch solved stride by stride from here
        const bool whole = lever_path.contact < 0;
        if (whole && before) *before = up_ws;
        if (whole && !before) before.emplace(up_ws);
        const LeverState state_before = path_state;
        const int far = std::min(n, node_at.back() + kRestStride * stride);
        if (Status st = solve_upstream(far); !st.ok()) return st;
        bool dwell = at_rest(j + 1);
        for (int k = 0; k < cn.dof && dwell; ++k)
          dwell = std::abs(cam_motion[((j + 1) * cn.dof + k) * 4] - cam_motion[(j * cn.dof + k) * 4]) <= kRestMotion;
        if (dwell) continue;
        node_at.pop_back();
        cam_motion.resize(cam_motion.size() - static_cast<std::size_t>(cn.dof) * 4);
        if (whole) up_ws = *before;  // (a path that fell back to whole solves goes on from far)
        path_state = state_before;
      }
      if (Status st = solve_upstream(next); !st.ok()) return st;
    }
  }
  result.upstream_solves = static_cast<int>(node_at.size());
  // which samples are needed: for a swing cam only those where it moves (swing_profile
  // traces the envelope where its rate exceeds 1e-3 of the peak; the rest are its dwell)
  std::vector<char> needed(static_cast<std::size_t>(n), 1);
  std::size_t interval = 0;  // upstream interval of the current sample
  // the cam's variable first_variable + k at sample i (septic hermite between solves)
  detail::SepticPieces upstream_pieces(cn.dof);
  for (std::size_t j = 0; j + 1 < node_at.size(); ++j)
    upstream_pieces.add_interval(&cam_motion[j * cn.dof * 4], &cam_motion[(j + 1) * cn.dof * 4],
                                 (node_at[j + 1] - node_at[j]) * 2 * pi / n);
  auto upstream_dof = [&](int i, int k) {
    while (node_at[interval + 1] <= i) ++interval;
    const int a = node_at[interval], b = node_at[interval + 1];
    double d[4];
    upstream_pieces.eval(interval, k, static_cast<double>(i - a) / (b - a), d);
    return jet_from_derivatives<3>(d);
  };
  // a swing cam's angle at every sample first (its rate says which samples are needed),
  // then its other coordinates (a floating lever's position) where needed
  const int angle_dof = cam_angle_variable - cn.first_variable;
  std::vector<Jet3> angle_at;
  auto upstream_at = [&](int i, Jet3* up_vars) {
    for (int k = 0; k < cn.dof; ++k)
      up_vars[cn.first_variable + k] = k == angle_dof && !angle_at.empty() ? angle_at[i] : upstream_dof(i, k);
  };
  std::vector<Jet3> up_vars_at(up.variables.size(), Jet3(0.0));
  if (options.cam == "swing" && !cam_is_lone_driver) {
    double max_rate = 0.0;
    angle_at.resize(n);
    for (int i = 0; i < n; ++i) {
      angle_at[i] = upstream_dof(i, angle_dof);
      cam_rate[i] = angle_at[i].derivative(1);
      max_rate = std::max(max_rate, std::abs(cam_rate[i]));
    }
    for (int i = 0; i < n; ++i) needed[i] = std::abs(cam_rate[i]) > 1e-4 * max_rate;
    interval = 0;
  }
  std::vector<Jet3> vars(down.variables.size(), Jet3(0.0));
  std::vector<Jet3> inverted(invert_centre ? 2 : 0, Jet3(0.0));  // a roller's centre at a sample
  for (int i = 0; i < n; ++i) {
    const Jet3& L = motion[i];
    valve_rate[i] = L.derivative(1);
    if (!needed[i]) continue;  // a swing cam's dwell (cam_rate is set)
    const double u = std::clamp((L.value() - motion_lo) / level_step, 0.0, static_cast<double>(levels));
    for (int k = 0; k < fields; ++k) {
      double d[4];
      inverse_pieces.eval_at(u, k, d);
      (invert_centre ? inverted[k] : vars[fn->first_variable + k]) = compose(d, L);  // follower(theta) = F(L(theta))
    }
    // the cam's motion: the driver itself (its angle is theta), or interpolated from upstream
    const Jet3* up_vars = &driver_alone;
    driver_alone = Jet3::variable(theta[i]);
    if (cam_is_lone_driver) memo_sin_cos_insert(theta[i], driver_sin[i], driver_cos[i]);
    if (!cam_is_lone_driver) {
      upstream_at(i, up_vars_at.data());
      up_vars = up_vars_at.data();
    }
    const auto cpose = kin::detail::node_pose(up, cam, up_vars, up_ws.pivots.data());
    cam_rate[i] = up_vars[cam_angle_variable].derivative(1);  // [rad per rad of driver]
    auto to_profile = [&](const kin::detail::V2<Jet3>& g) { return global_to_profile(cpose, g); };
    auto rotate_to_profile = [&](const kin::detail::V2<Jet3>& v) {
      const Jet3 lx = cpose.c * v.x + cpose.s * v.y, ly = -cpose.s * v.x + cpose.c * v.y;
      return P2<Jet3>{co * lx + so * ly, -so * lx + co * ly};
    };
    if (floating_follower) {
      path[i] = to_profile(kin::detail::V2<Jet3>{through_lever.centre_x[i], through_lever.centre_y[i]});
      continue;  // a roller (invert_floating_follower requires one)
    }
    if (invert_centre) {
      path[i] = to_profile(kin::detail::V2<Jet3>{inverted[0], inverted[1]});
      continue;  // a roller: no face normal
    }
    const auto fpose = kin::detail::node_pose(down, follower, vars.data(), down_ws.pivots.data());
    path[i] = to_profile(fpose.apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]));
    if (!roller) {
      const Vec2 nn = follower_surface.normal;
      const double len = std::hypot(nn[0], nn[1]);
      normal[i] = rotate_to_profile(fpose.rotate(nn[0] / len, nn[1] / len));
    }
  }
  if (options.cam == "swing") {
    // the resting follower's centre over the first control's range (and 10 % beyond each
    // end), at the driver angle in the middle of the longest stretch where the cam rests
    std::vector<IdleCentre> idle_centres;
    if (!up.controls.empty() && roller) {
      double max_rate = 0.0;
      for (double r : cam_rate) max_rate = std::max(max_rate, std::abs(r));
      int best_start = -1, best_len = 0;
      for (int i = 0; i < n; ++i) {
        auto still = [&](int k) { return std::abs(cam_rate[(k + n) % n]) <= 1e-3 * max_rate; };
        if (!still(i) || still(i - 1)) continue;
        int len = 0;
        while (len < n && still(i + len)) ++len;
        if (len > best_len) best_len = len, best_start = i;
      }
      if (best_start >= 0) {
        const double rest_theta = theta[(best_start + best_len / 2) % n];
        const double rest_level = lift(rest_theta);
        const auto& c0 = up.controls[0];
        // control positions solved across the family; the centres are interpolated between
        // them (quintic splines in the control) and the envelope taken 4 times as densely
        constexpr int kIdleControls = 32;
        const double lo = c0.min - 0.1 * (c0.max - c0.min), hi = c0.max + 0.1 * (c0.max - c0.min);
        // from the synthesized position outwards on both sides, so each solve starts next to the last
        std::vector<double> family;
        for (int j = 0; j <= kIdleControls; ++j) family.push_back(lo + (hi - lo) * j / kIdleControls);
        const auto split = std::lower_bound(family.begin(), family.end(), controls[0]) - family.begin();
        std::vector<std::array<double, 3>> lower, upper;  // (control, x, y)
        // each side continues from the last solved point (the control moves by one family
        // step under the solver's trust check); a point the continuation cannot reach is
        // assembled afresh from the drawing, as a lone point would be
        auto solve_at = [](const kin::Mechanism& mech, kin::Workspace& w, const std::vector<double>& ctl, double at) {
          w.set_controls(ctl, true);
          if (kin::solve(mech, w, at, {0, false}).ok()) return true;
          w.set_controls(ctl);
          return kin::solve(mech, w, at, {0, false}).ok();
        };
        // a downstream that no control moves rests the same at every position: solved once
        const bool down_follows_control = std::any_of(down.nodes.begin(), down.nodes.end(), [](const kin::Node& nd) {
          return nd.control >= 0 || nd.pivot_control >= 0;
        });
        for (int side = 0; side < 2; ++side) {
          std::vector<double> ctl = controls;
          // both sides start from the synthesized position's workspaces (their last use: the
          // second side takes them over)
          kin::Workspace up_w = side == 0 ? up_ws : std::move(up_ws);
          kin::Workspace down_w = side == 0 ? down_ws : std::move(down_ws);
          bool down_at_rest = false;
          for (std::ptrdiff_t j = side == 0 ? split : split - 1; side == 0 ? j <= kIdleControls : j >= 0;
               j += side == 0 ? 1 : -1) {
            ctl[0] = family[static_cast<std::size_t>(j)];
            if (!solve_at(up, up_w, ctl, rest_theta)) break;  // the family ends where the mechanism no longer assembles
            if (down_follows_control || !down_at_rest) {
              if (!solve_at(down, down_w, ctl, rest_level)) break;
              down_at_rest = true;
            }
            const auto cpose = kin::detail::node_pose(up, cam, up_w.vars.data(), up_w.pivots.data());
            const auto fpose = kin::detail::node_pose(down, follower, down_w.vars.data(), down_w.pivots.data());
            const P2<Jet3> c =
                global_to_profile(cpose, fpose.apply(follower_surface.origin_mm[0], follower_surface.origin_mm[1]));
            (side == 0 ? upper : lower).push_back({ctl[0], c.x.value(), c.y.value()});
          }
        }
        std::vector<std::array<double, 3>> solved(lower.rbegin(), lower.rend());
        solved.insert(solved.end(), upper.begin(), upper.end());
        if (solved.size() >= 6) {
          std::vector<double> cs, xs, ys;
          for (const auto& q : solved) cs.push_back(q[0]), xs.push_back(q[1]), ys.push_back(q[2]);
          const Spline sx = Spline::interpolate(cs, xs), sy = Spline::interpolate(cs, ys);
          const int dense = 4 * (static_cast<int>(cs.size()) - 1);
          for (int j = 0; j <= dense; ++j) {
            const double cv = cs.front() + (cs.back() - cs.front()) * j / dense;
            double dx[2], dy[2];
            sx.evaluate(cv, 1, dx);
            sy.evaluate(cv, 1, dy);
            idle_centres.push_back({dx[0], dy[0], dx[1], dy[1]});
          }
        }
      }
    }
    bool folds = false;
    Status st = swing_profile(spec, up, cut, cam_surface, radius, roller, path, normal, theta, cam_rate, valve_rate,
                              idle_centres, options, result, folds);
    // a valve lift that folds the swing cam: how far down its scale would have to go
    if (folds && options.remedies && options.target_node.empty())
      st.message += ". " + swing_remedy_text(largest_synthesizable_scale(spec, lift, options));
    return st;
  }

  // orientation of the traced path: +1 counter-clockwise (shoelace area)
  double area = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto& a = path[i];
    const auto& b = path[(i + 1) % n];
    area += a.x.value() * b.y.value() - b.x.value() * a.y.value();
  }
  const double orient = area >= 0 ? 1.0 : -1.0;

  // envelope points with their first two derivatives in theta
  std::vector<P2<Jet2>> env(n);
  double face_min = 1e300, face_max = -1e300;
  for (int i = 0; i < n; ++i) {
    if (roller) {
      const P2<Jet2> d{derivative_of(path[i].x), derivative_of(path[i].y)};
      const Jet2 len = sqrt(d.x * d.x + d.y * d.y);
      if (!(len.value() > 1e-12))
        return {StatusCode::undercut, "the follower centre stands still relative to the cam (no envelope)",
                "cam " + fmt(theta[i] * 180 / pi) + " deg"};
      // outward normal of the centre path (right of a counter-clockwise tangent)
      const P2<Jet2> nu{orient * d.y / len, -orient * d.x / len};
      env[i] = {truncate<2>(path[i].x) - radius * nu.x, truncate<2>(path[i].y) - radius * nu.y};
    } else {
      const P2<Jet2> q{truncate<2>(path[i].x), truncate<2>(path[i].y)};
      const P2<Jet2> dq{derivative_of(path[i].x), derivative_of(path[i].y)};
      const P2<Jet2> nv{truncate<2>(normal[i].x), truncate<2>(normal[i].y)};
      const P2<Jet2> dn{derivative_of(normal[i].x), derivative_of(normal[i].y)};
      const P2<Jet2> t{-nv.y, nv.x};
      const Jet2 turn = t.x * dn.x + t.y * dn.y;  // rotation rate of the face in the cam frame
      if (!(std::abs(turn.value()) > 1e-12))
        return {StatusCode::undercut, "the flat face does not turn relative to the cam (no envelope)",
                "cam " + fmt(theta[i] * 180 / pi) + " deg"};
      const Jet2 lambda = (dq.x * nv.x + dq.y * nv.y) / turn;  // contact offset along the face [mm]
      // offset from the face's reference point (the drawing point_mm)
      face_min = std::min(face_min, lambda.value());
      face_max = std::max(face_max, lambda.value());
      env[i] = {q.x + lambda * t.x, q.y + lambda * t.y};
    }
  }
  if (!roller) {
    result.face_offset_min_mm = face_min;
    result.face_offset_max_mm = face_max;
  }

  // the profile must be traced monotonically in polar angle (star-shaped, no undercut), in
  // the sense in which it winds
  std::vector<double> phi(n + 1), dphi(n);
  double winding = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = env[i].x.value(), y = env[i].y.value();
    const double x1 = env[i].x.derivative(1), y1 = env[i].y.derivative(1);
    dphi[i] = (x * y1 - y * x1) / (x * x + y * y);
    winding += dphi[i];
  }
  const double sign = winding >= 0 ? 1.0 : -1.0;
  bool folds = false;
  for (int i = 0; i < n && !folds; ++i) {
    // roller: the profile runs backwards against its centre path where the centre path's
    // radius of curvature is below the roller radius (undercut, a cusp)
    const double d_env = env[i].x.derivative(1) * path[i].x.derivative(1) + env[i].y.derivative(1) * path[i].y.derivative(1);
    folds = !(dphi[i] * sign > 0) || (roller && d_env <= 0.0);
  }
  phi[0] = std::atan2(env[0].y.value(), env[0].x.value());
  for (int i = 1; i <= n; ++i) {
    const auto& e = env[i % n];
    double a = std::atan2(e.y.value(), e.x.value());
    a += 2 * pi * std::round((phi[i - 1] - a) / (2 * pi));
    phi[i] = a;
  }
  // every window where it folds, with the worst value in each
  if (folds) return detail::revolution_fold_status(env, path, phi, sign, orient, roller ? radius : -1.0);
  if (std::abs(std::abs(phi[n] - phi[0]) - 2 * pi) > 1e-6)
    return {StatusCode::undercut, "the synthesized profile does not wind once around the cam pivot", "whole revolution"};

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
    // bring the target into the traced range
    double target = target0 + 2 * pi * std::floor((std::min(phi[0], phi[n]) - target0) / (2 * pi) + 1.0);
    if (target > std::max(phi[0], phi[n])) target -= 2 * pi;
    // phi is monotone: phi[lo] .. phi[lo + 1] brackets the target; the targets ascend about
    // as densely as the samples, so the previous bracket and its neighbours are tried first
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
    const int hi = lo + 1;
    hint = lo;
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
  if (!result.has_concave) result.min_concave_radius_mm = 0.0;
  if (result.min_radius_of_curvature_mm == 1e300) result.min_radius_of_curvature_mm = 0.0;
  result.concave_narrower_than_wheel =
      result.has_concave && options.wheel_radius_mm > 0 && result.min_concave_radius_mm < options.wheel_radius_mm;
  result.concave_below_wheel =
      radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.wheel_radius_mm, true);
  result.below_min_radius = radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.min_radius_mm, false);
  result.base_radius_mm = extreme_radius(env, h, -1);
  result.max_radius_mm = extreme_radius(env, h, +1);
  result.profile.name = cut.profile;
  result.profile.form = ProfileForm::polar;
  result.profile.angle_deg = result.angle_deg;
  result.profile.radius_mm = result.radius_mm;
  return Status::success();
}

Status round_trip(const DesignSpec& spec, const PeriodicSpline& lift, const std::vector<double>& controls,
                  const std::string& connection, RoundTrip& out, const std::string& target_node) {
  const kin::Mechanism mech = kin::compile(spec);
  kin::SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0;
  s.step = 0.25;
  s.request = {1, true};
  const std::vector<double> pos = controls.empty() ? mech.default_controls() : controls;
  s.control_positions = {pos};
  const kin::SweepResult r = kin::sweep(mech, s);
  const auto& p = r.positions[0];
  if (!p.status.ok()) return p.status;
  const int target_index = target_node.empty() ? mech.output_node : mech.node_index(target_node);
  CAMOPT_ASSERT(target_index >= 0);
  const int out_var = mech.nodes[target_index].first_variable;
  // internal units (rad or mm) against the target; valve lift from its rest position
  const double rest = target_node.empty() ? mech.nodes[target_index].rest : 0.0;
  const double to_internal = mech.variables[out_var].is_angle ? pi / 180 : 1.0;
  int ci = -1;
  for (int i = 0; i < static_cast<int>(mech.connections.size()); ++i)
    if (mech.connections[i].name == connection) ci = i;
  out = {};
  double sum = 0.0;
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    const double target = lift(r.driver[i] * pi / 180);
    const double got = p.at(i, mech.variables.size(), out_var, 0) * to_internal - rest;
    const double e = std::abs(got - target);
    sum += e * e;
    if (e > out.max_error_mm) out.max_error_mm = e, out.max_error_at_deg = r.driver[i];
    if (ci >= 0) {
      const double pa = p.contacts[i * mech.connections.size() + ci].pressure_angle * 180 / pi;
      if (pa > out.max_pressure_angle_deg) out.max_pressure_angle_deg = pa, out.max_pressure_angle_at_deg = r.driver[i];
    }
  }
  out.rms_error_mm = std::sqrt(sum / static_cast<double>(r.driver.size()));
  return Status::success();
}

Status grinding_table(const ProfileSpec& profile, double master_radius, double step_deg, std::vector<double>& cam_deg,
                      std::vector<double>& lift_mm) {
  DesignSpec d;
  d.name = "grinding";
  d.output_node = "master";
  d.driver.node = "cam";
  const kin::CamProfile cam = kin::CamProfile::build(profile);
  const double base = cam.base_radius_mm();
  NodeSpec c;
  c.name = "cam";
  c.kind = NodeKind::rotational;
  NodeSpec m;
  m.name = "master";
  m.kind = NodeKind::translational;
  m.origin_mm = {base + master_radius, 0.0};
  m.direction = {1.0, 0.0};
  d.nodes = {c, m};
  d.profiles = {profile};
  ConnectionSpec k;
  k.name = "grind";
  k.kind = ConnectionKind::contact;
  k.surface_a.node = "cam";
  k.surface_a.shape = SurfaceShape::profile;
  k.surface_a.profile = profile.name;
  k.surface_b.node = "master";
  if (master_radius > 0) {
    k.surface_b.shape = SurfaceShape::circle;
    k.surface_b.origin_mm = {base + master_radius, 0.0};
    k.surface_b.radius_mm = master_radius;
  } else {
    k.surface_b.shape = SurfaceShape::line;
    k.surface_b.origin_mm = {base, 0.0};
    k.surface_b.normal = {-1.0, 0.0};
  }
  d.connections = {k};
  const kin::Mechanism mech = kin::compile(d);
  kin::SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0 - step_deg;
  s.step = step_deg;
  s.request = {0, false};
  const kin::SweepResult r = kin::sweep(mech, s);
  if (!r.positions[0].status.ok()) return r.positions[0].status;
  cam_deg = r.driver;
  lift_mm.resize(r.driver.size());
  const int v = mech.nodes[mech.output_node].first_variable;
  double low = 1e300;
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    lift_mm[i] = r.positions[0].at(i, mech.variables.size(), v, 0);
    low = std::min(low, lift_mm[i]);
  }
  for (auto& l : lift_mm) l -= low;  // measured from the base circle
  return Status::success();
}

}  // namespace camopt::synthesis
