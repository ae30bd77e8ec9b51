// a swing cam's profile for envelope synthesis (envelope.hpp). A swing cam is traced only
// while it moves, forth while the valve opens and back while it closes, over the same
// stretch of profile. The opening stroke gives the profile; the closing stroke must retrace
// it (else the target lift is not a function of the swing angle). Beyond the rest contact
// the profile continues as the idle curve (where the follower rests at the other control
// positions) or the dwell arc about the swing pivot; the untouched rest of the turn is
// bridged from the nose end to that rest side.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"
#include "camopt/synthesis/detail/fold_status.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/undercut_windows.hpp"

namespace camopt::synthesis::detail {

namespace {

// [mm] grinding accuracy: how far the closing stroke, or the idle curve at the rest
// contact, may lie off the traced stretch
constexpr double kGrindingAccuracy = 5e-3;
// [rad] step of the differences that give the traced stretch's slopes near its ends
// (see TracedStretch::differences)
constexpr double kDifferenceStep = 1e-3;
// [deg] the lengths of the bridge's nose that are tried, shortest first
constexpr double kBridgeNoseDeg[] = {2, 3, 4, 6, 8, 10, 12, 16, 20, 24, 32, 40};

// the opening stroke: the samples where the cam swings in the sense it swings while the
// valve opens fastest
struct Stroke {
  double max_rate = 0.0;   // [rad per rad] the peak |swing rate|
  double open_sign = 1.0;  // the sense of swing while the valve opens
  std::vector<int> run;    // the stroke's sample indices, in order
};

Status find_opening_stroke(const FollowerPath& follower, const std::vector<double>& theta, Stroke& out) {
  const std::vector<double>& cam_rate = follower.cam_rate;
  const std::vector<double>& valve_rate = follower.valve_rate;
  const int n = static_cast<int>(theta.size());
  double max_rate = 0.0;
  for (double r : cam_rate) max_rate = std::max(max_rate, std::abs(r));
  if (!(max_rate > 0))
    return {StatusCode::undercut, "the swing cam does not move over the revolution", "whole revolution"};
  // the sense of swing motion while the valve opens fastest
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
  out.max_rate = max_rate;
  out.open_sign = open_sign;
  for (int j = 0; j < runs[0].second; ++j) out.run.push_back((runs[0].first + j) % n);
  return Status::success();
}

// envelope of the roller of radius `radius` about centre path point c: p = c - r nu, nu the
// centre path's normal pointing away from the profile origin (the roller is outside the cam)
P2<Jet2> roller_envelope(const P2<Jet3>& c, double radius) {
  const P2<Jet2> d{derivative_of(c.x), derivative_of(c.y)};
  const Jet2 len = sqrt(d.x * d.x + d.y * d.y);
  P2<Jet2> nu{d.y / len, -d.x / len};
  if (nu.x.value() * c.x.value() + nu.y.value() * c.y.value() < 0) nu = {-1.0 * nu.x, -1.0 * nu.y};
  return P2<Jet2>{truncate<2>(c.x) - radius * nu.x, truncate<2>(c.y) - radius * nu.y};
}

// the traced stretch: the envelope along the opening stroke, sampled every h of theta, and
// its unwrapped polar angle phi, which runs on in the sense dir. Its radius at a polar angle
// is quintic hermite in theta between the samples
class TracedStretch {
 public:
  std::vector<P2<Jet2>> env;
  std::vector<double> phi;
  double dir = 1.0;  // +1: phi ascends along the stretch
  double h = 0.0;    // [rad] theta between samples

  double start() const { return phi.front(); }  // the rest contact
  double end() const { return phi.back(); }     // the nose end
  double length() const { return std::abs(phi.back() - phi.front()); }

