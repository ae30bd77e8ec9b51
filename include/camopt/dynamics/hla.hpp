#pragma once
// the hydraulic lash adjuster (HLA) element (docs/hla.md): compiled constants, the physics as
// pure functions, the hydraulic state and its discrete mode, the root functions and the event
// update a CVODE model calls, and a standalone rig that integrates one HLA under a prescribed
// load or motion (the leak-down tester, a cam event).
//
// units inside: lengths [mm], masses [N s^2/mm] (kg x 1e-3), forces [N], time [s], pressures
// [N/mm^2 = MPa] (gauge unless named absolute), volumes [mm^3], flows [mm^3/s], viscosity
// [N s/mm^2] (Pa s x 1e-6), density [N s^2/mm^4] (kg/m^3 x 1e-12).
//
// the coupling's contract: the plunger coordinate z [mm] is the HLA's extension from the
// drawing along `axis`, zdot its rate [mm/s]; the HLA pushes the supported node along +axis
// with hla_force(...) and the node's motion along axis is z. The hydraulic state is
// kHlaStates doubles (HlaIndex) added to the same CVODE vector; hla_rates fills their
// derivatives. hla_roots (kHlaRoots values) and hla_travel_roots (2 values) join the model's
// root functions; at a root the model calls hla_on_root, then restarts CVODE. None of the
// functions called from a CVODE callback throws or allocates.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/hla_spec.hpp"

namespace camopt::dynamics {

// validated constants of one HLA, in the units above
struct Hla {
  std::string name, node;
  Eigen::Vector2d axis{0, 1};  // unit: the direction the plunger pushes the node
  SourceRef where;

  // plunger and body
  double plunger_diameter = 0.0, plunger_area = 0.0;  // D [mm], A_p = pi D^2 / 4 [mm^2]
  double plunger_mass = 0.0;                          // [N s^2/mm]
  double travel_min = 0.0, travel_max = 0.0;          // stops of z [mm]
  double spring_preload = 0.0, spring_rate = 0.0;     // F_s(z) = preload - rate z [N]
  double series_body_mass = 0.0;  // in series: the contact side's mass [N s^2/mm]; 0 under a pivot

  // chamber and oil
  double chamber_volume = 0.0;      // V0 at z = 0 [mm^3]
  double bulk_modulus = 0.0;        // air-free oil at 0 gauge [MPa]
  double bulk_modulus_slope = 0.0;  // d(beta_oil)/dp [-]
  double air_fraction = 0.0;        // free air at atmospheric pressure [-]
  double polytropic_index = 1.0;    // [-]
  double atmospheric_pressure = 0.101325;  // absolute [MPa]
  double cavitation_pressure = 0.0;        // floor (gauge) [MPa]
  double density = 0.0;                    // [N s^2/mm^4]
  double viscosity = 0.0;                  // dynamic, at the oil temperature [N s/mm^2]

  // leak-down
  double clearance = 0.0, eccentricity = 0.0, leak_length = 0.0;  // c, eps, L [mm, -, mm]
  double leak_conductance = 0.0;  // pi D c^3 (1 + 1.5 eps^2) / (12 mu L) [mm^3/(s MPa)]
  double couette_area = 0.0;      // pi D c / 2 [mm^2]: Couette flow = couette_area * zdot
  double orifice_area = 0.0;      // fixed orifice [mm^2] (0: none)
  double orifice_cd = 0.0;
  double transition_pressure = 0.0;  // below it the orifice laws turn laminar [MPa]

  // check valve
  double ball_mass = 0.0;        // [N s^2/mm]
  double seat_diameter = 0.0, seat_area = 0.0;  // [mm], pi d^2 / 4 [mm^2]
  double ball_travel = 0.0;      // lift at the cage [mm]
  double ball_spring_rate = 0.0, ball_spring_preload = 0.0;  // closing force preload + rate h [N]
  double ball_damping = 0.0;     // [N s/mm]
  double valve_cd = 0.0;
  double restitution = 0.0;      // ball at the seat and the cage [-]

