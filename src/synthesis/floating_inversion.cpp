// inversion of a target motion through a floating follower (floating_inversion.hpp): the
// probe mechanism and the scan of L(q) (steps 1 and 2, floating_scan.cpp), then the walks
// that invert the target on the monotone pieces of L(q) (step 3), the landings on the base
// circle, and the bridges where the lift barely moves with the lever (step 4).
#include "camopt/synthesis/floating_inversion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/synthesis/detail/floating_scan.hpp"
#include "camopt/synthesis/hermite.hpp"

namespace camopt::synthesis {

namespace {

using Jet3 = Jet<3>;
using detail::kScanStep;

std::string fmt(double v) { return format_value(v, 6); }
std::string deg_of(double rad) { return fmt(rad * 180 / pi); }

// the slope, relative to the mean slope of the lift over the scan, below which L(q) counts
// as flat (idle travel): at a quadratic ramp foot the lift there is ~ 1e-8 of the full lift
constexpr double kFlatSlope = 1e-5;
// [mm per mm of peak lift] how close the target's turning lift must come to the lever's
// (the target is sampled: its extreme sample misses the true turn by ~ L'' h^2 / 8)
constexpr double kTurnTolerance = 1e-4;
// [relative to the mean slope] dL/dq at the last sample inverted before the base circle
// below which the lift does not fix the lever's travel there: the walk's end is then a
// designed landing (landing_samples). The bundled Valvetronic at 0 deg of control ends at
// 7.5e-5 (the lever's lift has a 2.2e-8 mm hump within 1.6e-3 mm of its rest); from 5 deg
// on its lift rises from the rest at 2.6e-2 .. 0.83 and the target fixes the travel
// down to the rest
constexpr double kLandingSlope = 1e-3;
constexpr int kMaxLandingSamples = 64;

// the landing of the lever's travel on the base circle from the jets q(tau) of the last
// inverted sample, tau the distance walked towards the rest [rad]: the septic hermite from
// them to rest (q and three derivatives 0) over m samples of h, for the smallest m whose
// acceleration q'' runs most evenly to 0 (total variation within 1 % of the least over
// m <= max_m, q falling monotonically to 0, as a ramp designer's constant-deceleration
// landing would). 0 when no such landing exists
int landing_samples(const Jet3& q_tau, double h, int max_m) {
  constexpr int kChecks = 64;  // points along the landing where q'' and the monotony are checked
  std::array<double, kChecks + 1> q2;
  double least = 1e300;
  int least_m = 0;
  for (int m = 2; m <= max_m; ++m) {
    const double span = m * h;
    const double start[4] = {q_tau.derivative(0), q_tau.derivative(1) * span,
                             q_tau.derivative(2) * span * span, q_tau.derivative(3) * span * span * span};
    const double rest[4] = {0.0, 0.0, 0.0, 0.0};
    const Septic piece(start, rest);
    bool monotone = true;
    for (int t = 0; t <= kChecks && monotone; ++t) {
      double d[4];
      piece.eval(static_cast<double>(t) / kChecks, d);
      monotone = d[0] >= -1e-9 * start[0] && d[1] <= 1e-9 * std::abs(start[1]);
      q2[static_cast<std::size_t>(t)] = d[2];
    }
    if (!monotone) {
      if (least_m > 0) break;  // past the monotone landings
      continue;
    }
    double variation = 0.0;
    for (int t = 1; t <= kChecks; ++t) variation += std::abs(q2[static_cast<std::size_t>(t)] - q2[static_cast<std::size_t>(t - 1)]);
    variation /= span * span;
    if (variation < least) least = variation, least_m = m;
    // q'' runs from its start to 0: no landing varies less than that
    if (variation <= 1.01 * std::abs(q_tau.derivative(2))) return m;
  }
  return least_m;
}

// q(theta) from L(q0 + d) = L0 + a1 d + a2 d^2 + a3 d^3 and the target's taylor
// coefficients b in theta (b0 = L0): series reversion to third order
Jet3 revert(const Jet3& lift_of_q, double q0, const Jet3& target) {
  const double a1 = lift_of_q.c[1], a2 = lift_of_q.c[2], a3 = lift_of_q.c[3];
  Jet3 q(q0);
  q.c[1] = target.c[1] / a1;
  q.c[2] = (target.c[2] - a2 * q.c[1] * q.c[1]) / a1;
  q.c[3] = (target.c[3] - 2 * a2 * q.c[1] * q.c[2] - a3 * q.c[1] * q.c[1] * q.c[1]) / a1;
  return q;
}

// f(q(theta)) from the jet of f in q (taylor coefficients at q(theta).value())
Jet3 compose_in(const Jet3& f_of_q, const Jet3& q) {
  double d[4];
  for (int k = 0; k < 4; ++k) d[k] = f_of_q.derivative(k);
  return compose(d, q);
}

// what each sample's lever travel comes from: not yet reached by a walk, the rest (base
// circle), inverted on a piece of L(q), or bridged between inverted neighbours
enum class Kind : char { open, rest, inverted, bridged };

// the inversion of the target on the monotone pieces of the scanned L(q), sample by sample
struct Walker {
  detail::LeverScan& scan;
  const detail::LiftPieces& pieces;
  const std::vector<double>& theta;
  const std::vector<Jet3>& motion;
  FloatingInversion& out;
  int n = 0;
  double h = 0.0;           // [rad] between samples
  double motion_hi = 0.0;   // [mm] the target's peak
  double mean_slope = 0.0;  // [mm per mm] of L(q) over the scan
  double flat = 0.0;        // |dL/dq| below which q is not inverted
  double rest_lift = 0.0;   // [mm] the lever's lift at rest (q = 0)
  double reverse = 0.0;     // [mm] target turning, beyond round-off
  std::vector<Kind> kind;
  std::vector<Jet3> q_of;         // the lever's travel at each sample, jets in theta
  std::vector<double> slope_of;   // dL/dq at each inverted sample