  // the sample interval [lo, lo + 1] holding polar angle a (the first or last interval
  // beyond the ends): the last answer and its neighbours first (the lookups mostly walk
  // along the stretch), else bisection
  int bracket(double a) {
    const int last_interval = static_cast<int>(phi.size()) - 2;
    auto holds = [&](int lo) {
      return (lo == 0 || (phi[lo] - a) * dir <= 0) && (lo == last_interval || (phi[lo + 1] - a) * dir > 0);
    };
    for (int lo : {hint_, hint_ + 1, hint_ - 1})
      if (lo >= 0 && lo <= last_interval && holds(lo)) return hint_ = lo;
    int lo = 0, hi = last_interval + 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      ((phi[mid] - a) * dir <= 0 ? lo : hi) = mid;
    }
    return hint_ = lo;
  }
  PolarHit hit(double a) {
    const int lo = bracket(a);
    return envelope_at_polar_angle(env[lo], env[lo + 1], phi[lo], phi[lo + 1], h, a);
  }
  // r, dr/da, d2r/da2 at polar angle a from the envelope's derivatives
  void polar(double a, double out[3]) { polar_derivatives(hit(a), out); }
  double radius(double a) {
    const PolarHit p = hit(a);
    return std::sqrt(p.x * p.x + p.y * p.y);
  }
  // r, dr/da, d2r/da2 at polar angle a by differences of the radius over e =
  // kDifferenceStep (central, or one-sided second-order into the stretch at its ends). Near
  // both ends the follower turns back: the envelope's speed in cam angle falls to ~1e-3 of
  // its peak, and the polar derivatives of a point there divide the cam motion's
  // interpolation error by that speed squared (the Valvetronic lever at 60 deg of control:
  // d2r/da2 672 mm/rad^2 at its rest point against 4.7e-4 by differences, a 2 mm concave
  // radius reported on its 36 mm idle arc); shorter steps amplify it by 1 / e^2 (with 1e-4
  // rad the untouched far side moved by up to 1.4e-3 mm between upstream spacings of 1/16
  // and 1.5 deg; with 1e-3 rad by at most 9.4e-6 mm)
  void differences(double a, double out[3]) {
    const double e = kDifferenceStep;
    const double d = (a - start()) * dir;  // [rad] into the stretch
    const double f0 = radius(a);
    out[0] = f0;
    if (d >= e && d <= length() - e) {
      const double fp = radius(a + e), fm = radius(a - e);
      out[1] = (fp - fm) / (2 * e);
      out[2] = (fp - 2 * f0 + fm) / (e * e);
      return;
    }
    const double s = d < e ? dir : -dir;  // towards the inside
    const double f1 = radius(a + s * e), f2 = radius(a + 2 * s * e);
    out[1] = s * (-3 * f0 + 4 * f1 - f2) / (2 * e);
    out[2] = (f0 - 2 * f1 + f2) / (e * e);
  }

