#pragma once
// mode (b): stiff but separable contacts, integrated in time with SUNDIALS CVODE (BDF,
// dense Newton) and root-finding events when a contact opens or closes.
//
// Model: small deviations dq of the free node coordinates from the kinematic path
// q_kin(theta), theta = omega t (a kineto-static reference; the deviations stay small
// against the radii of curvature, so gaps and gradients are linearised about the path):
//     M(theta) dq'' = -r(theta, omega) + sum_c F_c g_c - K_springs dq
// r the mode (a) load on each free coordinate (inertia of the kinematic motion minus the
// applied forces), so with dq constant and F_c = lambda_c the kinematic motion is exact.
// Contact c: penetration delta = -(gap_kin + g_n . dq), force
//     F = max(0, k delta + c_d delta')  while delta > 0, else 0
// with the line-contact stiffness linearised at a reference load F_ref (Johnson, Contact
// Mechanics, 1985, sec. 5.? approach of two cylinders: delta = (P / (pi E*)) (2 ln(4 R*/b) - 1),
// P = F/L) -> k = pi L E* / (2 ln(4 R*/b_ref) - 1), and damping c_d = 2 zeta sqrt(k m_c), m_c
// the effective mass at the contact. A follower held behind a lash gap sits on a compliant
// seat of the same stiffness. Links and gears are bilateral springs of link_stiffness.
// Events: a root function per contact (and seat) penetration; at each root CVODE restarts.
// The kinematic path (loads, gradients, gaps, mass matrix) is tabulated once by a monotone
// sweep (the kinematic solver's warm starts need a monotone driver) and interpolated with
// Catmull-Rom cubics, so the integrator may step back and forth in time freely.
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::dynamics {

struct CompliantOptions {
  double stiffness_scale = 1.0;  // multiplies every contact stiffness (convergence studies)
  double damping_ratio = 0.05;   // contact damping when the design gives none [-]
  double link_stiffness = 1e5;   // links [N/mm], gears [N mm/rad] (bilateral)
  double reference_force = 0.0;  // F_ref for the stiffness [N]; 0: 500 N
  double table_step_deg = 0.25;  // the kinematic path is tabulated on this cam-angle grid by a
                                 // monotone sweep, then interpolated (Catmull-Rom) [deg]
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 1e-8;  // on deviations [mm or rad]; rates: x 1e4 [per s]
  long max_steps = 200000;

  // one rule per option: throws InputError naming the option, its value and the rule
  void validate() const;
};

struct ContactEvent {
  double time_s = 0.0, cam_deg = 0.0;
  std::string contact;  // connection name, or "<node> seat"
  bool opens = false;   // true: the contact separates; false: it closes (impact)
};

struct CompliantResult {
  std::vector<double> cam_deg;      // output points [driver deg]
  int connections = 0, rows = 0;
  std::vector<double> force;        // [point * connections + c] [N] (gear: N mm)
  std::vector<double> deviation;    // [point * rows + r] dq [mm or rad]
  std::vector<double> stiffness;    // per connection [N/mm]
  std::vector<ContactEvent> events;
  long steps = 0, rhs_evaluations = 0;
};

// integrate from start_deg to stop_deg (driver), output every step_deg, at one engine
// speed [rpm] and control position. The state starts at the quasi-static deflection.
// An integrator failure returns StatusCode::integrator_failure naming the time, cam angle
// and state (and the message of an exception caught in a CVODE callback); bad arguments
// (step_deg <= 0, stop_deg <= start_deg, rpm <= 0), bad options (CompliantOptions::validate)
// and bad data (a contact without materials / width) throw InputError.
Status run_compliant(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                     double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                     const CompliantOptions& options, CompliantResult& out);

}  // namespace camopt::dynamics