  Walker(detail::LeverScan& s, const detail::LiftPieces& p, const std::vector<double>& th,
         const std::vector<Jet3>& mo, double peak_lift, FloatingInversion& o)
      : scan(s), pieces(p), theta(th), motion(mo), out(o), n(static_cast<int>(th.size())) {
    const std::vector<double>& grid_lift = scan.lift;
    h = 2 * pi / n;
    motion_hi = peak_lift;
    mean_slope = std::abs(grid_lift[scan.top] - grid_lift[0]) / (scan.top * kScanStep);
    flat = kFlatSlope * mean_slope;
    rest_lift = grid_lift[0];
    reverse = 1e-9 * std::max(1.0, mean_slope);
    kind.assign(n, Kind::open);
    q_of.assign(n, Jet3(0.0));
    slope_of.assign(n, 0.0);
  }

  int wrap(int i) const { return (i % n + n) % n; }

  // invert sample i on piece k: newton inside the piece's grid bracket, safeguarded by
  // bisection; guess: the travel predicted from the neighbouring sample (NaN: none), else
  // linear in the scan's bracket. a1: dL/dq there
  Status invert_on(int i, int k, double guess, double& a1) {
    const std::vector<double>& grid_lift = scan.lift;
    const std::vector<double>& turn_q = pieces.turn_q;
    const std::vector<double>& turn_lift = pieces.turn_lift;
    const double target = motion[i].value();
    const auto piece = static_cast<std::size_t>(k);
    const double sign = turn_lift[piece + 1] > turn_lift[piece] ? 1.0 : -1.0;
    // the bracket: between the piece's ends and the scan points inside it, the first whose
    // lift reaches the target and the one before (bisection: the lift is monotone there)
    int inside_lo = static_cast<int>(std::floor(turn_q[piece] / kScanStep)) + 1;
    int inside_hi = static_cast<int>(std::ceil(turn_q[piece + 1] / kScanStep)) - 1;
    while (inside_lo * kScanStep <= turn_q[piece]) ++inside_lo;
    while (inside_hi >= inside_lo && inside_hi * kScanStep >= turn_q[piece + 1]) --inside_hi;
    int reach = inside_lo, past = inside_hi + 1;  // the first scan point inside reaching the target
    auto reaches = [&](int j) { return j > inside_hi || (grid_lift[j] - target) * sign >= 0; };
    if (guess >= 0.0) {  // the scan point just past the predicted travel, if it is that point
      const int near = std::clamp(static_cast<int>(std::ceil(guess / kScanStep)), inside_lo, inside_hi + 1);
      if (reaches(near) && (near == inside_lo || !reaches(near - 1))) reach = past = near;
    }
    while (reach < past) {
      const int mid = (reach + past) / 2;
      if ((grid_lift[mid] - target) * sign >= 0)
        past = mid;
      else
        reach = mid + 1;
    }
    double lo = turn_q[piece], lo_lift = turn_lift[piece], hi = turn_q[piece + 1], hi_lift = turn_lift[piece + 1];
    if (reach > inside_lo) lo = (reach - 1) * kScanStep, lo_lift = grid_lift[reach - 1];
    if (reach <= inside_hi) hi = reach * kScanStep, hi_lift = grid_lift[reach];
    const double span = hi_lift - lo_lift;
    double q = span != 0.0 ? lo + std::clamp((target - lo_lift) / span, 0.0, 1.0) * (hi - lo) : 0.5 * (lo + hi);
    if (guess > lo && guess < hi) q = guess;
    Jet3 L;
    kin::V2<Jet3> c;
    for (int it = 0; it < 100; ++it) {
      const Status st = scan.at(q, L, c);
      if (!st.ok()) return {st.code, st.message, "cam " + deg_of(theta[i]) + " deg"};
      const double f = (L.value() - target) * sign;  // increasing in q on this piece
      if (std::abs(f) <= 1e-13 * std::max(1.0, motion_hi) || hi - lo < 1e-15) {
        a1 = L.c[1];
        q_of[i] = revert(L, q, motion[i]);
        out.centre_x[i] = compose_in(c.x, q_of[i]);
        out.centre_y[i] = compose_in(c.y, q_of[i]);
        return Status::success();
      }
      (f < 0 ? lo : hi) = q;
      double next = L.c[1] * sign > 0 ? q - f / (L.c[1] * sign) : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      q = next;
    }
    return {StatusCode::no_convergence,
            "inverting the valve lift " + fmt(target) + " mm for the travel of the lever '" + scan.follower_name() +
                "' did not converge",
            "cam " + deg_of(theta[i]) + " deg"};
  }

