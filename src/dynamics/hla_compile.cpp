// the HLA's spec -> validated constants in the dynamics' units (docs/hla.md, "Rules"): one rule
// per line, each an InputError at the key that breaks it, naming the value and the rule
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "camopt/dynamics/hla.hpp"

namespace camopt::dynamics {

namespace {

constexpr double kSteelDensity = 7850.0;  // [kg/m^3] a steel check ball when its mass is not given
constexpr double kKelvin = 273.15;

// the shortest text that reads back to the value (as the file gave it)
std::string shortest(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// "value v must be <rule>" at the key, unless ok
void require(bool ok, const HlaSpec& s, std::string_view key, double value, const std::string& rule) {
  if (!ok) throw InputError(s.at(key), "value " + shortest(value) + " must be " + rule);
}

void check_plunger(const HlaSpec& s) {
  require(s.plunger_diameter_mm > 0.0, s, "plunger_diameter_mm", s.plunger_diameter_mm, "> 0");
  require(s.plunger_mass_kg > 0.0, s, "plunger_mass_kg", s.plunger_mass_kg, "> 0");
  require(s.travel_min_mm <= 0.0, s, "travel_min_mm", s.travel_min_mm,
          "<= 0 (the travel limits must contain the drawing's z = 0)");
  require(s.travel_max_mm >= 0.0, s, "travel_max_mm", s.travel_max_mm,
          ">= 0 (the travel limits must contain the drawing's z = 0)");
  require(s.travel_max_mm > s.travel_min_mm, s, "travel_max_mm", s.travel_max_mm,
          "> travel_min_mm (" + format_value(s.travel_min_mm) + ")");
  require(s.return_spring_rate_N_per_mm >= 0.0, s, "return_spring_rate_N_per_mm", s.return_spring_rate_N_per_mm, ">= 0");
  require(s.return_spring_preload_N >= 0.0, s, "return_spring_preload_N", s.return_spring_preload_N, ">= 0");
  if (s.series_body_mass_kg)
    require(*s.series_body_mass_kg > 0.0, s, "series_body_mass_kg", *s.series_body_mass_kg, "> 0");
}

void check_oil(const HlaSpec& s) {
  require(s.chamber_volume_mm3 > 0.0, s, "chamber_volume_mm3", s.chamber_volume_mm3, "> 0");
  const double area = std::numbers::pi / 4.0 * s.plunger_diameter_mm * s.plunger_diameter_mm;
  const double collapsed = s.chamber_volume_mm3 + area * s.travel_min_mm;
  require(collapsed > 0.0, s, "chamber_volume_mm3", s.chamber_volume_mm3,
          "> -A_p travel_min_mm (" + format_value(-area * s.travel_min_mm) +
              " mm^3): the chamber must keep a volume at the plunger's lowest stop");
  require(s.bulk_modulus_MPa > 0.0, s, "bulk_modulus_MPa", s.bulk_modulus_MPa, "> 0");
  require(s.bulk_modulus_pressure_slope >= 0.0, s, "bulk_modulus_pressure_slope", s.bulk_modulus_pressure_slope, ">= 0");
  require(s.air_volume_fraction >= 0.0 && s.air_volume_fraction < 1.0, s, "air_volume_fraction",
          s.air_volume_fraction, "in [0, 1)");
  require(s.air_polytropic_index >= 1.0 && s.air_polytropic_index <= 1.4, s, "air_polytropic_index",
          s.air_polytropic_index, "in [1, 1.4] (isothermal to adiabatic air)");
  require(s.atmospheric_pressure_MPa > 0.0, s, "atmospheric_pressure_MPa", s.atmospheric_pressure_MPa, "> 0");
  require(s.cavitation_pressure_MPa > -s.atmospheric_pressure_MPa, s, "cavitation_pressure_MPa",
          s.cavitation_pressure_MPa,
          "> -atmospheric_pressure_MPa (" + format_value(-s.atmospheric_pressure_MPa) +
              "): the floor is a gauge pressure above absolute zero");
  require(s.oil_density_kg_per_m3 > 0.0, s, "oil_density_kg_per_m3", s.oil_density_kg_per_m3, "> 0");
  require(s.oil_viscosity_100C_mm2_per_s > 0.3, s, "oil_viscosity_100C_mm2_per_s", s.oil_viscosity_100C_mm2_per_s,
          "> 0.3 (Walther's log log (nu + 0.7) needs nu + 0.7 > 1)");
  require(s.oil_viscosity_40C_mm2_per_s > s.oil_viscosity_100C_mm2_per_s, s, "oil_viscosity_40C_mm2_per_s",
          s.oil_viscosity_40C_mm2_per_s,
          "> oil_viscosity_100C_mm2_per_s (" + format_value(s.oil_viscosity_100C_mm2_per_s) + ")");
  require(s.oil_temperature_C > -50.0 && s.oil_temperature_C < 200.0, s, "oil_temperature_C", s.oil_temperature_C,
          "in (-50, 200)");
}

void check_leak(const HlaSpec& s) {
  require(s.leak_clearance_mm > 0.0, s, "leak_clearance_mm", s.leak_clearance_mm, "> 0");
  require(s.leak_clearance_mm < 0.05 * s.plunger_diameter_mm, s, "leak_clearance_mm", s.leak_clearance_mm,
          "< 0.05 plunger_diameter_mm (" + format_value(0.05 * s.plunger_diameter_mm) +
              "): the annulus law is for a thin gap");
  require(s.leak_eccentricity_ratio >= 0.0 && s.leak_eccentricity_ratio < 1.0, s, "leak_eccentricity_ratio",
          s.leak_eccentricity_ratio, "in [0, 1)");
  require(s.leak_length_mm > 0.0, s, "leak_length_mm", s.leak_length_mm, "> 0");
  if (s.orifice_diameter_mm)
    require(*s.orifice_diameter_mm > 0.0, s, "orifice_diameter_mm", *s.orifice_diameter_mm, "> 0");
  require(s.orifice_discharge_coefficient > 0.0 && s.orifice_discharge_coefficient <= 1.0, s,
          "orifice_discharge_coefficient", s.orifice_discharge_coefficient, "in (0, 1]");
  require(s.orifice_transition_pressure_MPa > 0.0, s, "orifice_transition_pressure_MPa",
          s.orifice_transition_pressure_MPa, "> 0");
}

void check_valve(const HlaSpec& s) {
  require(s.ball_diameter_mm > 0.0, s, "ball_diameter_mm", s.ball_diameter_mm, "> 0");
  if (s.ball_mass_kg) require(*s.ball_mass_kg > 0.0, s, "ball_mass_kg", *s.ball_mass_kg, "> 0");
  require(s.seat_diameter_mm > 0.0, s, "seat_diameter_mm", s.seat_diameter_mm, "> 0");
  require(s.seat_diameter_mm < s.ball_diameter_mm, s, "seat_diameter_mm", s.seat_diameter_mm,
          "< ball_diameter_mm (" + format_value(s.ball_diameter_mm) + "): the ball must cover the seat");
  require(s.ball_travel_mm > 0.0, s, "ball_travel_mm", s.ball_travel_mm, "> 0");
  if (s.cage_height_mm) {
    // the seated ball's top sits sqrt(R^2 - r^2) + R above the seat plane
    const double r = 0.5 * s.seat_diameter_mm, big_r = 0.5 * s.ball_diameter_mm;
    const double top = std::sqrt(big_r * big_r - r * r) + big_r;
    require(s.ball_travel_mm <= *s.cage_height_mm - top, s, "ball_travel_mm", s.ball_travel_mm,
            "<= cage_height_mm - seated ball top (" + format_value(*s.cage_height_mm) + " - " + format_value(top) +
                " = " + format_value(*s.cage_height_mm - top) + " mm): the ball's travel is larger than its cage");
  }
  require(s.ball_spring_rate_N_per_mm >= 0.0, s, "ball_spring_rate_N_per_mm", s.ball_spring_rate_N_per_mm, ">= 0");
  require(s.ball_spring_preload_N >= 0.0, s, "ball_spring_preload_N", s.ball_spring_preload_N, ">= 0");
  require(s.ball_damping_N_s_per_m >= 0.0, s, "ball_damping_N_s_per_m", s.ball_damping_N_s_per_m, ">= 0");
  require(s.valve_discharge_coefficient > 0.0 && s.valve_discharge_coefficient <= 1.0, s,
          "valve_discharge_coefficient", s.valve_discharge_coefficient, "in (0, 1]");
  require(s.ball_restitution >= 0.0 && s.ball_restitution < 1.0, s, "ball_restitution", s.ball_restitution,
          "in [0, 1)");
}

void check_supply(const HlaSpec& s) {
  const bool constant = s.supply_pressure_MPa.has_value(), table = !s.supply_crank_deg.empty();
  if (constant == table)
    throw InputError(s.at(constant ? "supply_table" : "supply_pressure_MPa"),
                     "give exactly one of supply_pressure_MPa and supply_table");
  if (table) {
    if (s.supply_crank_deg.size() != s.supply_table_MPa.size() || s.supply_crank_deg.size() < 2)
      throw InputError(s.at("supply_table"), "the supply table needs at least 2 rows of crank_deg, pressure_MPa");
    for (std::size_t i = 1; i < s.supply_crank_deg.size(); ++i)
      require(s.supply_crank_deg[i] > s.supply_crank_deg[i - 1], s, "supply_table", s.supply_crank_deg[i],
              "> the previous crank_deg (row " + std::to_string(i) + ")");
    const double span = s.supply_crank_deg.back() - s.supply_crank_deg.front();
    require(span < 720.0, s, "supply_table", span, "< 720 crank deg (one cycle; do not repeat the first row)");
  }
}

// the chamber holds the return spring's preload (docs/hla.md, "Rules"): unloaded, the plunger's
// balance (p - p_supply) A_p + F_s(0) = 0 needs p = p_supply - F_s(0) / A_p, which must lie
// above the cavitation floor at the lowest supply pressure; else the spring would pull a void
// instead of refilling the chamber through the check valve
void check_preload_held(const Hla& h, const HlaSpec& s) {
  const double p_unloaded = h.supply_min() - h.spring_preload / h.plunger_area;
  if (!(p_unloaded > h.cavitation_pressure))
    throw InputError(s.at("return_spring_preload_N"),
                     "value " + shortest(s.return_spring_preload_N) +
                         ": the chamber cannot hold the preload at the supply pressure: unloaded, the plunger needs "
                         "p = p_supply_min - preload / A_p = " + format_value(h.supply_min()) + " - " +
                         format_value(h.spring_preload) + " / " + format_value(h.plunger_area) + " = " +
                         format_value(p_unloaded) + " MPa, which must be > cavitation_pressure_MPa (" +
                         format_value(h.cavitation_pressure) + ")");
}

}  // namespace

Hla compile_hla(const HlaSpec& s) {
  // every single-key and joint rule, before anything is derived
  check_plunger(s);
  check_oil(s);
  check_leak(s);
  check_valve(s);
  check_supply(s);
  const double axis_length = std::hypot(s.axis[0], s.axis[1]);
  if (!(axis_length > 0.0) || !std::isfinite(axis_length))
    throw InputError(s.at("axis"), "value [" + format_value(s.axis[0]) + ", " + format_value(s.axis[1]) +
                                       "] must have non-zero finite length");

  Hla h;
  h.name = s.name;
  h.node = s.node;
  h.where = s.where;
  h.axis = Eigen::Vector2d(s.axis[0], s.axis[1]) / axis_length;
  // plunger and body
  h.plunger_diameter = s.plunger_diameter_mm;
  h.plunger_area = std::numbers::pi / 4.0 * s.plunger_diameter_mm * s.plunger_diameter_mm;
  h.plunger_mass = s.plunger_mass_kg * 1e-3;
  h.series_body_mass = s.series_body_mass_kg.value_or(0.0) * 1e-3;
  h.travel_min = s.travel_min_mm;
  h.travel_max = s.travel_max_mm;
  h.spring_preload = s.return_spring_preload_N;
  h.spring_rate = s.return_spring_rate_N_per_mm;
  // chamber and oil
  h.chamber_volume = s.chamber_volume_mm3;
  h.bulk_modulus = s.bulk_modulus_MPa;
  h.bulk_modulus_slope = s.bulk_modulus_pressure_slope;
  h.air_fraction = s.air_volume_fraction;
  h.polytropic_index = s.air_polytropic_index;
  h.atmospheric_pressure = s.atmospheric_pressure_MPa;
  h.cavitation_pressure = s.cavitation_pressure_MPa;
  h.density = s.oil_density_kg_per_m3 * 1e-12;
  const double nu = walther_viscosity(s.oil_viscosity_40C_mm2_per_s, s.oil_viscosity_100C_mm2_per_s, s.oil_temperature_C);
  h.viscosity = s.oil_density_kg_per_m3 * nu * 1e-12;  // rho [kg/m^3] nu [mm^2/s] -> [N s/mm^2]
  // leak-down
  h.clearance = s.leak_clearance_mm;
  h.eccentricity = s.leak_eccentricity_ratio;
  h.leak_length = s.leak_length_mm;
  h.leak_conductance = std::numbers::pi * h.plunger_diameter * std::pow(h.clearance, 3) *
                       (1.0 + 1.5 * h.eccentricity * h.eccentricity) / (12.0 * h.viscosity * h.leak_length);
  h.couette_area = 0.5 * std::numbers::pi * h.plunger_diameter * h.clearance;
  if (s.orifice_diameter_mm) h.orifice_area = std::numbers::pi / 4.0 * *s.orifice_diameter_mm * *s.orifice_diameter_mm;
  h.orifice_cd = s.orifice_discharge_coefficient;
  h.transition_pressure = s.orifice_transition_pressure_MPa;
  // check valve
  const double ball_kg = s.ball_mass_kg.value_or(kSteelDensity * std::numbers::pi / 6.0 * std::pow(s.ball_diameter_mm * 1e-3, 3));
  h.ball_mass = ball_kg * 1e-3;
  h.seat_diameter = s.seat_diameter_mm;
  h.seat_area = std::numbers::pi / 4.0 * s.seat_diameter_mm * s.seat_diameter_mm;
  h.ball_travel = s.ball_travel_mm;
  h.ball_spring_rate = s.ball_spring_rate_N_per_mm;
  h.ball_spring_preload = s.ball_spring_preload_N;
  h.ball_damping = s.ball_damping_N_s_per_m * 1e-3;
  h.valve_cd = s.valve_discharge_coefficient;
  h.restitution = s.ball_restitution;
  // supply
  h.supply_constant = s.supply_pressure_MPa.value_or(0.0);
  h.supply_crank_deg = s.supply_crank_deg;
  h.supply_pressure = s.supply_table_MPa;
  const double p_min = h.supply_min();
  require(p_min > h.cavitation_pressure, s, s.supply_pressure_MPa ? "supply_pressure_MPa" : "supply_table", p_min,
          "> cavitation_pressure_MPa (" + format_value(h.cavitation_pressure) + ") (the lowest supply pressure)");
  check_preload_held(h, s);
  return h;
}

double walther_viscosity(double nu40, double nu100, double temp_C) {
  const auto loglog = [](double nu) { return std::log10(std::log10(nu + 0.7)); };
  const double t40 = std::log10(40.0 + kKelvin), t100 = std::log10(100.0 + kKelvin);
  const double b = (loglog(nu40) - loglog(nu100)) / (t100 - t40);
  const double a = loglog(nu40) + b * t40;
  return std::pow(10.0, std::pow(10.0, a - b * std::log10(temp_C + kKelvin))) - 0.7;
}

double Hla::supply_at(double crank_deg) const noexcept {
  if (supply_crank_deg.empty()) return supply_constant;
  const std::vector<double>& x = supply_crank_deg;
  const std::vector<double>& y = supply_pressure;
  // wrap into [x0, x0 + 720); between the last row and x0 + 720 the table closes linearly
  const double period = 720.0;
  double a = std::fmod(crank_deg - x.front(), period);
  if (a < 0.0) a += period;
  a += x.front();
  if (a >= x.back()) {
    const double u = (a - x.back()) / (x.front() + period - x.back());
    return y.back() + u * (y.front() - y.back());
  }
  const auto it = std::upper_bound(x.begin(), x.end(), a);
  const std::size_t i = static_cast<std::size_t>(it - x.begin()) - 1;
  const double u = (a - x[i]) / (x[i + 1] - x[i]);
  return y[i] + u * (y[i + 1] - y[i]);
}

double Hla::supply_min() const noexcept {
  if (supply_pressure.empty()) return supply_constant;
  return *std::min_element(supply_pressure.begin(), supply_pressure.end());
}

}  // namespace camopt::dynamics
