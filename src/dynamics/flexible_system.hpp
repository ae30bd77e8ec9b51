#pragma once
// the flexible model's internals (flexible.hpp, docs/dynamics.md "Flexible model"): the
// extended coordinates, the kinematic path tabulated in smooth pieces between lash kinks, the
// one-sided force laws of contacts and valve seats, and the structured matrices (a dense core
// plus one tridiagonal band per spring chain) that keep the Newton system linear in the
// number of spring masses.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/hla.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::dynamics::detail {

// a compliant node: near end (its mode (a) row) and far end joined by a spring-damper
struct Element {
  int node = -1, near = -1, far = -1;
  double k = 0.0, c = 0.0;  // [N/mm, N s/mm] or [N mm/rad, N mm s/rad]
  bool damping_given = false;  // c from the design's damper key (else Rayleigh from the ratio)
  double zeta = 0.05;
};

// a compression spring as N + 1 equal segments with N internal masses (N may be 0)
struct Chain {
  std::string name;
  Spring law;                    // whole-spring load law
  int node = -1, row = -1;       // the node and its extended row (the spring's top end)
  int masses = 0, first = -1;    // internal masses: extended rows first .. first + masses - 1 (bottom first)
  double mass = 0.0;             // each internal mass, generalized [N per mm/s^2]
  double segment_damping = 0.0;  // [N s/mm] on the whole-spring travel rate ((N + 1) x a segment's)
  double spring_damping = 0.0;   // the design's viscous damping between the ends [N s/mm]
  double coil_damping = 0.0;     // coil-to-coil part of segment_damping [N s/mm, whole-spring]
  double solid_travel = -1.0;    // node travel at which the coils touch [mm]; < 0: unknown
  int table_index = -1;          // position in the path table
  int band = -1;                 // its band in the structured matrices (masses > 0)
};

// a hydraulic lash adjuster, under a rotational node's pivot: the pivot (and the node with it)
// moves by the plunger coordinate z along the axis; or in series on a translational node: the
// node's contact side (bucket, insert) moves by z along the axis from its valve side. The
// plunger's force, its travel stops and the hydraulic states are the HLA element's (hla.hpp)
struct Plunger {
  int hla = -1;                     // Model::hlas
  int node = -1, row = -1;          // the supported node and its free row (near end)
  int coord = -1;                   // z: its extended core coordinate [mm]
  int table_index = -1;             // its columns in the path table
  Eigen::Vector2d axis{0.0, 1.0};   // unit, the plunger's extension
  Eigen::Vector2d pivot{0.0, 0.0};  // the node's pivot in the drawing [mm]
  double mass = 0.0;                // z's own: plunger + node, or the series body [N per mm/s^2]
  bool series = false;              // in series on a translational node
  double along = 0.0;               // in series: axis . the node's direction (+-1)
  int far = -1;                     // the node's far end (compliant node), else -1
  std::vector<char> touches;        // per connection: on the node
  int first_state = -1;             // its hydraulic states in the state vector after q and q'
};

// one-sided force law of a contact or a valve seat (docs/dynamics.md, "Contact laws")
struct ForceLaw {
  ContactLaw law = ContactLaw::hertz;
  ContactDampingLaw damping_law = ContactDampingLaw::hunt_crossley;
  double k = 0.0;      // linear law [N/mm]
  double c = 0.0;      // linear damping [N s/mm]
  double alpha = 0.0;  // hunt-crossley [s/mm]
  double length = 0.0, e_star = 0.0;  // hertz line contact [mm], [N/mm^2]
  double scale = 1.0;  // contact_stiffness_scale (hertz)
  bool two_sided = false;  // a roller in a slot: the other wall at -penetration pushes back
  struct Value {
    double force = 0.0, elastic = 0.0;  // [N]
    double d_pen = 0.0, d_rate = 0.0;   // dF/d(penetration) [N/mm], dF/d(rate) [N s/mm]
    double elastic_tangent = 0.0;       // dF_elastic/d(penetration) [N/mm]
    double unclamped = 0.0;             // the law before max(0, .): < 0 while the bodies part [N]
  };
  // force at penetration pen [mm] and its rate [mm/s]; radius: hertz reduced radius [mm];
  // start: the hertz Newton's warm start (load length)
  Value evaluate(double pen, double rate, double radius, double& start) const;
  // elastic energy stored at a penetration [N mm]
  double energy(double pen, double radius, double& start) const;
  // the damping coefficient dF/d(rate) at a load [N s/mm] (summaries)
  double damping_at(double force) const;
};

