// the HLA's physics as pure functions (docs/hla.md, equations 1-9) and the hydraulic state's
// rates. Everything here is called from CVODE callbacks: no throw, no allocation.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "camopt/dynamics/hla.hpp"

namespace camopt::dynamics {

namespace {

// int_0^p dp' / beta_oil(p') with beta_oil = b0 + b1 p (a linear tangent modulus; eq. 1)
double oil_log_compression(const Hla& h, double p) {
  if (h.bulk_modulus_slope == 0.0) return p / h.bulk_modulus;
  return std::log1p(h.bulk_modulus_slope * p / h.bulk_modulus) / h.bulk_modulus_slope;
}

}  // namespace

// eq. 1: a unit volume of the mixture at 0 gauge holds (1 - x) oil and x free air; at p the oil
// has shrunk by exp(-int dp / beta_oil) and the air follows p_abs V^n = const
double hla_volume_ratio(const Hla& h, double p) {
  const double x = h.air_fraction;
  const double oil = (1.0 - x) * std::exp(-oil_log_compression(h, p));
  if (x == 0.0) return oil;
  const double air = x * std::pow(h.atmospheric_pressure / (h.atmospheric_pressure + p), 1.0 / h.polytropic_index);
  return oil + air;
}

// eq. 2: beta_eff = -s / (ds/dp), s = hla_volume_ratio
double hla_bulk_modulus(const Hla& h, double p) {
  const double x = h.air_fraction;
  const double beta_oil = h.bulk_modulus + h.bulk_modulus_slope * p;
  const double oil = (1.0 - x) * std::exp(-oil_log_compression(h, p));
  if (x == 0.0) return beta_oil;
  const double p_abs = h.atmospheric_pressure + p;
  const double air = x * std::pow(h.atmospheric_pressure / p_abs, 1.0 / h.polytropic_index);
  return (oil + air) / (oil / beta_oil + air / (h.polytropic_index * p_abs));
}

// eq. 3
double hla_chamber_volume(const Hla& h, double z) { return h.chamber_volume + h.plunger_area * z; }

// eq. 5: Poiseuille flow through the eccentric annulus plus the Couette flow the plunger drags
double hla_leak_flow(const Hla& h, double dp, double zdot) {
  return h.leak_conductance * dp + h.couette_area * zdot;
}

// eq. 6: Q = Cd A sqrt(2/rho) dp / (dp^2 + p_t^2)^(1/4): the orifice law for |dp| >> p_t,
// linear in dp below p_t, so the rates stay Lipschitz through dp = 0
double hla_orifice_law(double cd_area, double dp, double density, double transition_pressure) {
  if (cd_area == 0.0) return 0.0;
  const double scale = std::sqrt(std::sqrt(dp * dp + transition_pressure * transition_pressure));
  return cd_area * std::sqrt(2.0 / density) * dp / scale;
}

// eq. 7: the curtain area under the ball, at most the seat bore
double hla_valve_area(const Hla& h, double lift) {
  const double curtain = std::numbers::pi * h.seat_diameter * std::max(lift, 0.0);
  return std::min(curtain, h.seat_area);
}

// eq. 8
double hla_ball_force(const Hla& h, double supply, double p, double lift, double lift_rate) {
  return (supply - p) * h.seat_area - (h.ball_spring_preload + h.ball_spring_rate * lift) - h.ball_damping * lift_rate;
}

// eq. 9: the reservoir is at the supply pressure
double hla_force(const Hla& h, double crank_deg, double p, double z) {
  return (p - h.supply_at(crank_deg)) * h.plunger_area + h.spring_preload - h.spring_rate * z;
}

void hla_rates(const Hla& h, double crank_deg, double z, double zdot, const double* x, const HlaMode& mode,
               double* rates, HlaFlows* flows) noexcept {
  const double p = x[kHlaPressure], lift = x[kHlaBallLift], lift_rate = x[kHlaBallVelocity];
  const double supply = h.supply_at(crank_deg);
  // the flows (eqs. 5-7); the seated ball closes the valve whatever the state's lift
  HlaFlows q;
  q.leak = hla_leak_flow(h, p - supply, zdot);
  q.orifice = hla_orifice_law(h.orifice_cd * h.orifice_area, p - supply, h.density, h.transition_pressure);
  const double open_lift = mode.ball == HlaBall::seated ? 0.0 : lift;
  q.refill = hla_orifice_law(h.valve_cd * hla_valve_area(h, open_lift), supply - p, h.density, h.transition_pressure);
  const double net = q.refill - q.leak - q.orifice;  // into the chamber
  const double swept = h.plunger_area * zdot;           // the chamber's growth
  // pressure or void (eq. 4): the void takes the volume the oil cannot fill at the floor
  if (mode.cavitating) {
    rates[kHlaPressure] = 0.0;
    rates[kHlaVoid] = swept - net;
  } else {
    const double oil_volume = hla_chamber_volume(h, z) - x[kHlaVoid];
    rates[kHlaPressure] = hla_bulk_modulus(h, p) / oil_volume * (net - swept);
    rates[kHlaVoid] = 0.0;
  }
  // the ball (eq. 8): free between its stops, held on a stop
  if (mode.ball == HlaBall::free && !mode.ball_held) {
    rates[kHlaBallLift] = lift_rate;
    rates[kHlaBallVelocity] = hla_ball_force(h, supply, p, lift, lift_rate) / h.ball_mass;
  } else {
    rates[kHlaBallLift] = 0.0;
    rates[kHlaBallVelocity] = 0.0;
  }
  if (flows) *flows = q;
}

}  // namespace camopt::dynamics
