// the exact single-mass valve checked against itself and against independent numerics:
// each mode's closed form against its equation of motion written out again from the force
// laws, continuity and root accuracy at the switches, a fixed-step RK4 of the same
// non-smooth equation, the energy balance by quadrature, and a lash case that bounces.
#include "oracles/valve_oracle.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

namespace {

using namespace camopt::oracles;
using camopt::test::Series;
namespace tol = camopt::test::tol;

constexpr double pi = std::numbers::pi;

constexpr double kSideStep = 1e-11;               // [s] either side of a switch
constexpr double kBallisticShare = 0.95;          // bounce height over its ballistic height

// the lash case: 4700 rpm, e = 4 mm, lash 0.15 mm, 50 g valve, 250 N preload, 40 N/mm
ValveParams lash_case() {
  ValveParams p;
  p.mass = 0.05;
  p.eccentricity = 4e-3;
  p.cam_speed = 4700.0 * 2.0 * pi / 60.0;
  p.lash = 0.15e-3;
  p.preload = 250.0;
  p.spring_rate = 40e3;
  p.spring_damping = 20.0;
  p.cam_stiffness = 2e8;
  p.cam_damping = 500.0;
  p.seat_stiffness = 5e8;
  p.seat_damping = 1000.0;
  return p;
}

// at rest on the seat under the preload, cam on its base circle (phi = 0, t = 0)
ValveStart seated(const ValveParams& p) { return {0.0, -p.preload / (p.seat_stiffness + p.spring_rate), 0.0}; }

// one revolution plus 0.2 rad: past the closing, before the lash closes again at 0.27 rad
double run_end(const ValveParams& p) { return (2.0 * pi + 0.2) / p.cam_speed; }

// the force laws written out again, independent of the oracle: cam face, gaps, forces
struct Forces {
  double cam = 0, seat = 0, total = 0;  // [N]
  double scale = 0;                     // sum of |every term| [N]
};
Forces forces(const ValveParams& p, double t, double x, double v, bool cam_on, bool seat_on) {
  const double th = p.cam_speed * t + p.cam_phase;
  const double xc = p.eccentricity * (1.0 - std::cos(th)), vc = p.eccentricity * p.cam_speed * std::sin(th);
  Forces f;
  if (cam_on) f.cam = p.cam_stiffness * (xc - p.lash - x) + p.cam_damping * (vc - v);
  if (seat_on) f.seat = -p.seat_stiffness * x - p.seat_damping * v;
  f.total = f.cam + f.seat - p.preload - p.spring_rate * x - p.spring_damping * v;
  f.scale = p.preload + p.spring_rate * std::abs(x) + p.spring_damping * std::abs(v) +
            (cam_on ? p.cam_stiffness * (std::abs(xc) + p.lash + std::abs(x)) +
                          p.cam_damping * (std::abs(vc) + std::abs(v))
                    : 0.0) +
            (seat_on ? p.seat_stiffness * std::abs(x) + p.seat_damping * std::abs(v) : 0.0);
  return f;
}
bool engaged(double d, double d_rate, double k, double c) { return d > 0.0 && k * d + c * d_rate > 0.0; }
// the one-sided laws: a contact pushes while it penetrates and k d + c d' > 0
Forces one_sided(const ValveParams& p, double t, double x, double v) {
  const double th = p.cam_speed * t + p.cam_phase;
  const double dc = p.eccentricity * (1.0 - std::cos(th)) - p.lash - x;
  const double dc_rate = p.eccentricity * p.cam_speed * std::sin(th) - v;
  return forces(p, t, x, v, engaged(dc, dc_rate, p.cam_stiffness, p.cam_damping),
                engaged(-x, -v, p.seat_stiffness, p.seat_damping));
}

// classical RK4 of m x'' = one-sided forces at a fixed step over the trajectory's span: its
// largest deviation from the oracle and its contact events (at the end of the step in
// which the one-sided laws change state)
struct Rk4Run {
  Series x{"rk4 valve lift [m]", "t [s]"}, v{"rk4 valve speed [m/s]", "t [s]"};  // against the oracle
  std::vector<ValveEvent> events;
};
Rk4Run rk4_run(const ValveParams& p, const ValveTrajectory& tr, double h) {
  auto accel = [&](double t, double x, double v) { return one_sided(p, t, x, v).total / p.mass; };
  auto modes = [&](double t, double x, double v) {
    const Forces f = one_sided(p, t, x, v);
    return std::array<bool, 2>{f.cam != 0.0, f.seat != 0.0};
  };
  Rk4Run run;
  double x = tr.at(tr.t_begin).x, v = tr.at(tr.t_begin).v;
  const long n = std::lround((tr.t_end - tr.t_begin) / h);
  std::array<bool, 2> mode = modes(tr.t_begin, x, v);
  for (long i = 0; i < n; ++i) {
    const double t = tr.t_begin + static_cast<double>(i) * h;
    const double k1x = v, k1v = accel(t, x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = accel(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = accel(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = accel(t + h, x + h * k3x, v + h * k3v);
    x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    const double t1 = t + h;
    const std::array<bool, 2> next = modes(t1, x, v);
    for (std::size_t c = 0; c < 2; ++c)
      if (next[c] != mode[c])
        run.events.push_back({t1, c == 0 ? ValveContact::cam : ValveContact::seat, next[c], x, v});
    mode = next;
    const ValveSample e = tr.at(t1);
    run.x.add(t1, x, e.x);
    run.v.add(t1, v, e.v);
  }
  return run;
}

// 5-point gauss-legendre on [-1, 1]
constexpr double kGaussNode[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                  0.9061798459386640};
constexpr double kGaussWeight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                    0.2369268850561891};

}  // namespace

TEST_CASE("valve oracle: each mode's closed form satisfies its equation of motion", "[oracles]") {
  // the lash case (all under-damped), a critically damped set (C^2 = 4 m K exactly in the
  // free and cam modes) and an over-damped one; start state off equilibrium
  const ValveParams critical{1.0, 0.01, 3.0, 0.4, 0.002, 2.0, 4.0, 4.0, 12.0, 4.0, 5.0, 0.0};
  const ValveParams over{1.0, 0.01, 3.0, -0.7, 0.0, 1.0, 4.0, 10.0, 1.0, 30.0, 50.0, 2.0};
  int regimes[3] = {0, 0, 0}, set = 0;
  for (const ValveParams& p : {lash_case(), critical, over}) {
    ++set;
    for (int m = 0; m < 4; ++m) {
      const ValveMode mode{(m & 1) != 0, (m & 2) != 0};
      const double t0 = 0.37 * 2.0 * pi / p.cam_speed, x0 = 1e-3, v0 = -0.2;
      const ValveSegment s = make_valve_segment(p, mode, t0, x0, v0);
      ++regimes[static_cast<int>(s.regime)];
      CHECK_REL(s.motion(t0)[0], x0, tol::kResidualRel);
      CHECK_REL(s.motion(t0)[1], v0, tol::kResidualRel);
      // over 20 periods of the fastest of the mode's frequency, its fastest decay rate and
      // the cam (the slow over-damped root reaches gamma tau > 1)
      const double period = 2.0 * pi / std::max({std::sqrt(s.K / s.m), s.C / s.m, p.cam_speed});
      // the analytic derivatives within kOracleFdRel of their peaks over the samples
      const std::string of = " of set " + std::to_string(set) + " mode " + std::to_string(m);
      Series velocity("x'" + of, "t [s]"), acceleration("x''" + of, "t [s]");
      for (int i = 0; i <= 400; ++i) {
        const double t = t0 + 0.05 * period * i;
        const std::array<double, 3> y = s.motion(t);
        const Forces f = forces(p, t, y[0], y[1], mode.cam, mode.seat);
        INFO("mode " << m << " t " << t << " x " << y[0]);
        CHECK_ABS(p.mass * y[2], f.total, tol::kResidualRel * (p.mass * std::abs(y[2]) + f.scale));
        CHECK_ABS(s.m * y[2] + s.C * y[1] + s.K * y[0], s.forcing(t),
                  tol::kResidualRel * (s.m * std::abs(y[2]) + s.C * std::abs(y[1]) + s.K * std::abs(y[0]) +
                                       std::abs(s.f0) + std::abs(s.a) + std::abs(s.b)));
        // the analytic derivatives against 8th-order differences of x and x'
        const double h = 0.01 * period;
        velocity.add(t, y[1], central_difference([&](double u) { return s.motion(u)[0]; }, t, 1, 4, h));
        acceleration.add(t, y[2], central_difference([&](double u) { return s.motion(u)[1]; }, t, 1, 4, h));
      }
      CHECK_SERIES(velocity.compare({.rel = tol::kOracleFdRel}));
      CHECK_SERIES(acceleration.compare({.rel = tol::kOracleFdRel}));
    }
  }
  CHECK(regimes[0] >= 1);  // under-damped
  CHECK(regimes[1] >= 2);  // critical: free and cam modes of `critical`
  CHECK(regimes[2] >= 1);  // over-damped
}

TEST_CASE("valve oracle: exact resonance of an undamped mode is refused", "[oracles]") {
  // K = k_v + k_c = 4 = m w^2 with the cam engaged, undamped
  const ValveParams p{1.0, 0.01, 2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 3.0, 0.0, 10.0, 0.0};
  CHECK_THROWS_AS(make_valve_segment(p, {true, false}, 0.0, 0.0, 0.0), std::domain_error);
  // the same mode a hair off resonance is solved, with the 1 / (K - m w^2) amplitude
  ValveParams q = p;
  q.cam_stiffness = 3.0 + 1e-6;
  const ValveSegment s = make_valve_segment(q, {true, false}, 0.0, 0.0, 0.0);
  CHECK_REL(s.P, -q.cam_stiffness * q.eccentricity / 1e-6, tol::kNearResonanceRel);
  CHECK_NOTHROW(make_valve_segment(p, {false, true}, 0.0, 0.0, 0.0));
}

TEST_CASE("valve oracle: x, x' continuous and the contact indicator changing sign at every switch", "[oracles]") {
  const ValveParams p = lash_case();
  const ValveTrajectory tr = integrate_valve(p, seated(p), run_end(p));
  REQUIRE(tr.events.size() + 1 == tr.segments.size());  // one contact at a time in this run
  double peak_x = 0, peak_v = 0;
  for (double t = tr.t_begin; t < tr.t_end; t += 1e-6) {
    peak_x = std::max(peak_x, std::abs(tr.at(t).x));
    peak_v = std::max(peak_v, std::abs(tr.at(t).v));
  }
  for (std::size_t i = 0; i < tr.events.size(); ++i) {
    const ValveEvent& e = tr.events[i];
    const ValveSegment &before = tr.segments[i], &after = tr.segments[i + 1];
    REQUIRE(after.t0 == e.t);
    const std::array<double, 3> y0 = before.motion(e.t), y1 = after.motion(e.t);
    INFO("event " << i << " at " << e.t);
    CHECK_ABS(y1[0], y0[0], tol::kSwitchContinuityRel * peak_x);
    CHECK_ABS(y1[1], y0[1], tol::kSwitchContinuityRel * peak_v);
    // along the mode before the switch: engaged state as the mode says just before, the
    // other just after (the one-sided laws of this test decide)
    const bool cam = e.contact == ValveContact::cam;
    auto is_engaged = [&](double t) {
      const std::array<double, 3> y = before.motion(t);
      const double th = p.cam_speed * t + p.cam_phase;
      return cam ? engaged(p.eccentricity * (1 - std::cos(th)) - p.lash - y[0],
                           p.eccentricity * p.cam_speed * std::sin(th) - y[1], p.cam_stiffness, p.cam_damping)
                 : engaged(-y[0], -y[1], p.seat_stiffness, p.seat_damping);
    };
    CHECK(is_engaged(e.t - kSideStep) == !e.engages);
    CHECK(is_engaged(e.t + kSideStep) == e.engages);
    // x'' jumps by c d' / m where a contact engages through d = 0, else it is continuous
    const double th = p.cam_speed * e.t + p.cam_phase;
    const double d = cam ? p.eccentricity * (1 - std::cos(th)) - p.lash - e.x : -e.x;
    const double d_rate = cam ? p.eccentricity * p.cam_speed * std::sin(th) - e.v : -e.v;
    const double c = cam ? p.cam_damping : p.seat_damping;
    const double jump = e.engages && std::abs(d) < 1e-15 ? c * d_rate / p.mass : 0.0;
    CHECK_ABS(y1[2] - y0[2], jump, tol::kAccelJumpRel * c * std::abs(d_rate) / p.mass);
  }
}

TEST_CASE("valve oracle: agrees with a fixed-step RK4 of the non-smooth equation", "[oracles]") {
  // the forces switch inside a step, so RK4's velocity error is first order at each switch:
  // up to the acceleration jump c d' / m (7000 m/s^2 at the first landing) times the part
  // of the step it falls in, erratic in the step. measured at 10 ns: x within 4.4e-10 m, v
  // within 3.8e-5 m/s (20 ns: 4.2e-9 m, 3.6e-4 m/s; 2.5 ns: 2.6e-10 m, 1.4e-5 m/s)
  constexpr double kStep = 1e-8;               // [s]
  const ValveParams p = lash_case();
  const ValveTrajectory tr = integrate_valve(p, seated(p), run_end(p));
  const Rk4Run coarse = rk4_run(p, tr, kStep);
  CHECK_SERIES(coarse.x.compare({.abs = tol::kValveRk4LiftAbs}));
  CHECK_SERIES(coarse.v.compare({.abs = tol::kValveRk4SpeedAbs}));
  REQUIRE(coarse.events.size() == tr.events.size());
  for (std::size_t i = 0; i < coarse.events.size(); ++i) {
    INFO("event " << i << " exact " << tr.events[i].t << " rk4 " << coarse.events[i].t);
    CHECK(coarse.events[i].contact == tr.events[i].contact);
    CHECK(coarse.events[i].engages == tr.events[i].engages);
    CHECK_ABS(coarse.events[i].t, tr.events[i].t, tol::kRk4EventSteps * kStep);
  }
}

TEST_CASE("valve oracle: the cam's work balances kinetic, spring, contact and dissipated energy", "[oracles]") {
  // W_cam = int F_c x_c' dt. with d' = x_c' - x' for the cam and d = -x for the seat,
  //   F_c x_c' = F_c x' + d/dt (k_c d^2 / 2) + c_c d'^2,   F_s x' = -d/dt (k_s d^2 / 2) - c_s d'^2,
  // so W_cam = dKE + d(F0 x + k_v x^2 / 2) + d(contact elastic) + int c d'^2 (cam, seat,
  // valve spring) + the elastic energy k d^2 / 2 a contact holds when its force falls to
  // zero with d > 0 (lost at the release: the law has no tensile tail, [hunt]).
  const ValveParams p = lash_case();
  const ValveTrajectory tr = integrate_valve(p, seated(p), run_end(p));
  double work = 0, gross = 0, dissipated = 0;
  auto integrate = [&](double ta, double tb, const ValveSegment& s) {
    const int pieces = std::max(1, static_cast<int>(std::ceil((tb - ta) / tr.scan_step)));
    for (int j = 0; j < pieces; ++j) {
      const double a = ta + (tb - ta) * j / pieces, b = ta + (tb - ta) * (j + 1) / pieces;
      for (int q = 0; q < 5; ++q) {
        const double t = 0.5 * (a + b) + 0.5 * (b - a) * kGaussNode[q], wq = 0.5 * (b - a) * kGaussWeight[q];
        const std::array<double, 3> y = s.motion(t);
        const double vc = p.eccentricity * p.cam_speed * std::sin(p.cam_speed * t + p.cam_phase);
        const Forces f = forces(p, t, y[0], y[1], s.mode.cam, s.mode.seat);
        work += wq * f.cam * vc;
        gross += wq * std::abs(f.cam * vc);
        dissipated += wq * p.spring_damping * y[1] * y[1];
        if (s.mode.cam) dissipated += wq * p.cam_damping * (vc - y[1]) * (vc - y[1]);
        if (s.mode.seat) dissipated += wq * p.seat_damping * y[1] * y[1];
      }
    }
  };
  for (std::size_t i = 0; i < tr.segments.size(); ++i)
    integrate(tr.segments[i].t0, i + 1 < tr.segments.size() ? tr.segments[i + 1].t0 : tr.t_end, tr.segments[i]);
  // stored energy: kinetic, valve spring, engaged contacts
  auto stored = [&](double t, const ValveMode& mode) {
    const std::array<double, 3> y = tr.segment_at(t).motion(t);
    const double dc = p.eccentricity * (1 - std::cos(p.cam_speed * t + p.cam_phase)) - p.lash - y[0];
    return 0.5 * p.mass * y[1] * y[1] + p.preload * y[0] + 0.5 * p.spring_rate * y[0] * y[0] +
           (mode.cam ? 0.5 * p.cam_stiffness * dc * dc : 0.0) +
           (mode.seat ? 0.5 * p.seat_stiffness * y[0] * y[0] : 0.0);
  };
  // a contact engaging or releasing with d != 0 gains or loses k d^2 / 2
  double released = 0;
  for (const ValveEvent& e : tr.events) {
    const bool cam = e.contact == ValveContact::cam;
    const double d = cam ? p.eccentricity * (1 - std::cos(p.cam_speed * e.t + p.cam_phase)) - p.lash - e.x : -e.x;
    const double held = 0.5 * (cam ? p.cam_stiffness : p.seat_stiffness) * d * d;
    released += e.engages ? -held : held;
  }
  const double change = stored(tr.t_end, tr.segments.back().mode) - stored(tr.t_begin, tr.segments.front().mode);
  INFO("work " << work << " J, gross " << gross << " J, stored change " << change << " J, dissipated " << dissipated
               << " J, released " << released << " J, imbalance " << work - (change + dissipated + released) << " J");
  CHECK_ABS(work, change + dissipated + released, tol::kEnergyBalanceRel * gross);
  // the releases are not negligible here: each bounce's lift-off leaves k_s d^2 / 2 behind
  CHECK(released > 1e3 * tol::kEnergyBalanceRel * gross);
}

TEST_CASE("valve oracle: 4700 rpm with 0.15 mm lash bounces on the seat at closing", "[oracles]") {
  // what the case shows: the valve reaches the seat at 0.537 m/s still riding the closing
  // flank (the cam lets go 9 us later), the stiff lightly damped seat (zeta = 0.1, contact
  // 32 us) throws it back up, and it lands five more times (flights 12 um high down to
  // 65 nm) before it stays down. at opening the cam takes up the lash at the same speed
  // and the valve skips off the cam four times before it follows it.
  const ValveParams p = lash_case();
  const double half_turn = pi / p.cam_speed;
  const ValveTrajectory fine = integrate_valve(p, seated(p), run_end(p), 1e-6);
  const ValveTrajectory finer = integrate_valve(p, seated(p), run_end(p), 0.5e-6);
  CHECK(fine.scan_step == 1e-6);
  REQUIRE(fine.events.size() == finer.events.size());
  for (std::size_t i = 0; i < fine.events.size(); ++i)
    CHECK_REL(finer.events[i].t, fine.events[i].t, tol::kScanHalvingRel);
  const double ta = half_turn, tb = fine.t_end;  // the closing half of the run
  const double v_seat = fine.seating_velocity(ta, tb);
  const int bounces = fine.bounce_count(ta, tb);
  CHECK(finer.bounce_count(ta, tb) == bounces);
  CHECK_REL(finer.seating_velocity(ta, tb), v_seat, tol::kScanHalvingRel);
  CHECK(bounces == 5);
  // landing speed: the cam face speed e w sin(theta) where x_c = lash + F / k_c, the cam
  // force F = F0 + m x_c'' being what the rigid follower would need there
  double xc = p.lash, speed = 0;
  for (int i = 0; i < 3; ++i) {
    const double c = 1.0 - xc / p.eccentricity, s = std::sqrt(1.0 - c * c);
    speed = p.eccentricity * p.cam_speed * s;
    xc = p.lash + (p.preload + p.mass * p.eccentricity * p.cam_speed * p.cam_speed * c) / p.cam_stiffness;
  }
  CHECK_REL(v_seat, speed, tol::kLandingSpeedRel);
  CHECK_REL(v_seat, 0.536589, tol::kPrinted6DigitsRel);
  // bounce heights fall, each below the ballistic height of its lift-off state (x < 0, the
  // seat still compressed, and x') against the preload alone: the valve spring's damping
  // takes energy away, its rate adds at most k_v |x| (0.03 N) below the seat
  const std::vector<double> heights = fine.bounce_heights(ta, tb);
  REQUIRE(static_cast<int>(heights.size()) == bounces);
  std::vector<ValveEvent> lift_off;
  for (const ValveEvent& e : fine.events)
    if (e.t >= ta && e.contact == ValveContact::seat && !e.engages) lift_off.push_back(e);
  REQUIRE(lift_off.size() == heights.size());
  for (std::size_t i = 0; i < heights.size(); ++i) {
    const double ballistic = lift_off[i].x + p.mass * lift_off[i].v * lift_off[i].v / (2.0 * p.preload);
    INFO("bounce " << i << " height " << heights[i] << " ballistic " << ballistic);
    CHECK(heights[i] < ballistic);
    CHECK(heights[i] > kBallisticShare * ballistic);
    if (i > 0) CHECK(heights[i] < heights[i - 1]);
  }
  CHECK_REL(finer.bounce_heights(ta, tb)[0], heights[0], tol::kScanHalvingRel);
  // peak lift, quasi-static by then (the opening's skips decay at c / 2m = 5200 1/s): the
  // cam's 2 e - lash less the contact deflection under F0 + k_v x - m e w^2
  const double top = 2.0 * p.eccentricity - p.lash;
  const double deflection =
      (p.preload + p.spring_rate * top - p.mass * p.eccentricity * p.cam_speed * p.cam_speed) / p.cam_stiffness;
  CHECK_ABS(fine.max_lift(0.0, ta + 0.5 * half_turn), top - deflection, tol::kQuasiStaticDeflectionRel * deflection);
}