  // one walk from the peak (dir -1: back along the opening stroke, +1: on along the closing
  // stroke; q falls either way): each sample on the piece the lever has reached; the walk
  // moves to the previous piece where the target turns back at that piece's turning lift,
  // and stops where the target is at the lever's rest (q = 0). landing_anchor: its last
  // inverted sample when it reached the rest on the first piece (else unchanged)
  Status walk(int dir, int peak, int& landing_anchor) {
    const std::vector<double>& turn_q = pieces.turn_q;
    const std::vector<double>& turn_lift = pieces.turn_lift;
    int k = pieces.count() - 1;
    int last = -1, last_piece = -1;  // the walk's last inverted sample and its piece
    double extreme = motion[peak].value();  // the target's running extreme on this piece
    bool near_rest = false;  // on the first piece, past the target's last turn: bridged to the rest
    // each walk covers half the revolution (the opening stroke and the base circle before
    // it, the closing stroke and the base circle after it), unless it reaches the rest
    for (int step = dir < 0 ? 0 : 1; dir < 0 ? step <= n / 2 : step < n - n / 2; ++step) {
      const int i = wrap(peak + dir * step);
      if (kind[i] != Kind::open) break;  // met the other walk
      const double target = motion[i].value();
      if (k == 0 && std::abs(target - rest_lift) <= reverse) {  // the lever at rest: the base circle
        if (last_piece == 0) landing_anchor = last;
        break;
      }
      if (near_rest) {
        kind[i] = Kind::bridged;
        continue;
      }
      const auto piece = static_cast<std::size_t>(k);
      const double rises = turn_lift[piece + 1] > turn_lift[piece] ? 1.0 : -1.0;  // L(q) rises with q: +1
      // walking towards smaller q the target must move by -rises; a turn back beyond
      // round-off means the lever passed the piece's lower turning point
      if ((target - extreme) * rises > reverse || (k == 0 && (target - rest_lift) * rises < -reverse)) {
        if (k == 0) {
          // a turn (or a step past the rest lift) within a scan step of the rest: the
          // target's ripple next to the rest, left to the bridge down to q = 0
          near_rest = true;
          kind[i] = Kind::bridged;
          continue;
        }
        if (std::abs(extreme - turn_lift[piece]) > kTurnTolerance * std::max(1.0, motion_hi))
          return {StatusCode::singular,
                  "the target lift turns back at " + fmt(extreme) + " mm, but the lever '" + scan.follower_name() +
                      "' turns back only at " + fmt(turn_lift[piece]) + " mm of lift (its idle travel, at " +
                      fmt(turn_q[piece]) + " mm of cam-roller travel): the lift does not fix the lever's "
                      "travel there",
                  "cam " + deg_of(theta[i]) + " deg"};
        --k;
        // the samples on both sides of the turn: dL/dq ~ 0, their jets by reversion are
        // ill-conditioned, so they are bridged
        kind[wrap(i - dir)] = Kind::bridged;
        kind[i] = Kind::bridged;
        extreme = target;
        continue;
      }
      extreme = (target - extreme) * rises < 0 ? target : extreme;
      double a1 = 0.0, guess = NAN;
      if (last == wrap(i - dir) && last_piece == k) {
        // cubic taylor of the neighbour's travel, one sample on
        const Jet3& q = q_of[last];
        const double s1 = dir * h;
        guess = q.c[0] + s1 * (q.c[1] + s1 * (q.c[2] + s1 * q.c[3]));
      }
      const Status st = invert_on(i, k, guess, a1);
      if (!st.ok()) return st;
      kind[i] = std::abs(a1) < flat ? Kind::bridged : Kind::inverted;
      slope_of[i] = a1;
      last = i, last_piece = k;
    }
    return Status::success();
  }

