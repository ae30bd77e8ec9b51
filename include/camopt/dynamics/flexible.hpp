#pragma once
// flexible lumped-parameter valvetrain dynamics: component compliance, one-sided contacts
// with lash (Hertz line contact or a linear spring-damper), damping and regularised Coulomb
// friction, a seat under every valve and multi-mass valve springs (surge, coil clash),
// integrated over several cam revolutions with SUNDIALS CVODE (BDF) and root-finding.
//
// Generic scheme (docs/dynamics.md "Flexible model"): the state is the deviation dq of every
// free node coordinate from the kinematic path, extended by
//  - a far-end coordinate per compliant node (rotational `torsional_stiffness_Nm_per_rad`,
//    translational `axial_stiffness_N_per_mm`): the body becomes two halves of its
//    generalized mass joined by a spring-damper. The near end keeps the connections that
//    solve the node in the kinematic plan (its drive side) and its springs; the far end
//    takes every later connection (the driven side), the seat and the gas force;
//  - the absolute displacements of the internal masses of every compression spring with
//    `surge_masses` N > 0 (N + 1 equal segments, the spring's load law per segment).
// The kinematic path is smooth between the angles where a lash contact opens or closes; at
// each of them the deviation's rate jumps by minus the path's, so the bodies' velocities are
// continuous (the follower starts from rest when the lash closes).
// Contact c: penetration delta = -(gap_kin + g_c . dq), force F = max(0, law(delta, delta')).
#include <functional>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::dynamics {

struct FlexibleOptions {
  int revolutions = 3;                 // cam revolutions integrated; the last is reported
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 1e-7;    // deviations [mm or rad]; rates x 1e4 [per s]
  double contact_stiffness_scale = 1.0;  // multiplies every Hertz force (studies, rigid limit)
  // contacts and the valve seat: Hunt-Crossley damping (hertz.hpp) with this coefficient of
  // restitution at restitution_speed when the design gives no damping_N_s_per_mm (a design
  // damping c becomes alpha = c / (1.5 reference_force): the same dF/d(rate) at that load)
  double contact_restitution = 0.8;
  double restitution_speed_m_per_s = 0.5;
  double contact_damping_ratio = 0.05;   // links and gears (bilateral), of their local mode
  // compliant nodes without damping_ratio: stiffness-proportional (Rayleigh) damping
  // c = 2 zeta k / w1, w1 the first natural frequency of the train (train_frequency_hz)
  double component_damping_ratio = 0.05;
  double spring_damping_ratio = 0.01;    // first surge mode of a multi-mass spring
  double friction_velocity_m_per_s = 0.01;  // regularised Coulomb: mu v / sqrt(v^2 + v0^2)
  double link_stiffness = 1e5;         // links [N/mm], gears [N mm/rad] (bilateral)
  double coil_clash_stiffness = 1e4;   // whole spring once a coil gap closes [N/mm]
  double reference_force = 500.0;      // damping from the tangent stiffness at this load [N]
  double table_step_deg = 0.25;        // kinematic path tabulated on this grid (one revolution)
  long max_steps = 2000000;            // steps plus contact events over the whole run
  bool restart_at_events = true;       // CVodeReInit at every contact / seat / coil event
  bool analytic_jacobian = true;       // Newton matrix from K and D; false: CVODE's finite differences (dense)
  // start from rest: the valve on its seat and every body at rest at the first angle (the
  // engine starting at speed), and every revolution reported (start-up transients); false:
  // the static start moving with the kinematic path, the last revolution reported
  bool start_at_rest = false;
  bool coil_displacements = false;     // record the displacement of every coil mass
  // the contacts' geometry is linearised about the kinematic path: a loaded contact whose
  // bodies have slid s from it has its gap off by s^2 / (2 (R_a + R_b)); past this the run
  // stops (a floating body, or far past the separation speed) [mm]
  double max_gap_error_mm = 0.1;
  // periodic steady state: stop before `revolutions` once every state component at a
  // window's start repeats the previous window's within this many integration tolerances
  // (|dy| <= periodic_tolerance (rtol |y| + atol), CVODE's error weight); 0: never. The
  // integration's own revolution-to-revolution noise is ~20-130 of these (direct-acting valve)
  double periodic_tolerance = 1000.0;
  // asked between output points (outside CVODE's callbacks): true stops the run with
  // StatusCode::interrupted, nothing recorded (a caller's Ctrl-C); empty: never asked
  std::function<bool()> stop_requested;