  // supply: constant, or a table over one 720-deg cycle from its first angle (linear, wrapped)
  double supply_constant = 0.0;  // [MPa]
  std::vector<double> supply_crank_deg, supply_pressure;

  // gallery pressure at a crank angle [MPa]; the reservoir in the plunger is at this pressure
  double supply_at(double crank_deg) const noexcept;
  // the lowest gallery pressure over the cycle [MPa]
  double supply_min() const noexcept;
};

// validated constants; every rule broken is an InputError naming file:line:column: key, value
// and rule (docs/hla.md, "Rules")
Hla compile_hla(const HlaSpec& spec);

// ---- the physics (pure functions; sources in docs/hla.md)

// kinematic viscosity [mm^2/s] at temp_C from two at 40 and 100 C: Walther's equation
// log10 log10(nu + 0.7) = A - B log10(T [K]) (ASTM D341)
double walther_viscosity(double nu40_mm2_per_s, double nu100_mm2_per_s, double temp_C);

// effective bulk modulus [MPa] of the oil with free air at gauge pressure p (docs/hla.md, eq. 2)
double hla_bulk_modulus(const Hla& hla, double p);
// volume of a fixed mass of the chamber's oil at p over its volume at 0 gauge [-] (eq. 1):
// beta_eff = -s / (ds/dp); the chamber's content at reference conditions is (V - void) / s
double hla_volume_ratio(const Hla& hla, double p);
// chamber volume [mm^3] at plunger extension z: V0 + A_p z
double hla_chamber_volume(const Hla& hla, double z);
// leak from the chamber through the annulus [mm^3/s] at dp = p - p_reservoir, plunger rate zdot
double hla_leak_flow(const Hla& hla, double dp, double zdot);
// orifice law Cd A sqrt(2 dp / rho) with its sign, laminar below transition_pressure [mm^3/s]
double hla_orifice_law(double cd_area, double dp, double density, double transition_pressure);
// check-valve flow area [mm^2] at ball lift h: min(pi d_seat h, pi d_seat^2 / 4)
double hla_valve_area(const Hla& hla, double h);
// force on the ball away from the seat [N]: (p_supply - p) A_seat - (preload + rate h) - c hdot
double hla_ball_force(const Hla& hla, double supply, double p, double h, double hdot);
// force of the HLA on the supported node along axis [N]: (p - p_reservoir) A_p + F_s(z)
double hla_force(const Hla& hla, double crank_deg, double p, double z);

// ---- the hydraulic state, its mode and rates

enum HlaIndex : int { kHlaPressure = 0, kHlaVoid, kHlaBallLift, kHlaBallVelocity, kHlaStates };

enum class HlaBall : std::uint8_t { seated, free, caged };

struct HlaMode {
  HlaBall ball = HlaBall::seated;
  bool cavitating = false;  // the pressure sits at the floor and the void volume moves
  bool ball_held = false;   // a rig's valve held at its lift (seated = shut): no ball dynamics
};

// the flows of one instant [mm^3/s]
struct HlaFlows {
  double leak = 0.0;     // chamber -> reservoir through the annulus (Poiseuille + Couette)
  double orifice = 0.0;  // chamber -> reservoir through the fixed orifice
  double refill = 0.0;   // supply -> chamber through the check valve
};

// d/dt of the hydraulic state (kHlaStates values) and, when flows is given, the flows
void hla_rates(const Hla& hla, double crank_deg, double z, double zdot, const double* x, const HlaMode& mode,
               double* rates, HlaFlows* flows = nullptr) noexcept;

// ---- events

// root functions: [0] pressure at the floor / void closing, [1] ball at the seat (leaving or
// landing), [2] ball at the cage; an inactive one is 1
constexpr int kHlaRoots = 3;
void hla_roots(const Hla& hla, double crank_deg, double z, double zdot, const double* x, const HlaMode& mode,
               double* g) noexcept;
// plunger travel: [0] z - travel_min, [1] travel_max - z (the coupling applies the stop)
void hla_travel_roots(const Hla& hla, double z, double* g) noexcept;

// what changed at an event (a bit set)
enum HlaEvent : std::uint32_t {
  kHlaCavitationStart = 1u << 0,
  kHlaCavitationEnd = 1u << 1,
  kHlaBallOpen = 1u << 2,     // left the seat
  kHlaBallSeat = 1u << 3,     // landed on the seat (impact)
  kHlaBallCage = 1u << 4,     // reached the cage (impact)
  kHlaBallLeaveCage = 1u << 5,
  kHlaBallBounce = 1u << 6,   // rebounded from a stop (restitution)
};
// the names of the bits set, "ball-open, cavitation-start"
std::string hla_event_names(std::uint32_t events);

// at a root: found[i] != 0 for each root function that crossed zero; the state is set onto
// the stop or the floor it reached and the mode follows the forces and rates there
std::uint32_t hla_on_root(const Hla& hla, double crank_deg, double z, double zdot, double* x, HlaMode& mode,
                          const int* found) noexcept;
// the mode consistent with a state (a run's start): the ball on a stop while the net force
// presses it there, cavitating when at the floor with a falling pressure
HlaMode hla_settle_mode(const Hla& hla, double crank_deg, double z, double zdot, double* x, bool ball_held = false) noexcept;

// ---- the standalone rig

// the external force on the plunger pushing it into the body [N] (the tester's weight, the
// valvetrain's load), or a prescribed plunger motion
struct HlaRigLoad {
  double force_N = 0.0;                     // constant part
  std::vector<double> table_time_s, table_force_N;  // added: linear, periodic over period_s
  double period_s = 0.0;
  bool prescribed_motion = false;           // z(t) = z0 + velocity t + amplitude sin(2 pi f t)
  double velocity_mm_per_s = 0.0, amplitude_mm = 0.0, frequency_hz = 0.0;
  double rpm = 0.0;                         // crank angle = crank0 + 6 rpm t [deg] (supply table)
  double crank0_deg = 0.0;
};

struct HlaRigOptions {
  double duration_s = 1.0;
  double output_step_s = 1e-3;
  double z0_mm = 0.0, zdot0_mm_per_s = 0.0;
  double p0_MPa = 0.0;
  // start at the pressure that balances the load at z0 and, under a force, at the plunger speed
  // the chamber's net outflow allows (zdot0_mm_per_s is then not used)
  bool p0_equilibrium = true;
  double ball_lift0_mm = 0.0;
  bool ball_held = false;      // the valve held at ball_lift0_mm (0: shut)
  double stop_z_mm = -1e300;   // end the run when z falls to this (the leak-down travel's end)
  double relative_tolerance = 1e-10;
  long max_steps = 2000000;
};

struct HlaRigEvent {
  double time_s = 0.0;
  std::string name;  // hla_event_names, or "plunger-min", "plunger-max", "plunger-free", "stop"
  double pressure_MPa = 0.0, ball_lift_mm = 0.0, z_mm = 0.0;
};

// time series at every output step (and the run's last instant)
struct HlaRigResult {
  std::vector<double> time_s, z_mm, zdot_mm_per_s, pressure_MPa, void_mm3, ball_lift_mm, force_N, supply_MPa;
  std::vector<double> leak_mm3_per_s, orifice_mm3_per_s, refill_mm3_per_s;
  // cumulated flows [mm^3] and the same at reference conditions: int Q / s(p) dt (hla_volume_ratio)
  std::vector<double> leak_mm3, orifice_mm3, refill_mm3;
  std::vector<double> leak_ref_mm3, orifice_ref_mm3, refill_ref_mm3;
  std::vector<HlaRigEvent> events;
  double stop_time_s = -1.0;  // when z reached stop_z_mm (< 0: not reached)
  long steps = 0;
};

// integrates the plunger (mass, return spring, chamber force, external force, travel stops)
// and the hydraulics with CVODE (BDF); integrator failures are a Status naming the time
[[nodiscard]] Status run_hla_rig(const Hla& hla, const HlaRigLoad& load, const HlaRigOptions& options,
                                 HlaRigResult& out);

}  // namespace camopt::dynamics