 private:
  int hint_ = 0;
};

// the envelope of the roller along the opening stroke; where it does not run on in polar
// angle, the undercut Status listing every window where it folds back (folds: not the
// target's ripple)
Status trace_stretch(const Halves& halves, const FollowerPath& follower, const std::vector<double>& theta,
                     const Stroke& stroke, TracedStretch& out, bool& folds) {
  for (int i : stroke.run) {
    out.env.push_back(roller_envelope(follower.path[i], halves.radius));
    double a = std::atan2(out.env.back().y.value(), out.env.back().x.value());
    if (!out.phi.empty()) a += 2 * pi * std::round((out.phi.back() - a) / (2 * pi));
    out.phi.push_back(a);
  }
  out.dir = out.phi.back() > out.phi.front() ? 1.0 : -1.0;
  out.h = 2 * pi / static_cast<int>(theta.size());
  for (std::size_t j = 1; j < out.phi.size(); ++j)
    if ((out.phi[j] - out.phi[j - 1]) * out.dir <= 0) {
      bool ripple = false;
      const Status st = detail::swing_fold_status(out.env, out.phi, out.dir, stroke.run, follower.path, theta,
                                                  follower.cam_rate, stroke.max_rate, follower.valve_rate,
                                                  halves.radius, ripple);
      folds = !ripple;
      return st;
    }
  return Status::success();
}

// the closing stroke must retrace the opening one: radial distance of each closing envelope
// point from the traced profile at its polar angle (or from the nearer end of the stretch
// when it lies beyond it), within the grinding accuracy
Status check_closing_stroke(const Halves& halves, const FollowerPath& follower, const std::vector<double>& theta,
                            const Stroke& stroke, TracedStretch& traced, SynthesisResult& result) {
  const int n = static_cast<int>(theta.size());
  const std::vector<double>& phi = traced.phi;
  double worst = 0.0, worst_at = 0.0;
  const double lo_phi = std::min(phi.front(), phi.back()), hi_phi = std::max(phi.front(), phi.back());
  for (int i = 0; i < n; ++i) {
    if (!(follower.cam_rate[i] * stroke.open_sign < -1e-3 * stroke.max_rate)) continue;
    const P2<Jet2> q = roller_envelope(follower.path[i], halves.radius);
    const double qx = q.x.value(), qy = q.y.value();
    double a = std::atan2(qy, qx);
    a += 2 * pi * std::round((0.5 * (lo_phi + hi_phi) - a) / (2 * pi));
    double off = 0.0;
    if (a >= lo_phi && a <= hi_phi) {
      off = std::abs(std::hypot(qx, qy) - traced.radius(a));
    } else {
      const P2<Jet2>& end = std::abs(a - phi.front()) < std::abs(a - phi.back()) ? traced.env.front() : traced.env.back();
      off = std::hypot(qx - end.x.value(), qy - end.y.value());
    }
    if (off > worst) worst = off, worst_at = theta[i];
  }
  if (worst > kGrindingAccuracy)
    return {StatusCode::undercut,
            "the closing stroke of the swing cam does not retrace the opening stroke (off by " + fmt(worst) +
                " mm): the target lift is not a function of the swing angle",
            "cam " + fmt(worst_at * 180 / pi) + " deg"};
  result.notes.push_back("swing cam traced over " + fmt(traced.length() * 180 / pi) +
                         " deg of its profile; closing stroke retraces it within " + fmt(worst) + " mm (at cam " +
                         fmt(worst_at * 180 / pi) + " deg; the round trip on the closing stroke is limited by this)");
  return Status::success();
}

// the profile beyond the rest contact, as a function of the polar distance delta =
// (phi_start - a) * dir beyond it: the idle curve over idle_reach, then a quintic over
// `settle` to a constant radius (slope and curvature 0), so the bridge from the nose meets
// a plain arc about the profile origin. Without an idle curve: the dwell arc about the
// swing pivot (a floating lever has no pivot: an arc about the profile origin)
struct RestSide {
  double px = 0.0, py = 0.0, dwell = 0.0;  // [mm] the dwell arc's centre (profile frame) and radius
  double phi_start = 0.0, dir = 1.0;       // the rest contact and the traced sense
  Spline idle;                             // the idle curve: radius against delta
  double idle_reach = 0.0;                 // [rad] of polar distance covered by the idle curve
  double settle = 0.0, settled_radius = 0.0;
  std::optional<Quintic> to_arc;