  // one rule per option: throws InputError naming the option, its value and the rule
  void validate() const;
};

struct FlexibleEvent {
  double time_s = 0.0, cam_deg = 0.0;
  std::string what;    // connection name, "<node> seat" or "<spring> coil <j>"
  bool opens = false;  // contact separates / seat lifts / coil gap opens; false: closes
  double speed_m_per_s = 0.0;  // closing speed of the pair (seat: valve seating velocity)
};

// the extended coordinates: dq rows, far ends, spring masses
struct FlexibleLayout {
  int rows = 0;            // free node coordinates (mode (a) rows)
  int elements = 0;        // compliant nodes: far-end coordinates rows .. rows + elements
  int spring_masses = 0;   // internal spring masses after the plungers
  int plungers = 0;        // HLA plunger coordinates after the far ends
  int hydraulic_states = 0;  // first-order states after the coordinates and their rates
  int size() const { return rows + elements + plungers + spring_masses; }
};

// one model constant as used by a run: its key, value and unit, and whether the design gave it
struct FlexibleParameter {
  std::string key;    // e.g. "connection.cam_roller.law", "spring.valve_spring.coil_damping_ratio"
  std::string value;  // the number written shortest, or a name
  std::string unit;
  bool from_design = false;
};

struct FlexibleResult {
  FlexibleLayout layout;
  std::vector<FlexibleParameter> parameters;  // every law, stiffness and damping used
  std::vector<double> cam_deg;        // output points (last revolution) [driver deg]
  std::vector<double> lift_kinematic; // output node, kinematic [mm or deg]
  std::vector<double> lift;           // output node far end, dynamic [mm or deg]
  std::vector<double> velocity;       // its velocity [mm/s or deg/s]
  std::vector<double> acceleration;   // its acceleration [mm/s^2 or deg/s^2]
  int connections = 0;
  std::vector<double> force;          // [point * connections + c] [N] (gear: N mm)
  std::vector<double> friction_power; // [point * connections + c] [W]
  std::vector<double> seat_force;     // [point] [N] summed over the seats
  std::vector<std::string> seat_names;     // seated nodes
  std::vector<double> seat_forces;    // [point * seats + s] [N]
  std::vector<double> seat_area;      // per seat: face area [mm^2] (mean seat pressure)
  std::vector<double> cam_torque;     // [point] drive torque on the driver [N mm]
  std::vector<std::string> element_names;  // compliant nodes
  std::vector<double> deformation;    // [point * elements + e] far - near [mm or rad]
  std::vector<std::string> chain_names;    // springs with a segment chain
  std::vector<int> chain_segments;
  std::vector<double> coil_force_top, coil_force_base;  // [point * chains + s] [N]
  std::vector<double> spring_static_load;               // [point * chains + s] load at the node travel [N]
  std::vector<double> coil_displacement;  // [point * spring_masses + k] absolute [mm] (coil_displacements)
  // hydraulic lash adjusters (hla.hpp), [point * hlas + k]
  std::vector<std::string> hla_names;      // the nodes they support
  std::vector<double> hla_plunger;         // plunger extension from the drawing [mm]
  std::vector<double> hla_force;           // on the follower [N]
  std::vector<double> hla_pressure;        // high-pressure chamber [MPa]
  std::vector<double> hla_ball_lift;       // check-valve ball off its seat [mm]
  std::vector<double> hla_leak_flow;       // out of the chamber: clearance and orifice [mm^3/s]
  std::vector<double> hla_refill_flow;     // into it through the check valve [mm^3/s]
  // their integrals from t = 0 as oil at 0 gauge [mm^3]: the chamber's content
  // (V(z) - void) / hla_volume_ratio(p) changes by refill - leak
  std::vector<double> hla_leak_volume, hla_refill_volume;
  std::vector<double> hydraulic_state;     // [point * hydraulic states + i] (hla.hpp's layout)
  std::vector<double> state;          // [point * size + i] extended coordinates
  std::vector<double> initial_state;  // [2 * size]: coordinates then rates at t = 0
  // energy bookkeeping from t = 0 (quadratures), at the output points [N mm]
  // hla_work: the HLAs' force on their plungers (an input of the train, as the drive);
  // spring_work: the springs the energy leaves out (torsion springs, springs on floating bodies)
  std::vector<double> drive_work, gas_work, viscous_loss, friction_loss, hla_work, spring_work, energy;
  std::vector<FlexibleEvent> events;  // in the reported revolution (cam_deg within it)
  std::vector<double> contact_damping;  // per connection [N s/mm] (contacts: at reference_force)
  double train_frequency_hz = 0.0;      // first mode at peak lift, the component damping's reference
  double start_time_s = 0.0;          // time of the reported revolution's first point
  std::vector<double> kink_deg;       // where a lash contact opens or closes on the kinematic path [deg]
  double gap_error_mm = 0.0;          // largest linearised-gap error of a loaded contact at the output points
  double gap_error_at_cam_deg = 0.0;
  std::string gap_error_contact;
  long steps = 0, rhs_evaluations = 0;  // rhs includes the finite-difference Jacobian's
  long jacobian_evaluations = 0;
  int revolutions_integrated = 0;     // windows integrated (periodic: the last one is not recorded)
  bool periodic = false;              // stopped at a periodic steady state
  double periodic_difference = -1.0;  // last start-state difference [integration tolerances]; < 0: none
};