// a valve seat: a one-sided contact on a node's travel at its rest displacement
struct Seat {
  int node = -1, row = -1;   // the node and its extended row (the far end of a compliant valve)
  int source = -1;           // its entry in Model::seats
  int near = -1;             // the node's free row (kinematic rate)
  int table_index = -1;
  double sign = 1.0;         // +1: the valve opens towards + travel and the seat pushes +
  double cos_angle = 1.0;    // hertz law: normal approach = cos x axial approach
  double radius = 5.0;       // hertz law: crown radius [mm]
  double area = 0.0;         // face area pi d w [mm^2] (mean seat pressure)
  ForceLaw law;
  mutable double start = 0.0;
};

// the path table's columns (free rows R, connections C, chains S, seats V, plungers P)
struct Layout {
  int R = 0, C = 0, S = 0, V = 0, P = 0;
  int inertia = 0, gas = 0, other = 0, spring_k = 0, vel = 0, gn = 0, gt = 0, gap = 0, curv = 0, curv2 = 0, slide = 0,
      gn_drv = 0, gt_drv = 0, load_drv = 0, mass = 0, xs = 0, xs1 = 0, seat = 0, out = 0, out1 = 0, out2 = 0,
      pz_gn = 0, pz_gt = 0, pz_inertia = 0, pz_mass = 0, size = 0;
  Layout() = default;
  Layout(int r, int c, int s, int v, int p);
};

// the kinematic path over one revolution, tabulated in pieces that are smooth: a lash
// contact that opens or closes kinks the path (the held follower starts or stops moving), so
// a piece ends at each such angle and is interpolated (Catmull-Rom) from its own points only
struct PathPiece {
  double a = 0.0, b = 0.0;   // [rad]
  int first = 0, count = 0;  // table rows first .. first + count - 1, evenly spaced over [a, b]
  bool periodic = false;     // the whole revolution, no kink
  double step() const { return periodic ? (b - a) / count : (b - a) / (count - 1); }
};

// a matrix on the extended coordinates: a dense core (free rows and far ends) and one
// tridiagonal band per spring chain with masses, coupled to the core at the chain's node row
struct Band {
  std::vector<double> diag, off;  // off[i]: entries (i, i + 1) and (i + 1, i); i = 0 the bottom mass
  double couple = 0.0;            // entries (top mass, node row) and (node row, top mass)
};
struct Structured {
  Eigen::MatrixXd core;
  std::vector<Band> bands;
  void resize(int core_size, const std::vector<Chain>& chains);
  void set_zero();
  void add(double s, const Structured& o);  // this += s o
  void copy_from(const Structured& o);
  // y = A x on the extended coordinates
  void multiply(const std::vector<Chain>& chains, const double* x, double* y) const;
  // out = a A x + b B y (one pass)
  static void multiply_add(const std::vector<Chain>& chains, double a, const Structured& ma, const double* x, double b,
                           const Structured& mb, const double* y, double* out);
  Eigen::MatrixXd dense(const std::vector<Chain>& chains, int n) const;
};
// LU of a Structured matrix: each chain's band (Thomas, bottom up) is eliminated into the
// core's node row, then the core is factored; O(n) in the number of spring masses
struct StructuredLU {
  const std::vector<Chain>* chains = nullptr;
  Structured a;
  std::vector<std::vector<double>> pivots, top_column;  // per band: eliminated diagonal, A_ss^-1 e_top
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  mutable Eigen::VectorXd work;
  bool factor(const std::vector<Chain>& c);  // factors `a`; false when singular or not finite
  void solve(double* x) const;               // in place, the extended coordinates
};

class System {
 public:
  System(const kin::Mechanism& me, const FlexibleOptions& o) : mech(me), opt(o) {}
  const kin::Mechanism& mech;
  const FlexibleOptions& opt;
  Model flex;  // the mode (a) model without the chained springs, spring end masses on the nodes
  int R = 0, C = 0, N = 0, E = 0, P = 0;  // free rows, connections, extended size, elements, plungers
  int core() const { return R + E + P; }
  std::vector<Element> elements;
  std::vector<Plunger> plungers;          // their coordinates follow the far ends
  int H = 0;                              // hydraulic states (after q and q' in the state vector)
  Eigen::VectorXd hyd;                    // the hydraulic state the forces use
  std::vector<HlaMode> hla_modes;         // per plunger: the ball's stop, cavitation
  bool pin_plungers = false;              // the static start: plungers held at z = 0 by a stiff spring
  std::vector<int> far_of_row;            // row -> far row (-1: rigid)
  std::vector<std::vector<int>> row_map;  // per connection: row -> extended row
  std::vector<Chain> chains;
  std::vector<Seat> seats;
  std::vector<ForceLaw> laws;             // per connection (contacts)
  std::vector<double> link_k, link_c;     // per connection (links, gears) [N/mm or N mm/rad], [.. s]
  std::vector<char> frozen;               // per connection: force held at frozen_force (modes)
  std::vector<double> frozen_force;
  std::vector<int> lash;                  // connections with lash (the path's kinks)
  int output_row = -1;
  bool output_angle = false;
  double train_frequency_hz = 0.0;

