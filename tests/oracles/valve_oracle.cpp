#include "oracles/valve_oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace camopt::oracles {

namespace {

constexpr double pi = std::numbers::pi;
// the scan step is at most this fraction of the fastest period in the problem
constexpr double kPeriodFraction = 1.0 / 32.0;
// bisection stops at this width relative to the length of the run
constexpr double kRootRelTolerance = 1e-15;
constexpr int kMaxBisections = 200;
// above this gamma tau the over-damped basis is formed from the two exponentials (no
// overflow of cosh, sinh); below it from cosh, sinh (no cancellation)
constexpr double kExponentialForm = 1.0;

// e^{-alpha tau} (cos, sin / sqrt(lambda)) and their analogues: the basis c, s of the
// homogeneous solution [thomson]
std::array<double, 2> homogeneous_basis(const ValveSegment& s, double tau) {
  const double decay = std::exp(-s.alpha * tau);
  switch (s.regime) {
    case ValveSegment::Regime::underdamped: {
      const double wd = std::sqrt(s.lambda);
      return {decay * std::cos(wd * tau), decay * std::sin(wd * tau) / wd};
    }
    case ValveSegment::Regime::critical:
      return {decay, decay * tau};
    case ValveSegment::Regime::overdamped:
      break;
  }
  const double gamma = std::sqrt(-s.lambda);
  if (gamma * tau < kExponentialForm)
    return {decay * std::cosh(gamma * tau), decay * std::sinh(gamma * tau) / gamma};
  // gamma < alpha since K > 0, so both exponents are negative
  const double slow = std::exp((gamma - s.alpha) * tau), fast = std::exp(-(gamma + s.alpha) * tau);
  return {0.5 * (slow + fast), 0.5 * (slow - fast) / gamma};
}

// engaged flags from a state: g > 0
ValveMode mode_of(const ValveParams& p, double t, double x, double v) {
  const std::array<double, 3> xc = p.cam(t);
  ValveMode mode;
  mode.cam = contact_indicator(xc[0] - p.lash - x, xc[1] - v, p.cam_stiffness, p.cam_damping) > 0.0;
  mode.seat = contact_indicator(-x, -v, p.seat_stiffness, p.seat_damping) > 0.0;
  return mode;
}

// the flags the state at t along segment s implies
ValveMode implied_mode(const ValveParams& p, const ValveSegment& s, double t) {
  const std::array<double, 3> y = s.motion(t);
  return mode_of(p, t, y[0], y[1]);
}

// the first time in (lo, hi] where the implied mode differs from the segment's, given
// that it does at hi and not at lo
double bisect_switch(const ValveParams& p, const ValveSegment& s, double lo, double hi, double width) {
  for (int i = 0; i < kMaxBisections && hi - lo > width; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (implied_mode(p, s, mid) == s.mode ? lo : hi) = mid;
  }
  return hi;
}

void record_switches(ValveTrajectory& out, ValveMode from, ValveMode to, double t, double x, double v) {
  if (from.cam != to.cam) out.events.push_back({t, ValveContact::cam, to.cam, x, v});
  if (from.seat != to.seat) out.events.push_back({t, ValveContact::seat, to.seat, x, v});
  if (static_cast<int>(out.events.size()) > kMaxValveEvents)
    throw std::runtime_error("valve oracle: too many contact events");
}

}  // namespace

std::array<double, 3> ValveParams::cam(double t) const {
  const double th = cam_speed * t + cam_phase, c = std::cos(th), s = std::sin(th);
  return {eccentricity * (1.0 - c), eccentricity * cam_speed * s, eccentricity * cam_speed * cam_speed * c};
}

double contact_indicator(double d, double d_rate, double stiffness, double damping) {
  return std::min(d, stiffness * d + damping * d_rate);
}