// integrate `options.revolutions` cam revolutions ending at stop_deg at one engine speed
// [rpm] and control position; report the last from start_deg to stop_deg every step_deg.
// An integrator failure returns StatusCode::integrator_failure naming the time, cam angle and
// state (and the message of an exception caught in a CVODE callback); bad arguments (step_deg
// <= 0, stop_deg <= start_deg, rpm <= 0), bad options (FlexibleOptions::validate) and bad data
// (a contact without materials / width, compliance on a floating node) throw InputError.
Status run_flexible(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                    double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                    const FlexibleOptions& options, FlexibleResult& out);

// natural frequencies [Hz] of the flexible model linearised about its static equilibrium at
// one cam angle (no speed): generalized eigenvalues of K x = w^2 M x, ascending. With
// release_driver_contacts the contacts touching the driver carry no stiffness (the cam force
// is the input, as in the handbook's multi-DOF models).
Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      std::vector<double>& frequencies_hz);

// the modes with their shapes and names: coordinates named "<node>" (a rigid node, or the near
// end of a compliant one), "<node>.far", "<node>.hla" (the plunger of an HLA under it), "<spring>.coil<j>" (j = 1 bottom .. N top)
struct FlexibleModes {
  std::vector<std::string> coordinates;
  std::vector<std::string> units;        // "mm" or "rad"
  std::vector<double> frequencies_hz;    // ascending
  std::vector<double> shapes;            // [mode * coordinates + i], mass-normalised, largest entry positive
  std::vector<double> static_state;      // the static equilibrium the modes are about
};
Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      FlexibleModes& out);

// every law, stiffness and damping the flexible model would use for this design (validate,
// summaries); throws InputError for bad data
std::vector<FlexibleParameter> flexible_parameters(const kin::Mechanism& mech, const Model& model,
                                                   const std::vector<double>& controls, const FlexibleOptions& options);

// the model at one cam angle, engine speed and state: generalized forces f(q, dq/dt) on the
// extended rows and the Newton matrices K = -df/dq, D = -df/d(dq/dt) that CVODE's Newton
// iteration uses (row-major size x size). q, qd: deviations and their rates [mm or rad, per s]
// in the extended coordinates; empty: run_flexible's static start. For the finite-difference
// check of the Jacobian (tests) and local studies.
struct FlexibleLinearisation {
  FlexibleLayout layout;
  std::vector<double> q, qd;       // the state used
  std::vector<double> force;       // [N or N mm]
  std::vector<double> stiffness;   // [i * size + j]
  std::vector<double> damping;
};
Status flexible_linearise(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                          double engine_rpm_value, double cam_deg, const FlexibleOptions& options,
                          const std::vector<double>& q, const std::vector<double>& qd, FlexibleLinearisation& out);

}  // namespace camopt::dynamics