  // the path table
  Layout L;
  std::vector<double> table, path, row_angle;
  std::vector<PathPiece> pieces;
  std::vector<double> kinks;              // [rad] piece starts (empty: one periodic piece)
  int active_piece = 0;
  std::vector<double> gap_slope;          // per connection: d gap / d theta at evaluated_theta
  double evaluated_theta = std::nan("");

  double omega = 0.0, theta0 = 0.0;       // cam speed [rad/s], angle at t = 0 [rad]
  Structured m;                           // extended mass (angle-dependent core)
  Eigen::PartialPivLU<Eigen::MatrixXd> core_mass_lu;  // the core's block; the coil masses are diagonal
  Eigen::VectorXd inv_coil_mass;          // per coil mass row (after the core) [1 / (N per mm/s^2)]
  double factored_theta = std::nan("");
  // generalized forces and what derives from them at one state
  struct Forces {
    Eigen::VectorXd f;
    std::vector<double> connection, mu_eff, friction_power;  // per connection [N], [-], [N mm/s]
    std::vector<double> seat;                                 // per seat [N]
    double torque = 0.0;                                      // drive torque [N mm]
    double drive_power = 0.0, gas_power = 0.0, viscous_power = 0.0, friction_total = 0.0;  // [N mm/s]
    double hla_power = 0.0;  // the HLAs' force (chamber, spring, stops) on their plungers [N mm/s]
    double path_spring_power = 0.0;  // the springs left in the path (torsion, on floating bodies) [N mm/s]
    std::vector<double> coil_top, coil_base, static_load;     // per chain [N]
  } fr;
  Eigen::VectorXd acc;  // the last accelerations [per s^2]
  Structured jk, jd;  // Newton matrices K = -df/dq, D = -df/dqd
  long rhs_calls = 0, jacobian_calls = 0;
  mutable std::vector<double> hertz_start;
  std::string callback_error;  // an exception caught in a CVODE callback: "<callback>: <what>"

  // root functions: contacts' penetration, seats' penetration, coil gaps
  struct Root {
    int kind;  // 0 contact, 1 seat, 2 coil, 3 an HLA's root (segment: which of its roots)
    int index, segment;
  };
  std::vector<Root> root_list;

  // ---- the path (flexible_path.cpp) ----
  void evaluate(double t) { evaluate_angle(theta0 + omega * t); }
  void evaluate_angle(double theta);
  // the piece holding theta (the active one when theta is inside it or at its ends)
  int piece_of(double theta) const;
  // kinematic rate [per s] of extended row e on the active piece at its end (side 1) or start (side 0)
  double piece_end_rate(int piece, int side, int e) const;