  // ray from the origin at angle a meets the circle |x - P| = dwell: r = b + sqrt(D),
  // b = P.u(a), D = b^2 - |P|^2 + dwell^2 (b'' = -b); r, dr/da, d2r/da2
  void dwell_polar(double a, double out[3]) const {
    const double ux = std::cos(a), uy = std::sin(a);
    const double b = px * ux + py * uy, b1 = -px * uy + py * ux;
    const double disc = b * b - (px * px + py * py - dwell * dwell);
    const double root = std::sqrt(std::max(0.0, disc));
    out[0] = b + root;
    // D' = 2 b b', D'' = 2 (b'^2 - b^2)
    const double disc1 = 2 * b * b1, disc2 = 2 * (b1 * b1 - b * b);
    out[1] = root > 0 ? b1 + disc1 / (2 * root) : b1;
    out[2] = root > 0 ? -b + disc2 / (2 * root) - disc1 * disc1 / (4 * root * root * root) : -b;
  }
  // radius beyond the rest contact with dr/da, d2r/da2 (delta runs against a: d/da = -dir d/ddelta)
  void polar(double a, double out[3]) const {
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
  }
};

// the idle curve: with controls, the envelope of the resting roller over the control family
// (its centres in the profile frame, idle_centres, in control order): a dwell arc about the
// pivot when the pivot stays put (CVVL), the control arm's idle curve when it moves with the
// control (VVLD). Used on the far side of the rest contact; none from fewer than 8 centres
// or 6 points beyond the rest contact
Status fit_idle_curve(const TracedStretch& traced, const std::vector<IdleCentre>& idle_centres, double radius,
                      const SynthesisOptions& options, RestSide& rest, SynthesisResult& result) {
  if (idle_centres.size() < 8) return Status::success();
  const double phi_start = traced.start(), dir = traced.dir;
  const double untouched = 2 * pi - traced.length();
  std::vector<std::pair<double, double>> beyond;  // (delta, radius)
  for (const IdleCentre& c : idle_centres) {
    const double len = std::hypot(c.tx, c.ty);
    if (!(len > 1e-12)) continue;  // the centre stands still: no envelope point
    double nx = c.ty / len, ny = -c.tx / len;
    if (nx * c.x + ny * c.y < 0) nx = -nx, ny = -ny;  // away from the origin
    const double x = c.x - radius * nx, y = c.y - radius * ny;
    double delta = (phi_start - std::atan2(y, x)) * dir;
    delta -= 2 * pi * std::floor(delta / (2 * pi));
    if (delta > pi) continue;  // on the traced side of the rest contact
    beyond.push_back({delta, std::hypot(x, y)});
  }
  std::sort(beyond.begin(), beyond.end());
  // the idle curve starts at the rest contact itself (value continuity with the stretch)
  std::vector<double> dx{0.0}, dr{std::hypot(traced.env.front().x.value(), traced.env.front().y.value())};
  const double min_gap = 0.25 * (2 * pi / options.points);
  for (const auto& [delta, r] : beyond)
    if (delta - dx.back() > min_gap) dx.push_back(delta), dr.push_back(r);
  if (dx.size() < 6) return Status::success();
  // the first idle point must lie on the rest contact's side: its radius at the rest
  // contact (extrapolated from the family) against the traced stretch's
  const double gap = std::abs(dr[1] + (dr[1] - dr[2]) / (dx[2] - dx[1]) * dx[1] - dr[0]);
  if (gap > kGrindingAccuracy)
    return {StatusCode::undercut,
            "the synthesized stretch ends " + fmt(gap) + " mm off the idle curve (where the follower rests at "
            "the other control positions) at the rest contact: the target's idle travel does not follow the "
            "idle curve",
            "profile " + fmt(phi_start * 180 / pi) + " deg"};
  rest.idle = Spline::interpolate(dx, dr);
  rest.idle_reach = std::min(dx.back(), 0.25 * untouched);
  result.notes.push_back("idle curve (resting follower over the control range) continues the profile for " +
                         fmt(rest.idle_reach * 180 / pi) + " deg beyond the rest contact");
  return Status::success();
}

Status build_rest_side(const Halves& halves, const TracedStretch& traced, const std::vector<IdleCentre>& idle_centres,
                       const SynthesisOptions& options, RestSide& rest, SynthesisResult& result) {
  // the dwell arc about the swing pivot, in the profile frame
  const kin::Node& swing = halves.up.nodes[halves.up.node_index(halves.cut.cam_node)];
  const double ox = halves.frame.ox, oy = halves.frame.oy, co = halves.frame.co, so = halves.frame.so;
  const bool floating = swing.kind == NodeKind::floating;
  rest.px = floating ? 0.0 : co * (swing.pivot.x() - ox) + so * (swing.pivot.y() - oy);
  rest.py = floating ? 0.0 : -so * (swing.pivot.x() - ox) + co * (swing.pivot.y() - oy);
  const double rest_x = traced.env.front().x.value(), rest_y = traced.env.front().y.value();
  rest.dwell = std::hypot(rest_x - rest.px, rest_y - rest.py);
  rest.phi_start = traced.start();
  rest.dir = traced.dir;
  // the idle curve, where the follower rests at the other control positions
  if (Status st = fit_idle_curve(traced, idle_centres, halves.radius, options, rest, result); !st.ok()) return st;
  // beyond the idle curve's reach: the quintic to a plain arc
  if (rest.idle_reach > 0) {
    const double untouched = 2 * pi - traced.length();
    double d[3];
    rest.idle.evaluate(rest.idle_reach, 2, d);
    rest.settle = std::min(20.0 * pi / 180, 0.5 * (0.5 * untouched - rest.idle_reach));
    rest.settled_radius = d[0] + 0.5 * d[1] * rest.settle;
    rest.to_arc.emplace(d[0], d[1] * rest.settle, d[2] * rest.settle * rest.settle, rest.settled_radius, 0.0, 0.0);
  }
  return Status::success();
}

// the profile table: (polar angle in [0, 2 pi), radius, dr/da, d2r/da2) per row
struct PolarTable {
  std::vector<std::array<double, 4>> rows;

