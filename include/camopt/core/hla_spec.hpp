#pragma once
// plain description of a hydraulic lash adjuster ([[hla]], docs/hla.md) as read from a design
// file. No validation beyond types and single-value ranges happens here;
// dynamics::compile_hla (camopt/dynamics/hla.hpp) checks the rules that join several keys.
//
// pressures are gauge pressures [MPa] (atmospheric = 0) unless a key says otherwise; the
// plunger coordinate z [mm] is its extension out of the body from the drawing (z > 0: the
// HLA is longer, it pushes the supported node further along `axis`).
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "camopt/core/error.hpp"

namespace camopt {

struct HlaSpec {
  std::string name;
  std::string node;                  // the node whose pivot (or contact point) the HLA supports
  std::array<double, 2> axis{0, 1};  // plunger extension direction in the drawing (any length)

  // plunger and body
  double plunger_diameter_mm = 0.0;
  double plunger_mass_kg = 0.0;
  double travel_min_mm = 0.0, travel_max_mm = 0.0;  // stops of z (must contain 0)
  double return_spring_rate_N_per_mm = 0.0;         // F_s(z) = preload - rate z, pushing out
  double return_spring_preload_N = 0.0;             // at z = 0
  // in series on a translational node (a bucket tappet, a rocker arm's valve-side insert): the
  // mass of the part on the contacts' side of the chamber, out of the node's mass_kg [kg];
  // none for an HLA under a rotational node's pivot
  std::optional<double> series_body_mass_kg;

  // high-pressure chamber and its oil
  double chamber_volume_mm3 = 0.0;            // at z = 0
  double bulk_modulus_MPa = 1500.0;           // of the air-free oil at 0 gauge
  double bulk_modulus_pressure_slope = 0.0;   // d(beta_oil)/dp [-]
  double air_volume_fraction = 0.0;           // free air at atmospheric pressure [-]
  double air_polytropic_index = 1.0;          // 1 = isothermal
  double atmospheric_pressure_MPa = 0.101325; // absolute
  double cavitation_pressure_MPa = -0.095;    // floor of the chamber pressure (gauge)
  double oil_density_kg_per_m3 = 850.0;
  double oil_viscosity_40C_mm2_per_s = 0.0;   // kinematic, ASTM D341 (Walther) pair
  double oil_viscosity_100C_mm2_per_s = 0.0;
  double oil_temperature_C = 0.0;

  // leak-down: plunger-body annulus, optional fixed orifice
  double leak_clearance_mm = 0.0;  // radial
  double leak_eccentricity_ratio = 0.0;
  double leak_length_mm = 0.0;
  std::optional<double> orifice_diameter_mm;
  double orifice_discharge_coefficient = 0.7;
  double orifice_transition_pressure_MPa = 1e-4;  // the smooth laminar law below it (also the valve's)

  // check valve
  double ball_diameter_mm = 0.0;
  std::optional<double> ball_mass_kg;   // default: a steel ball, 7850 kg/m^3
  double seat_diameter_mm = 0.0;
  double ball_travel_mm = 0.0;          // lift at the cage stop
  std::optional<double> cage_height_mm; // the cage's inner height above the seat plane
  double ball_spring_rate_N_per_mm = 0.0;
  double ball_spring_preload_N = 0.0;   // at the seat
  double ball_damping_N_s_per_m = 0.0;
  double valve_discharge_coefficient = 0.6;
  double ball_restitution = 0.0;        // at the seat and at the cage

  // supply: gallery pressure, constant or a table against crank angle (one 720-deg cycle)
  std::optional<double> supply_pressure_MPa;
  std::vector<double> supply_crank_deg, supply_table_MPa;
  std::string supply_source_file;  // resolved path of supply_table

  SourceRef where;                                  // the [[hla]] table
  std::vector<std::pair<std::string, SourceRef>> key_where;  // each key written

  // where `key` was written (the table, with the key path, when it was not)
  SourceRef at(std::string_view key) const {
    for (const auto& [k, ref] : key_where)
      if (k == key) return ref;
    SourceRef ref = where;
    ref.key_path = where.key_path.empty() ? std::string(key) : where.key_path + "." + std::string(key);
    return ref;
  }
};

}  // namespace camopt