  // ---- quantities along the path (valid after evaluate) ----
  double gn(int r, int c) const { return path[L.gn + r + R * c]; }
  double gt(int r, int c) const { return path[L.gt + r + R * c]; }
  // connection c's gap gradient on every extended row it acts on: f(row, g_n, g_t), the
  // node rows (or their far ends) and the plungers under its nodes
  template <class F>
  void for_gradient(int c, F&& f) const {
    for (int r = 0; r < R; ++r) f(row_map[c][r], gn(r, c), gt(r, c));
    for (const Plunger& p : plungers)
      if (p.touches[c]) f(p.coord, path[L.pz_gn + p.table_index * C + c], path[L.pz_gt + p.table_index * C + c]);
  }
  double reduced_radius(int c) const {
    const double k = path[L.curv + c];
    return k > 1e-6 ? 1.0 / k : 1e6;  // flat on flat: a long cylinder
  }
  double normal_dot(int c, const double* q) const {
    double s = 0.0;
    for_gradient(c, [&](int row, double g, double) { s += g * q[row]; });
    return s;
  }
  double tangent_dot(int c, const double* q) const {
    double s = 0.0;
    for_gradient(c, [&](int row, double, double g) { s += g * q[row]; });
    return s;
  }
  double penetration(int c, const double* q) const { return -(path[L.gap + c] + normal_dot(c, q)); }
  double penetration_rate(int c, const double* qd) const { return -(gap_slope[c] * omega + normal_dot(c, qd)); }
  // seat: axial penetration (travel below the rest displacement) and its rate
  double seat_penetration(const Seat& s, const double* q) const {
    return -s.sign * (path[L.seat + s.table_index] + q[s.row]);
  }
  double seat_rate(const Seat& s, const double* qd) const {
    return -s.sign * (path[L.vel + s.near] * omega + qd[s.row]);
  }
  ForceLaw::Value seat_force(const Seat& s, double pen, double rate) const;  // axial [N]
  double chain_x(const Chain& ch, const double* q) const { return path[L.xs + ch.table_index] + q[ch.row]; }
  double chain_v(const Chain& ch, const double* qd) const { return path[L.xs1 + ch.table_index] * omega + qd[ch.row]; }
  double chain_u(const Chain& ch, int j, const double* q) const {  // j = 0 .. masses + 1
    return j == 0 ? 0.0 : j == ch.masses + 1 ? chain_x(ch, q) : q[ch.first + j - 1];
  }
  double chain_ud(const Chain& ch, int j, const double* qd) const {
    return j == 0 ? 0.0 : j == ch.masses + 1 ? chain_v(ch, qd) : qd[ch.first + j - 1];
  }
  // kinematic velocity of an extended row [per s]
  double kinematic_rate(int e) const {
    if (e < R) return path[L.vel + e] * omega;
    if (e < R + E) return path[L.vel + elements[e - R].near] * omega;
    return 0.0;  // plungers: at rest on the path; chain masses are absolute
  }

  // ---- forces and matrices (flexible_forces.cpp) ----
  // the generalized forces and powers at (q, qd); powers_only: the work integrals' powers
  // alone (the coil masses' forces are left out)
  void forces(const double* q, const double* qd, bool powers_only = false);
  void chain_forces(std::size_t chain, const double* q, const double* qd, bool powers_only);
  // K = -df/dq and D = -df/d(dq/dt) at (q, qd); statics: the tangent stiffness alone (no
  // rate terms, friction left out) for Newton statics and the modes
  void newton_matrices(const double* q, const double* qd, Structured& k, Structured& d, bool statics = false) const;
  void mass_matrix(Structured& out) const;
  void factor_mass();
  void accelerations(const double* q, const double* qd);
  // kinetic (true motion) + elastic [N mm], after accelerations at the same angle
  double energy(const double* q, const double* qd) const;
  // the largest error of a loaded contact's linearised gap (after forces) [mm], and its
  // contact: sliding s from the kinematic contact point leaves out s^2 / (2 (R_a + R_b))
  double gap_error(const double* q, int& contact) const;
  std::string gap_error_message(double error, int contact) const;
  // contacts and seats: min(penetration, unclamped force), > 0 exactly while the pair carries
  // a force (it closes when the penetration or the force becomes positive, opens when the
  // force falls to zero); coils: the coil overlap
  double root_value(const Root& rt, const double* q, const double* qd) const;
  std::string root_name(const Root& rt) const;
};