  void put(double a, const double r[3]) {
    double a0 = std::fmod(a, 2 * pi);
    if (a0 < 0) a0 += 2 * pi;
    if (a0 >= 2 * pi) a0 = 0.0;
    rows.push_back({a0, r[0], r[1], r[2]});
  }
};

// the traced stretch at the resolution of resolution_angles: its distances from the rest
// point along the traced direction [rad] and r, dr/da, d2r/da2 at each. Where the envelope
// moves slower than 1/10 of its fastest (per sample, in polar angle) the rows take their
// slopes from differences (TracedStretch::differences): there the polar derivatives'
// error, ~ 4e-10 / (speed per sample)^2 mm/rad^2 on the bundled designs, would pass 4e-3
// mm/rad^2 (3e-5 of the Valvetronic lever's d2r/da2 at its far end)
void traced_rows(TracedStretch& traced, double step, std::vector<double>& along,
                 std::vector<std::array<double, 3>>& rows, PolarTable& table) {
  const std::vector<double>& phi = traced.phi;
  const double phi_start = traced.start(), dir = traced.dir;
  for (double a : resolution_angles(traced.env, phi, traced.h, step, false)) along.push_back((a - phi_start) * dir);
  rows.reserve(along.size());
  double fastest_step = 0.0;  // [rad] of polar angle per sample
  for (std::size_t j = 1; j < phi.size(); ++j) fastest_step = std::max(fastest_step, std::abs(phi[j] - phi[j - 1]));
  for (double d : along) {
    double r[3];
    const double a = phi_start + dir * d;
    const int lo = traced.bracket(a);
    if (std::abs(phi[lo + 1] - phi[lo]) < 0.1 * fastest_step) traced.differences(a, r);
    else traced.polar(a, r);
    table.put(a, r);
    rows.push_back({r[0], r[1], r[2]});
  }
}

// quintic hermite over `length` from r, dr/db, d2r/db2 at `from` to those at `to`
Quintic hermite_over(const double* from, const double* to, double length) {
  return Quintic(from[0], from[1] * length, from[2] * length * length, to[0], to[1] * length,
                 to[2] * length * length);
}

// r, dr/db, d2r/db2 at the fraction t of a quintic or septic piece of `length`
void piece_at(const Quintic& q, double length, double t, double out[3]) {
  q.eval(t, out[0], out[1], out[2]);
  out[1] /= length;
  out[2] /= length * length;
}
void piece_at(const Septic& q, double length, double t, double out[3]) {
  double d[4];
  q.eval(t, d);
  out[0] = d[0], out[1] = d[1], out[2] = d[2];
  out[1] /= length;
  out[2] /= length * length;
}

// the bridge over the untouched far side, in the distance b = (a - phi_end) * sense from the
// nose end, is a cam lobe's far flank: where the traced end still rises, a nose
// (nose_septic: c2 with the traced end, c3 with its mirror image) turns it over to a maximum
// at b = L; the mirror image of the nose and of the traced stretch comes back down to the
// rest radius at b = 2 L + traced; a quintic settles from there onto the rest side. L: the
// shortest of kBridgeNoseDeg whose nose and settling piece keep a convex radius >= the
// roller's and options.min_radius_mm. Otherwise (the end does not rise, or no nose fits)
// one quintic spans the bridge: it can bulge well past the traced end (57.9 mm on the
// bundled Valvetronic lever, whose nose tops at 45.4 mm)
struct Bridge {
  double phi_end = 0.0, sense = 1.0, reach = 0.0;  // the nose end, the sense of b, the bridge's length [rad]
  double nose = 0.0;          // [rad] the nose's length L (0: one quintic)
  double settle_from = 0.0;   // [rad] where the settling piece starts, 2 L + traced
  Quintic settle_piece;
  Septic nose_piece;