  // a walk whose last inverted sample (anchor) barely moves the lift lands on the rest as
  // designed (landing_samples) instead of where the target's lift first meets the rest
  // lift: there the lever's travel is ~1e-3 mm, and stepping it to 0 in one sample would put
  // a slope step on the synthesized cam (a -124 mm radius on the bundled Valvetronic)
  void land(int anchor, int dir) {
    if (anchor < 0 || kind[anchor] != Kind::inverted || !(std::abs(slope_of[anchor]) < kLandingSlope * mean_slope))
      return;
    auto walked = [&](int j) { return wrap(anchor + dir * j); };
    // samples past the anchor that the landing may take: the walk's own bridged tail, then
    // the rest up to the other walk
    int available = 1;
    while (available <= kMaxLandingSamples && kind[walked(available)] == Kind::bridged) ++available;
    while (available <= kMaxLandingSamples && kind[walked(available)] == Kind::open) ++available;
    Jet3 q_tau = q_of[anchor];  // its travel in the walked angle tau = dir (theta - theta_anchor)
    q_tau.c[1] *= dir, q_tau.c[3] *= dir;
    const int landing = landing_samples(q_tau, h, available - 1);
    if (landing == 0) return;
    for (int j = 1; j < available; ++j) kind[walked(j)] = j < landing ? Kind::bridged : Kind::open;
  }

  // where the walks meet without reaching the rest, they must agree: the lever rests past
  // its drawing rest (a target whose base circle lies beyond the lever's idle travel)
  Status check_meeting(int peak) {
    const int meet_a = wrap(peak - n / 2), meet_b = (meet_a + n - 1) % n;  // the walks' last samples
    if (kind[meet_a] == Kind::rest || kind[meet_b] == Kind::rest) return Status::success();
    const double gap = std::abs(q_of[meet_a].value() - q_of[meet_b].value());
    if (kind[meet_a] == Kind::inverted && kind[meet_b] == Kind::inverted && gap > 1e-3)
      return {StatusCode::singular,
              "the opening and closing strokes leave the lever '" + scan.follower_name() + "' " + fmt(gap) +
                  " mm of cam-roller travel apart on the base circle: the target's base circle lies on two pieces of "
                  "the lever's lift (before and after its idle travel)",
              "cam " + deg_of(theta[meet_a]) + " deg"};
    out.rest_travel_mm = q_of[meet_a].value();
    return Status::success();
  }

  // the samples at rest take the roller's rest centre; returns their count
  int place_rest() {
    int rest_samples = 0;
    const kin::V2<Jet3> rest_centre{Jet3(scan.jets[0][4]), Jet3(scan.jets[0][8])};
    for (int i = 0; i < n; ++i)
      if (kind[i] == Kind::rest) {
        ++rest_samples;
        out.centre_x[i] = Jet3(rest_centre.x.value());
        out.centre_y[i] = Jet3(rest_centre.y.value());
        q_of[i] = Jet3(0.0);
      }
    return rest_samples;
  }