ValveSegment make_valve_segment(const ValveParams& p, ValveMode mode, double t0, double x0, double v0) {
  ValveSegment s;
  s.mode = mode;
  s.t0 = t0;
  s.m = p.mass;
  s.w = p.cam_speed;
  s.phi = p.cam_phase;
  // valve spring; cam: k_c (x_c - lash) + c_c x_c' = k_c (e - lash) - k_c e cos + c_c e w sin
  s.C = p.spring_damping;
  s.K = p.spring_rate;
  s.f0 = -p.preload;
  if (mode.cam) {
    s.C += p.cam_damping;
    s.K += p.cam_stiffness;
    s.f0 += p.cam_stiffness * (p.eccentricity - p.lash);
    s.a = -p.cam_stiffness * p.eccentricity;
    s.b = p.cam_damping * p.eccentricity * p.cam_speed;
  }
  if (mode.seat) {
    s.C += p.seat_damping;
    s.K += p.seat_stiffness;
  }
  // particular: (K - m w^2) P + C w Q = a, (K - m w^2) Q - C w P = b
  s.x_static = s.f0 / s.K;
  if (s.a != 0.0 || s.b != 0.0) {
    const double r = s.K - s.m * s.w * s.w, cw = s.C * s.w, det = r * r + cw * cw;
    if (det == 0.0) throw std::domain_error("valve oracle: exact resonance of an undamped mode");
    s.P = (r * s.a - cw * s.b) / det;
    s.Q = (r * s.b + cw * s.a) / det;
  }
  // homogeneous: m r^2 + C r + K = 0, lambda = (4 m K - C^2) / (4 m^2)
  s.alpha = s.C / (2.0 * s.m);
  const double disc = 4.0 * s.m * s.K - s.C * s.C;
  s.lambda = disc / (4.0 * s.m * s.m);
  s.regime = disc > 0.0   ? ValveSegment::Regime::underdamped
             : disc < 0.0 ? ValveSegment::Regime::overdamped
                          : ValveSegment::Regime::critical;
  const double th = s.w * t0 + s.phi;
  const double xp = s.x_static + s.P * std::cos(th) + s.Q * std::sin(th);
  const double vp = s.w * (s.Q * std::cos(th) - s.P * std::sin(th));
  s.A = x0 - xp;
  s.B = (v0 - vp) + s.alpha * s.A;
  return s;
}

std::array<double, 3> ValveSegment::motion(double t) const {
  const double th = w * t + phi, ct = std::cos(th), st = std::sin(th);
  const double harmonic = P * ct + Q * st;
  const std::array<double, 2> h = homogeneous_basis(*this, t - t0);
  const double c = h[0], s = h[1];
  // c' = -lambda s - alpha c, s' = c - alpha s
  const double c1 = -lambda * s - alpha * c, s1 = c - alpha * s;
  const double c2 = (alpha * alpha - lambda) * c + 2.0 * alpha * lambda * s;
  const double s2 = (alpha * alpha - lambda) * s - 2.0 * alpha * c;
  return {x_static + harmonic + A * c + B * s, w * (Q * ct - P * st) + A * c1 + B * s1,
          -w * w * harmonic + A * c2 + B * s2};
}

double ValveSegment::forcing(double t) const {
  const double th = w * t + phi;
  return f0 + a * std::cos(th) + b * std::sin(th);
}

double valve_scan_step(const ValveParams& p, double max_step) {
  double fastest = std::abs(p.cam_speed);
  for (int cam = 0; cam < 2; ++cam)
    for (int seat = 0; seat < 2; ++seat) {
      const double K = p.spring_rate + cam * p.cam_stiffness + seat * p.seat_stiffness;
      const double C = p.spring_damping + cam * p.cam_damping + seat * p.seat_damping;
      fastest = std::max({fastest, std::sqrt(K / p.mass), C / p.mass});
    }
  return std::min(max_step, kPeriodFraction * 2.0 * pi / fastest);
}

