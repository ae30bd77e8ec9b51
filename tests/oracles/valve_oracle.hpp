#pragma once
// exact piecewise-analytic reference for a single-mass valve driven by an eccentric cam
// through a lash gap, with one-sided spring-damper contacts at the cam and at the seat.
// the flexible valvetrain model is tested against it; nothing here uses camopt library
// code (standard library only), so the two cannot share a mistake.
//
// model (SI inside: m, s, kg, N), x the valve lift, 0 on the seat, + opening:
//   cam     x_c = e (1 - cos(w t + phi)), penetration d_c = x_c - lash - x
//   seat    penetration d_s = -x
//   contact engaged iff g = min(d, k d + c d') > 0; then F = k d + c d', else 0 (never
//           pulls: the linear spring-dashpot of [hunt] with its tensile tail cut off)
//   valve   m x'' = F_c + F_s - F0 - k_v x - c_v x'
// in each of the four contact modes the equation is linear with constant coefficients,
//   m x'' + C x' + K x = f0 + a cos(w t + phi) + b sin(w t + phi),
// solved in closed form [thomson]. a mode switch is a root of some contact's g along the
// current mode's exact solution: found by scanning at a fixed step and bisection, then the
// solution restarts from the state there (x, x' continuous; x'' jumps by c d' / m where a
// contact engages through d = 0).
//
// references
//   [thomson] W. T. Thomson, M. D. Dahleh, Theory of Vibration with Applications, 5th ed.,
//             Prentice Hall, 1998, ch. 2-3 (free damped vibration in the under-, critically
//             and over-damped regimes; response to harmonic and constant forcing).
//   [hunt]    K. H. Hunt, F. R. E. Crossley, "Coefficient of restitution interpreted as
//             damping in vibroimpact", J. Appl. Mech. 42 (1975) 440-445 (the linear
//             spring-dashpot contact: its force jump at touch-down and the tensile force it
//             predicts before separation).
#include <array>
#include <vector>

namespace camopt::oracles {

struct ValveParams {
  double mass = 0;            // m [kg]
  double eccentricity = 0;    // e [m]
  double cam_speed = 0;       // w [rad/s]
  double cam_phase = 0;       // phi [rad]
  double lash = 0;            // [m], >= 0
  double preload = 0;         // F0 [N], >= 0
  double spring_rate = 0;     // k_v [N/m], > 0
  double spring_damping = 0;  // c_v [N s/m], >= 0
  double cam_stiffness = 0;   // k_c [N/m]
  double cam_damping = 0;     // c_c [N s/m]
  double seat_stiffness = 0;  // k_s [N/m]
  double seat_damping = 0;    // c_s [N s/m]

  // x_c, x_c', x_c'' of the cam follower face [m, m/s, m/s^2]
  std::array<double, 3> cam(double t) const;
};

enum class ValveContact { cam, seat };

// which contacts carry force
struct ValveMode {
  bool cam = false, seat = false;
  bool operator==(const ValveMode&) const = default;
};

// g = min(d, k d + c d'): the contact is engaged iff g > 0
double contact_indicator(double d, double d_rate, double stiffness, double damping);

// the exact solution of one mode from (t0, x0, v0): particular part in theta = w t + phi,
//   x_p = x_s + P cos(theta) + Q sin(theta),
// homogeneous part in tau = t - t0 with alpha = C / 2m, lambda = K/m - alpha^2,
//   x_h = A c(tau) + B s(tau),  c = e^{-alpha tau} cos(sqrt(lambda) tau),
//   s = e^{-alpha tau} sin(sqrt(lambda) tau) / sqrt(lambda) (under-damped; cosh / sinh for
//   lambda < 0, c = e^{-alpha tau}, s = tau e^{-alpha tau} at lambda = 0), so that
//   A = x_h(0), B = x_h'(0) + alpha A.
struct ValveSegment {
  enum class Regime { underdamped, critical, overdamped };

  ValveMode mode;
  double t0 = 0;
  double m = 0, C = 0, K = 0;                 // [kg, N s/m, N/m]
  double f0 = 0, a = 0, b = 0;                // forcing [N]
  double w = 0, phi = 0;                      // theta = w t + phi [rad/s, rad]
  double x_static = 0, P = 0, Q = 0;          // particular [m]
  double alpha = 0, lambda = 0;               // [1/s, 1/s^2]
  double A = 0, B = 0;                        // homogeneous [m, m/s]
  Regime regime = Regime::underdamped;

  // x, x', x'' at t [m, m/s, m/s^2], exact derivatives of the closed form
  std::array<double, 3> motion(double t) const;
  // right-hand side f0 + a cos(theta) + b sin(theta) [N]
  double forcing(double t) const;
};

// the segment of mode `mode` starting at (t0, x0, v0); throws std::domain_error at exact
// resonance (C = 0 and K = m w^2 with harmonic forcing)
ValveSegment make_valve_segment(const ValveParams& p, ValveMode mode, double t0, double x0, double v0);

struct ValveStart {
  double t = 0, x = 0, v = 0;  // [s, m, m/s]
};

struct ValveEvent {
  double t = 0;              // [s]
  ValveContact contact = ValveContact::cam;
  bool engages = false;      // false: disengages
  double x = 0, v = 0;       // state at the event [m, m/s]
};

struct ValveSample {
  double x = 0, v = 0, a = 0;             // [m, m/s, m/s^2]
  double cam_force = 0, seat_force = 0;   // [N], >= 0 up to round-off at a switch
};

// the exact solution over [t_begin, t_end] as consecutive segments
struct ValveTrajectory {
  ValveParams params;
  double t_begin = 0, t_end = 0;
  double scan_step = 0;  // [s] the step the switches were searched with
  std::vector<ValveSegment> segments;
  std::vector<ValveEvent> events;

  // the segment holding t (the later one at a switch)
  const ValveSegment& segment_at(double t) const;
  ValveSample at(double t) const;
  // highest lift over [ta, tb] [m]: endpoints and every x' = 0 crossing from + to -
  double max_lift(double ta, double tb) const;

  // the landing is the first seat engagement in [ta, tb] (the window should hold one
  // closing; with lash the valve lands while still on the cam's closing flank, so it is not
  // sought after the cam lets go); seating velocity |x'| there [m/s], NaN if none
  double seating_velocity(double ta, double tb) const;
  // seat engagements in [ta, tb] after the landing
  int bounce_count(double ta, double tb) const;
  // max lift between each seat disengagement after the landing and the next seat
  // engagement, for the flights that end inside [ta, tb] [m]
  std::vector<double> bounce_heights(double ta, double tb) const;
};

// the scan step: max_step, or 1/32 of the fastest period of the four modes and of the cam
// if that is shorter [s]
double valve_scan_step(const ValveParams& p, double max_step);

// integrate exactly from `start` to t_end; the contact mode at the start follows from the
// start state (engaged iff g > 0). throws std::runtime_error past kMaxValveEvents events.
inline constexpr int kMaxValveEvents = 100000;
ValveTrajectory integrate_valve(const ValveParams& p, ValveStart start, double t_end, double max_scan_step = 1e-6);

}  // namespace camopt::oracles