  void polar(double a, double out[3]) const {
    const double b = (a - phi_end) * sense;
    if (nose == 0.0) {
      piece_at(settle_piece, reach, b / reach, out);
    } else if (b <= 2 * nose) {  // the nose and its mirror image
      piece_at(nose_piece, nose, (b <= nose ? b : 2 * nose - b) / nose, out);
      if (b > nose) out[1] = -out[1];
    } else {  // past the mirrored traced stretch (its rows are copied, see walk_far_side)
      CAMOPT_ASSERT(b >= settle_from - 1e-9);
      piece_at(settle_piece, reach - settle_from, (b - settle_from) / (reach - settle_from), out);
    }
    out[1] *= sense;
  }
};

// the bridge from the nose end to the rest side, which takes over at `join`; end_d and
// rest_d: r, dr/da, d2r/da2 at the nose end and at the rest point
Bridge fit_bridge(const TracedStretch& traced, const RestSide& rest, double join, const double end_d[3],
                  const double rest_d[3], double radius, const SynthesisOptions& options, SynthesisResult& result) {
  double join_d[3];
  rest.polar(join, join_d);
  const double span = join - traced.end();  // signed
  const double sense = span > 0 ? 1.0 : -1.0, reach = std::abs(span);
  const double traced_length = traced.length();
  // the traced end, the rest point and the join, per unit b
  const double end_b[3] = {end_d[0], end_d[1] * sense, end_d[2]};
  const double rest_b[3] = {rest_d[0], rest_d[1] * sense, rest_d[2]};
  const double join_b[3] = {join_d[0], join_d[1] * sense, join_d[2]};
  const double bound = 1.0 / std::max(radius, options.min_radius_mm);  // [1/mm]
  auto convex_ok = [&](const double r[3]) { return r[0] > 0 && polar_curvature(r[0], r[1], r[2]) <= bound; };
  // the single quintic until a nose fits (nose_piece unused while nose = 0)
  Bridge bridge{traced.end(), sense, reach, 0.0, 0.0, hermite_over(end_b, join_b, reach),
                nose_septic(end_b[0], end_b[1], end_b[2], 1.0)};
  if (end_b[1] > 0) {
    for (double length_deg : kBridgeNoseDeg) {
      const double length = length_deg * pi / 180;
      const double from = 2 * length + traced_length, rest_length = reach - from;
      if (rest_length < traced_length) break;
      const Septic rising = nose_septic(end_b[0], end_b[1], end_b[2], length);
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
          bridge.nose = length, bridge.settle_from = from, bridge.nose_piece = rising, bridge.settle_piece = settling;
          break;
        }
      }
      if (bridge.nose > 0) break;
    }
  }
  if (bridge.nose > 0)
    result.notes.push_back("beyond the traced stretch (untouched) a " + fmt(bridge.nose * 180 / pi) +
                           " deg nose turns the profile over and its mirror image comes back to the rest radius");
  else if (end_b[1] > 0)
    result.notes.push_back("beyond the traced stretch (untouched) one quintic bridges to the rest side: no nose of " +
                           fmt(kBridgeNoseDeg[0]) + " to " + fmt(kBridgeNoseDeg[std::size(kBridgeNoseDeg) - 1]) +
                           " deg keeps a convex radius >= " + fmt(std::max(radius, options.min_radius_mm)) + " mm");
  return bridge;
}

// the far side into the table: the bridge at the traced stretch's resolution rule
// (neighbours at most `step` apart in polar angle and in turn of the tangent, dpsi/da =
// |kappa| sqrt(r^2 + r'^2)); its mirrored stretch copies the traced rows; the rest side
// (smooth, no target detail) uniform in polar angle. Distances d from the rest point along
// the traced direction [rad]
void walk_far_side(const TracedStretch& traced, const Bridge& bridge, const RestSide& rest, double rest_reach,
                   double step, const std::vector<double>& along, const std::vector<std::array<double, 3>>& rows,
                   PolarTable& table) {
  const double phi_start = traced.start(), dir = traced.dir, traced_length = traced.length();
  const double bridge_end = 2 * pi - rest_reach;
  // the largest step from a point with r, dr/da, d2r/da2 under the rule
  auto local_step = [&](const double r[3]) {
    const double turn = std::abs(polar_curvature(r[0], r[1], r[2])) * std::sqrt(r[0] * r[0] + r[1] * r[1]);
    return step / std::max(1.0, turn);
  };
  auto walk = [&](double from, double to) {  // points strictly between from and to
    double r[3];
    bridge.polar(phi_start + dir * from, r);
    for (double d = from;;) {
      const double local = local_step(r);
      if (d + 1.5 * local > to) break;
      d += local;
      bridge.polar(phi_start + dir * d, r);
      table.put(phi_start + dir * d, r);
    }
  };
  if (bridge.nose > 0) {
    walk(traced_length, traced_length + 2 * bridge.nose);
    // the traced stretch mirrored about the nose's maximum, d -> 2 (traced + nose) - d: its
    // rows (dense in cam angle, which the mirror does not need) thinned to the rule above
    double last = traced_length + 2 * bridge.nose;
    for (std::size_t k = along.size(); k-- > 0;) {
      const double r[3] = {rows[k][0], -rows[k][1], rows[k][2]};
      const double d = 2 * (traced_length + bridge.nose) - along[k];
      if (k > 0 && k + 1 < along.size() && d - last < 0.999 * local_step(r)) continue;
      table.put(phi_start + dir * d, r);
      last = d;
    }
    walk(bridge.settle_from + traced_length, bridge_end);
  } else {
    walk(traced_length, bridge_end);
  }
  const int rest_count = std::max(2, static_cast<int>(std::ceil(rest_reach / step - 1e-9)));
  for (int j = 0; j < rest_count; ++j) {
    const double d = bridge_end + rest_reach * j / rest_count;
    double r[3];
    if (j == 0) bridge.polar(phi_start + dir * d, r);
    else rest.polar(phi_start + dir * d, r);
    table.put(phi_start + dir * d, r);
  }
}