// ---- the hydraulic lash adjusters (flexible_hla.cpp) ----
// a plunger coordinate for every HLA of the model, after the far ends (s.R, s.E set; before
// the chains); its hydraulic states counted in s.H. InputError for an HLA the flexible model
// cannot place (neither under a rotational node's fixed pivot nor in series on a solved
// translational node along its direction, a link on the node)
void add_plungers(System& s, const Model& model);
// the plunger's force on z at (q, qd) and the current hydraulic state s.hyd: the chamber and
// the return spring, and the travel stops [N]; its -d/dz and -d/dz' for the Newton matrices
double plunger_force(const System& s, const Plunger& p, const double* q, const double* qd);
double plunger_stiffness(const System& s, const Plunger& p, const double* q);
double plunger_damping(const System& s, const Plunger& p, const double* q);
// the hydraulic states at the start (supply pressure, ball on its seat), and the HLAs' modes
// consistent with a state (the ball on its seat while the net force presses it there)
void initial_hydraulics(const System& s, double t, double* h);
void settle_hydraulics(System& s, double t, const double* q, const double* qd, double* h);
// after a static balance with the plungers pinned: each chamber's pressure set to carry its
// pivot's load at z = 0 (at least the gallery's: a lighter load lets the check valve refill
// and the plunger extend; the gallery's for a series HLA on a seated valve, whose load the
// seat shares), the plungers put at 0 and released
void hold_pivot_loads(System& s, Eigen::VectorXd& x);
// CVODE's absolute tolerance of hydraulic state i
double hydraulic_tolerance(const System& s, int i);
// the chamber stiffness A^2 beta / V plus the return spring at the current state [N/mm]
// (the train's first mode, the damping reference)
double hla_static_stiffness(const System& s, const Plunger& p);
// what a run reports of one HLA at a state
struct HlaPoint {
  double plunger_mm = 0.0, force_N = 0.0, pressure_MPa = 0.0, ball_lift_mm = 0.0;
  double leak_mm3_per_s = 0.0, refill_mm3_per_s = 0.0;
  double volume_ratio = 1.0;  // the chamber oil's volume over its volume at 0 gauge (hla_volume_ratio)
};
HlaPoint hla_point(const System& s, const Plunger& p, double t, const double* q, const double* qd, const double* h);
// d/dt of the hydraulic states at time t, (q, qd) and h; false when not finite
bool hydraulic_rates(const System& s, double t, const double* q, const double* qd, const double* h, double* hdot);
// the HLA roots (ball on its seat and cage, cavitation, plunger stops): their count, values
// and names, and the update of the HLA's discrete state at one found root
void add_hla_roots(System& s);
double hla_root_value(const System& s, const System::Root& rt, double t, const double* q, const double* qd,
                      const double* h);
std::string hla_root_name(const System& s, const System::Root& rt);
// found: plunger's kHlaRoots flags (CVodeGetRootInfo's); returns the HlaEvent bits
std::uint32_t on_hla_roots(System& s, int plunger, const int* found, double t, const double* q, const double* qd,
                           double* h);

// ---- the path (flexible_path.cpp) ----
// tabulate one revolution from theta_first [rad] in smooth pieces (s.L, s.lash set): a
// uniform sweep finds where a lash contact opens or closes, bisection puts each such kink to
// round-off, and every piece is tabulated between its kinks
Status tabulate_path(System& s, const std::vector<double>& controls, double theta_first);

// ---- the build (flexible_build.cpp) ----
// build the extended model at cam angle theta_first [rad] (s.omega set), tabulate the path and
// set stiffness and damping; throws InputError for bad data
Status build_system(System& s, const Model& model, const std::vector<double>& controls, double theta_first);
// the static start: every connection at its mode (a) force, then Newton-polished on the full
// nonlinear balance; chain masses moving with the kinematic spring compression
Status static_start(System& s, const Model& model, const std::vector<double>& controls, double theta,
                    Eigen::VectorXd& x0, Eigen::VectorXd& v0);
// Newton on the static balance f(x, v) = 0 in x with the tangent stiffness; returns the
// residual norm reached
double polish_static(System& s, Eigen::VectorXd& x, const Eigen::VectorXd& v, int iterations);

// ---- the CVODE run (flexible_run.cpp) ----
// integrate from (x0, v0) at cam angle first_deg [deg] at engine speed rpm, window by window,
// reporting start_deg .. stop_deg every step_deg (FlexibleOptions::revolutions, start_at_rest)
Status integrate_flexible(System& s, double first_deg, double rpm, const Eigen::VectorXd& x0,
                          const Eigen::VectorXd& v0, double start_deg, double stop_deg, double step_deg,
                          FlexibleResult& out);

// ---- CVODE's Newton system (flexible_linear.cpp) ----
// a SUNMatrix holding J = [[0, I], [-M^-1 K, -M^-1 D]] as beta I + alpha J with structured K,
// D and M, and the direct solver of beta I + alpha J through its Schur complement
// (beta^2 M - alpha beta D + alpha^2 K) x_v = beta M b_v + alpha K b_q
struct NewtonMatrix {
  const std::vector<Chain>* chains = nullptr;
  int n = 0;  // extended coordinates (the state has 2n)
  Structured k, d, m;
  double alpha = 0.0, beta = 0.0;
};
}  // namespace camopt::dynamics::detail

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

namespace camopt::dynamics::detail {
SUNMatrix make_newton_matrix(SUNContext ctx, const System& s);
NewtonMatrix& newton_content(SUNMatrix a);
SUNLinearSolver make_newton_solver(SUNContext ctx, const System& s);
}  // namespace camopt::dynamics::detail