  // runs of samples where the lift barely moves with q (next to a turning point or the
  // rest) take q from septic hermite pieces between their neighbours' jets; the lever's
  // lift there misses the target by at most out.fill_error_mm
  Status bridge(int& bridged_samples) {
    for (int i = 0; i < n; ++i) {
      if (kind[i] != Kind::bridged || kind[(i + n - 1) % n] == Kind::bridged) continue;
      int count = 0;
      while (count < n && kind[(i + count) % n] == Kind::bridged) ++count;
      if (count >= n) return {StatusCode::singular, "the lift does not fix the lever anywhere", "whole revolution"};
      const int before = (i + n - 1) % n, after = (i + count) % n;
      const double span = (count + 1) * h;
      double p0[4], p1[4];
      for (int o = 0; o < 4; ++o) {
        p0[o] = q_of[before].derivative(o) * std::pow(span, o);
        p1[o] = q_of[after].derivative(o) * std::pow(span, o);
      }
      const Septic piece(p0, p1);
      for (int c = 0; c < count; ++c) {
        const int s = (i + c) % n;
        double d[4];
        piece.eval((c + 1.0) / (count + 1.0), d);  // derivatives per unit of the piece's parameter
        d[0] = std::max(0.0, d[0]);
        for (int o = 1; o < 4; ++o) d[o] /= std::pow(span, o);
        const Jet3 q = jet_from_derivatives<3>(d);
        Jet3 lift;
        kin::V2<Jet3> cc;
        const Status st = scan.at(q.value(), lift, cc);
        if (!st.ok()) return {st.code, st.message, "cam " + deg_of(theta[s]) + " deg"};
        const double e = std::abs(lift.value() - motion[s].value());
        if (e > out.fill_error_mm) out.fill_error_mm = e, out.fill_error_at_rad = theta[s];
        out.centre_x[s] = compose_in(cc.x, q);
        out.centre_y[s] = compose_in(cc.y, q);
        ++bridged_samples;
      }
    }
    return Status::success();
  }
};

}  // namespace

Status invert_floating_follower(const DesignSpec& spec, const MechanismCut& cut, const std::string& target_node,
                                const std::vector<double>& controls, const std::vector<double>& theta,
                                const std::vector<Jet3>& motion, FloatingInversion& out) {
  // the follower's roller, checked: a circle on the lever against a rotational cam
  const detail::FloatingRoller roller = detail::floating_roller(spec, cut);
  // 1. the probe mechanism: a radial probe on the roller, through the lever's rest pose
  kin::Mechanism probe;
  if (Status st = detail::probe_through_rest(cut, roller, target_node, controls, probe); !st.ok()) return st;
  // 2. L(q) and the roller centre scanned from the rest up past the target's largest lift
  double motion_hi = -1e300;
  for (const auto& L : motion) motion_hi = std::max(motion_hi, L.value());
  detail::LeverScan scan(std::move(probe), controls, cut, roller, target_node);
  if (Status st = scan.run(motion_hi); !st.ok()) return st;
  // ... split into monotone pieces at its turning points
  detail::LiftPieces pieces;
  if (Status st = detail::monotone_pieces(scan, motion_hi, pieces); !st.ok()) return st;
  out = {};
  out.centre_x.assign(theta.size(), Jet3(0.0));
  out.centre_y.assign(theta.size(), Jet3(0.0));
  Walker walker(scan, pieces, theta, motion, motion_hi, out);
  // 3. two walks from the target's peak, back along the opening stroke and on along the
  // closing one (the scan continued from the rest keeps the drawing's assembly branch; a
  // cold start next to the peak may land on another one)
  const int n = walker.n;
  int peak = 0;
  for (int i = 1; i < n; ++i)
    if (motion[i].value() > motion[peak].value()) peak = i;
  int landing_anchor[2] = {-1, -1};  // per walk (opening, closing): its last inverted sample when it reached the rest
  for (int dir : {-1, +1})
    if (Status st = walker.walk(dir, peak, landing_anchor[dir > 0]); !st.ok()) return st;
  // landings on the base circle where a walk's end barely moves the lift
  for (int side = 0; side < 2; ++side) walker.land(landing_anchor[side], side == 0 ? -1 : 1);
  // between the two walks: the base circle
  for (auto& kd : walker.kind)
    if (kd == Kind::open) kd = Kind::rest;
  if (Status st = walker.check_meeting(peak); !st.ok()) return st;
  // 4. the rest, then bridges where the lift barely moves with q
  const int rest_samples = walker.place_rest();
  int bridged_samples = 0;
  if (Status st = walker.bridge(bridged_samples); !st.ok()) return st;
  out.rest_lift = walker.rest_lift;
  out.fill_span = std::to_string(rest_samples) + " samples at the lever's rest, " + std::to_string(bridged_samples) +
                  " bridged where the lift barely moves with the lever (" + std::to_string(pieces.count()) +
                  " monotone piece(s) of the lift against the cam-roller travel)";
  return Status::success();
}

}  // namespace camopt::synthesis
