// the HLA's discrete mode: root functions (pressure floor and void, ball at its seat and its
// cage, plunger travel) and the update at an event. Called from CVODE callbacks and between
// CVODE calls: no throw, no allocation (hla_event_names aside, which is for reports).
#include <cmath>

#include "camopt/dynamics/hla.hpp"

namespace camopt::dynamics {

namespace {

// a rebound slower than this ends on the stop [mm/s]: the bounces of a restitution e < 1 form
// a geometric series; the last ones would last nanoseconds
constexpr double kSettleSpeed = 1.0;

// the chamber pressure's rate in pressure mode (not cavitating) at the state
double pressure_rate(const Hla& h, double crank_deg, double z, double zdot, const double* x, const HlaMode& mode) {
  HlaMode pressure_mode = mode;
  pressure_mode.cavitating = false;
  double rates[kHlaStates];
  hla_rates(h, crank_deg, z, zdot, x, pressure_mode, rates);
  return rates[kHlaPressure];
}

// at the floor: cavitating when the pressure would fall below it
void settle_pressure(const Hla& h, double crank_deg, double z, double zdot, double* x, HlaMode& mode,
                     std::uint32_t& events) {
  if (!mode.cavitating) {
    x[kHlaPressure] = h.cavitation_pressure;
    x[kHlaVoid] = 0.0;
    if (pressure_rate(h, crank_deg, z, zdot, x, mode) < 0.0) {
      mode.cavitating = true;
      events |= kHlaCavitationStart;
    }
  } else {
    // the void has closed: the oil fills the chamber again and its pressure rises
    x[kHlaVoid] = 0.0;
    x[kHlaPressure] = h.cavitation_pressure;
    mode.cavitating = false;
    events |= kHlaCavitationEnd;
  }
}

// the ball reached a stop (at lift `stop`, `toward` = +1 for the cage, -1 for the seat): it
// rebounds with the restitution, or rests there while the net force presses it on the stop
void land_ball(const Hla& h, double supply, double p, double* x, HlaMode& mode, double stop, double toward,
               std::uint32_t& events) {
  x[kHlaBallLift] = stop;
  const double rebound = -h.restitution * x[kHlaBallVelocity];
  const bool approaching = x[kHlaBallVelocity] * toward > 0.0;
  if (approaching && std::abs(rebound) > kSettleSpeed) {
    x[kHlaBallVelocity] = rebound;
    events |= kHlaBallBounce;
    return;
  }
  x[kHlaBallVelocity] = 0.0;
  const double pressing = toward * hla_ball_force(h, supply, p, stop, 0.0);
  if (pressing >= 0.0) {
    mode.ball = toward > 0.0 ? HlaBall::caged : HlaBall::seated;
    events |= toward > 0.0 ? kHlaBallCage : kHlaBallSeat;
  }
}

}  // namespace

void hla_roots(const Hla& h, double crank_deg, double, double, const double* x, const HlaMode& mode,
               double* g) noexcept {
  const double supply = h.supply_at(crank_deg), p = x[kHlaPressure], lift = x[kHlaBallLift];
  g[0] = mode.cavitating ? x[kHlaVoid] : p - h.cavitation_pressure;
  g[1] = 1.0;
  g[2] = 1.0;
  if (mode.ball_held) return;
  switch (mode.ball) {
    case HlaBall::seated: g[1] = hla_ball_force(h, supply, p, 0.0, 0.0); break;  // turns > 0: opens
    case HlaBall::free:
      g[1] = lift;                  // falls to 0: lands on the seat
      g[2] = h.ball_travel - lift;  // falls to 0: reaches the cage
      break;
    case HlaBall::caged: g[2] = hla_ball_force(h, supply, p, h.ball_travel, 0.0); break;  // turns < 0: leaves
  }
}

void hla_travel_roots(const Hla& h, double z, double* g) noexcept {
  g[0] = z - h.travel_min;
  g[1] = h.travel_max - z;
}

std::uint32_t hla_on_root(const Hla& h, double crank_deg, double z, double zdot, double* x, HlaMode& mode,
                          const int* found) noexcept {
  std::uint32_t events = 0;
  const double supply = h.supply_at(crank_deg);
  if (found[0] != 0) settle_pressure(h, crank_deg, z, zdot, x, mode, events);
  if (mode.ball_held || (found[1] == 0 && found[2] == 0)) return events;
  const double p = x[kHlaPressure];
  switch (mode.ball) {
    case HlaBall::seated:
      if (found[1] != 0 && hla_ball_force(h, supply, p, 0.0, 0.0) > 0.0) {
        mode.ball = HlaBall::free;
        x[kHlaBallLift] = 0.0;
        x[kHlaBallVelocity] = 0.0;
        events |= kHlaBallOpen;
      }
      break;
    case HlaBall::free:
      if (found[1] != 0) land_ball(h, supply, p, x, mode, 0.0, -1.0, events);
      if (found[2] != 0) land_ball(h, supply, p, x, mode, h.ball_travel, 1.0, events);
      break;
    case HlaBall::caged:
      if (found[2] != 0 && hla_ball_force(h, supply, p, h.ball_travel, 0.0) < 0.0) {
        mode.ball = HlaBall::free;
        x[kHlaBallVelocity] = 0.0;
        events |= kHlaBallLeaveCage;
      }
      break;
  }
  return events;
}

HlaMode hla_settle_mode(const Hla& h, double crank_deg, double z, double zdot, double* x, bool ball_held) noexcept {
  HlaMode mode;
  mode.ball_held = ball_held;
  const double supply = h.supply_at(crank_deg);
  const double lift = x[kHlaBallLift];
  // the ball: on a stop while pressed there, else free
  if (ball_held) {
    mode.ball = lift <= 0.0 ? HlaBall::seated : HlaBall::free;
    x[kHlaBallVelocity] = 0.0;
  } else if (lift <= 0.0) {
    x[kHlaBallLift] = 0.0;
    mode.ball = hla_ball_force(h, supply, x[kHlaPressure], 0.0, x[kHlaBallVelocity]) <= 0.0 ? HlaBall::seated : HlaBall::free;
  } else if (lift >= h.ball_travel) {
    x[kHlaBallLift] = h.ball_travel;
    mode.ball = hla_ball_force(h, supply, x[kHlaPressure], h.ball_travel, x[kHlaBallVelocity]) >= 0.0 ? HlaBall::caged
                                                                                                      : HlaBall::free;
  } else {
    mode.ball = HlaBall::free;
  }
  if (mode.ball != HlaBall::free) x[kHlaBallVelocity] = 0.0;
  // the pressure: at (or below) the floor with a falling rate, the chamber cavitates
  if (x[kHlaPressure] <= h.cavitation_pressure) {
    std::uint32_t events = 0;
    settle_pressure(h, crank_deg, z, zdot, x, mode, events);
  } else {
    x[kHlaVoid] = 0.0;
  }
  return mode;
}

std::string hla_event_names(std::uint32_t events) {
  static constexpr const char* kNames[] = {"cavitation-start", "cavitation-end", "ball-open",  "ball-seat",
                                           "ball-cage",        "ball-leave-cage", "ball-bounce"};
  std::string out;
  for (int i = 0; i < 7; ++i)
    if (events & (1u << i)) out += (out.empty() ? "" : ", ") + std::string(kNames[i]);
  return out;
}

}  // namespace camopt::dynamics