// the table runs once round in polar angle (either sense) from the rest point: reversed and
// rotated it ascends (sorted only if rounding left it out of order); into the result
void finish_table(PolarTable& table, double dir, const Halves& halves, const SynthesisOptions& options,
                  SynthesisResult& result) {
  auto& rows = table.rows;
  if (dir < 0) std::reverse(rows.begin(), rows.end());
  std::rotate(rows.begin(), std::min_element(rows.begin(), rows.end()), rows.end());
  if (!std::is_sorted(rows.begin(), rows.end())) std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[0] == b[0]; }),
             rows.end());
  const std::size_t count = rows.size();
  result.angle_deg.resize(count);
  result.radius_mm.resize(count);
  std::vector<double> dr(count), ddr(count);
  for (std::size_t k = 0; k < count; ++k) {
    result.angle_deg[k] = rows[k][0] * 180 / pi;
    result.radius_mm[k] = rows[k][1];
    dr[k] = rows[k][2];
    ddr[k] = rows[k][3];
  }
  finish_from_polar(result, options.wheel_radius_mm, dr, ddr);
  result.below_min_radius = radius_windows(result.angle_deg, result.radius_of_curvature_mm, options.min_radius_mm, false);
  result.profile.name = halves.cut.profile;
  result.profile.form = ProfileForm::polar;
  result.profile.angle_deg = result.angle_deg;
  result.profile.radius_mm = result.radius_mm;
}

}  // namespace

Status swing_profile(const Halves& halves, const FollowerPath& follower, const std::vector<double>& theta,
                     const std::vector<IdleCentre>& idle_centres, const SynthesisOptions& options,
                     SynthesisResult& result, bool& folds) {
  if (!halves.roller)
    throw InputError("synthesize --cam swing: the swing cam's follower must be a roller or pad (circle), not a flat face");
  // the opening stroke: the longest run of samples where the cam swings as the valve opens
  Stroke stroke;
  if (Status st = find_opening_stroke(follower, theta, stroke); !st.ok()) return st;
  // the traced stretch: the roller's envelope along it, which must run on in polar angle
  TracedStretch traced;
  if (Status st = trace_stretch(halves, follower, theta, stroke, traced, folds); !st.ok()) return st;
  // the closing stroke must retrace it
  if (Status st = check_closing_stroke(halves, follower, theta, stroke, traced, result); !st.ok()) return st;
  // beyond the rest contact: the idle curve or the dwell arc
  RestSide rest;
  if (Status st = build_rest_side(halves, traced, idle_centres, options, rest, result); !st.ok()) return st;
  // the rest side takes over in the middle of the untouched range
  const double rest_reach = 0.5 * (2 * pi - traced.length());
  const double join = traced.start() - traced.dir * rest_reach + traced.dir * 2 * pi;
  // the slopes at the nose end and at the rest point, by differences
  double end_d[3], rest_d[3];
  traced.differences(traced.end(), end_d);
  traced.differences(traced.start(), rest_d);
  // the traced stretch into the table at its resolution
  const double step = 2 * pi / options.points;
  std::vector<double> along;
  std::vector<std::array<double, 3>> rows;
  PolarTable table;
  table.rows.reserve(2 * static_cast<std::size_t>(options.points));
  traced_rows(traced, step, along, rows, table);
  // the bridge over the untouched far side, from the nose end to the rest side
  const Bridge bridge = fit_bridge(traced, rest, join, end_d, rest_d, halves.radius, options, result);
  // the bridge, the mirrored stretch and the rest side into the table
  walk_far_side(traced, bridge, rest, rest_reach, step, along, rows, table);
  // the table sorted into the result's polar table
  finish_table(table, traced.dir, halves, options, result);
  return Status::success();
}

}  // namespace camopt::synthesis::detail