ValveTrajectory integrate_valve(const ValveParams& p, ValveStart start, double t_end, double max_scan_step) {
  ValveTrajectory out;
  out.params = p;
  out.t_begin = start.t;
  out.t_end = t_end;
  out.scan_step = valve_scan_step(p, max_scan_step);
  const double width = kRootRelTolerance * std::max(t_end - start.t, std::abs(t_end));
  out.segments.push_back(make_valve_segment(p, mode_of(p, start.t, start.x, start.v), start.t, start.x, start.v));
  for (;;) {
    const ValveSegment& s = out.segments.back();
    double lo = s.t0, hi = s.t0;
    bool switched = false;
    for (long k = 1; hi < t_end && !switched; ++k) {
      lo = hi;
      hi = std::min(s.t0 + static_cast<double>(k) * out.scan_step, t_end);
      switched = !(implied_mode(p, s, hi) == s.mode);
    }
    if (!switched) break;
    const double ts = bisect_switch(p, s, lo, hi, width);
    const std::array<double, 3> y = s.motion(ts);
    const ValveMode next = mode_of(p, ts, y[0], y[1]);
    record_switches(out, s.mode, next, ts, y[0], y[1]);
    out.segments.push_back(make_valve_segment(p, next, ts, y[0], y[1]));
  }
  return out;
}

const ValveSegment& ValveTrajectory::segment_at(double t) const {
  auto it = std::upper_bound(segments.begin(), segments.end(), t,
                             [](double tt, const ValveSegment& s) { return tt < s.t0; });
  return it == segments.begin() ? segments.front() : *std::prev(it);
}

ValveSample ValveTrajectory::at(double t) const {
  const ValveSegment& s = segment_at(t);
  const std::array<double, 3> y = s.motion(t);
  ValveSample out{y[0], y[1], y[2], 0.0, 0.0};
  if (s.mode.cam) {
    const std::array<double, 3> xc = params.cam(t);
    out.cam_force = params.cam_stiffness * (xc[0] - params.lash - y[0]) + params.cam_damping * (xc[1] - y[1]);
  }
  if (s.mode.seat) out.seat_force = -params.seat_stiffness * y[0] - params.seat_damping * y[1];
  return out;
}

double ValveTrajectory::max_lift(double ta, double tb) const {
  double best = std::max(at(ta).x, at(tb).x);
  const int n = std::max(1, static_cast<int>(std::ceil((tb - ta) / scan_step)));
  for (int k = 1; k <= n; ++k) {
    double lo = ta + (tb - ta) * (k - 1) / n, hi = k == n ? tb : ta + (tb - ta) * k / n;
    if (!(at(lo).v > 0.0 && at(hi).v <= 0.0)) continue;
    for (int i = 0; i < kMaxBisections && hi - lo > kRootRelTolerance * std::abs(hi); ++i) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (at(mid).v > 0.0 ? lo : hi) = mid;
    }
    best = std::max({best, at(lo).x, at(hi).x});
  }
  return best;
}

namespace {
// index of the landing: the first seat engagement in [ta, tb], events.size() if none
std::size_t landing(const std::vector<ValveEvent>& events, double ta, double tb) {
  for (std::size_t i = 0; i < events.size(); ++i)
    if (events[i].contact == ValveContact::seat && events[i].engages && events[i].t >= ta && events[i].t <= tb)
      return i;
  return events.size();
}
}  // namespace

double ValveTrajectory::seating_velocity(double ta, double tb) const {
  const std::size_t i = landing(events, ta, tb);
  return i < events.size() ? std::abs(events[i].v) : std::numeric_limits<double>::quiet_NaN();
}

int ValveTrajectory::bounce_count(double ta, double tb) const {
  int n = 0;
  for (std::size_t i = landing(events, ta, tb) + 1; i < events.size() && events[i].t <= tb; ++i)
    if (events[i].contact == ValveContact::seat && events[i].engages) ++n;
  return n;
}

std::vector<double> ValveTrajectory::bounce_heights(double ta, double tb) const {
  std::vector<double> heights;
  double lifted = std::numeric_limits<double>::quiet_NaN();  // last seat disengagement
  for (std::size_t i = landing(events, ta, tb) + 1; i < events.size() && events[i].t <= tb; ++i) {
    if (events[i].contact != ValveContact::seat) continue;
    if (!events[i].engages) lifted = events[i].t;
    else if (!std::isnan(lifted)) heights.push_back(max_lift(lifted, events[i].t));
  }
  return heights;
}

}  // namespace camopt::oracles
