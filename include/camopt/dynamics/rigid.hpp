#pragma once
// mode (a): kinematically constrained (quasi-static + inertia) rigid dynamics. The motion
// comes from the kinematic solver at constant cam speed omega (d/dt = omega d/dtheta);
// every connection force is a Lagrange multiplier of
//     M q'' + Phi_q^T lambda = Q
// written in the node variables q (the surface parameters of contacts drop out by the
// envelope theorem): for each free node variable i
//     sum_c lambda_c g_ci = sum_bodies (m a_cg . d cg/dq_i + I alpha d phi/dq_i) - Q_i
// with g_c the gradient of connection c's separation function: a contact's gap (normal
// force, + compressive, with Coulomb friction mu sign(sliding) along the tangent), a
// link's length (+ compressive), a gear's phi_b - ratio phi_a (torque on b [N mm]).
// (Haug, Computer-Aided Kinematics and Dynamics of Mechanical Systems, 1989, ch. 6:
// inverse dynamics of kinematically driven systems.)
//
// Every force is linear in the load cases, so each output is kept split by case:
//   case 0: inertia, per (rad/s)^2 of cam speed;  case 1: gas force;  case 2 + s: spring s
// and a quantity at cam speed omega is q = q_0 omega^2 + sum_{j>=1} q_j (exact rpm^2
// scaling; friction keeps its sign with speed).
#include <Eigen/Core>
#include <Eigen/LU>
#include <limits>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::dynamics {

// cam speed [rad/s] at an engine speed [rpm, crankshaft]
double cam_speed_rad_per_s(double engine_rpm, double crank_per_cam);
// engine speed [rpm] at a cam speed [rad/s]
double engine_rpm(double cam_rad_per_s, double crank_per_cam);

class RigidWorkspace {
 public:
  RigidWorkspace(const kin::Mechanism& mech, const Model& model);
  // load cases (columns of force, torque, reaction, loads): 0 inertia (per (rad/s)^2), 1 gas,
  // 2 .. 2 + springs - 1 the springs, damping_case() the springs' viscous dampers (per rad/s)
  int cases() const { return cases_; }
  int damping_case() const { return cases_ - 1; }
  // the weight of case j at cam speed omega [rad/s]: omega^2, 1 or omega
  double case_weight(int j, double omega) const { return j == 0 ? omega * omega : j == cases_ - 1 ? omega : 1.0; }

  kin::Workspace kin;  // the kinematic solve (controls set by the caller)

  // results of the last solve_rigid, split by load case (columns)
  Eigen::MatrixXd force;     // per connection: normal / link force [N], gear torque [N mm]
  Eigen::RowVectorXd torque; // driver torque [N mm], the torque the drive applies
  Eigen::MatrixXd reaction;  // per node, rows 2n, 2n+1: pivot (rotational) or guide
                             // (translational) reaction on the body, global x, y [N]
  Eigen::VectorXd spring_load;  // per spring [N or N mm]
  double gas_force = 0.0;       // [N]
  Eigen::MatrixXd seat;         // per connection: seat reaction of the held node while its
                                // lash gap is open (generalized, on the held variable)
  Eigen::MatrixXd mass;         // free rows x free rows: generalized mass [N per (mm or rad)/s^2]
  Eigen::MatrixXd spring_stiffness;  // free rows x free rows: d(spring loads)/dq [N/mm, N mm/rad]
  Eigen::MatrixXd g_normal;     // node variables x connections: gradient of a contact's gap
  Eigen::MatrixXd g_tangent;    // the same along the tangent z x n (friction)
  std::vector<double> slide_sign;  // per contact: sign of the sliding speed (friction direction)

  // ---- internals ----
  Eigen::MatrixXd g;        // node variables x connections: d(separation)/dq
  Eigen::MatrixXd loads;    // variables x cases: inertia minus applied generalized force
  Eigen::MatrixXd system;   // free rows x connections
  Eigen::MatrixXd rhs;      // free rows x cases
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  Eigen::MatrixXd inverse;  // free rows x free rows: the balance's inverse (its condition)
  std::vector<Eigen::Vector2d> cg_acc;  // per node: d2 cg / dtheta2 [mm/rad^2]
  std::vector<double> phi_acc;          // per node: d2 phi / dtheta2 [-]
  std::vector<Eigen::Vector2d> cg_pos;  // per node: current cg [mm]
  std::vector<Eigen::Vector2d> on_b;    // per connection: force on body b per unit force (a gets -)

 private:
  int cases_ = 0;
};

// one driver angle [rad]: kinematics (order 2, contacts) then the force balance. A failed
// kinematic solve or a singular balance (a toggle) returns a Status naming the angle.
Status solve_rigid(const kin::Mechanism& mech, const Model& model, RigidWorkspace& ws, double driver_rad);

// d p / d q of a point p [mm] fixed to node n, for each of its variables (1 or 3);
// returns the number written. Rotational: z x (p - pivot); translational: direction;
// floating: e_x, e_y, z x (p - reference point).
int point_partials(const kin::Mechanism& mech, const kin::Workspace& kws, int node, const Eigen::Vector2d& p,
                   Eigen::Vector2d* out);

// a cam-angle sweep at one control position, every quantity split by load case
struct RigidSweep {
  std::vector<double> controls;
  std::vector<double> cam_deg;  // driver [deg]
  int cases = 0, connections = 0, nodes = 0, springs = 0, variables = 0;  // the last case: dampers, per rad/s
  std::vector<double> force;     // [(point * connections + c) * cases + j]
  std::vector<double> torque;    // [point * cases + j] [N mm]
  std::vector<double> reaction;  // [((point * nodes + n) * 2 + axis) * cases + j] [N]
  std::vector<kin::ContactState> contact;  // [point * connections + c]
  std::vector<double> spring_load;  // [point * springs + s] [N or N mm]
  std::vector<double> gas_force;    // [point] [N]
  std::vector<double> output;       // output node displacement from rest [mm or deg]
  std::vector<double> loads;        // [(point * variables + v) * cases + j]: inertia minus applied [N or N mm]

  std::size_t points() const { return cam_deg.size(); }
  // a split quantity at cam speed omega [rad/s]
  double at(const double* split, double omega) const {
    double v = split[0] * omega * omega + split[cases - 1] * omega;
    for (int j = 1; j + 1 < cases; ++j) v += split[j];
    return v;
  }
  double force_at(std::size_t point, int c, double omega) const {
    return at(&force[(point * connections + c) * cases], omega);
  }
  double torque_at(std::size_t point, double omega) const { return at(&torque[point * cases], omega); }
  double reaction_at(std::size_t point, int node, int axis, double omega) const {
    return at(&reaction[((point * nodes + node) * 2 + axis) * cases], omega);
  }
};

// sweep start..stop [driver deg] by step (both ends included) at one control position
Status rigid_sweep(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                   double start_deg, double stop_deg, double step_deg, RigidSweep& out);

// separation speed of contact c: the lowest engine speed [rpm] at which its normal force
// first reaches zero, exact from F = A(theta) + B(theta) omega^2 (A: springs and gas, at
// their crank-angle values; B: inertia). 0 when the force is already < 0 at rest (or
// unloaded at rest and pulled apart by inertia); +inf
// when it never reaches zero. Points where a lash gap is open are skipped.
struct Separation {
  double engine_rpm = std::numeric_limits<double>::infinity();
  double cam_deg = 0.0;  // where it happens first
};
Separation separation_speed(const RigidSweep& sweep, const Model& model, int connection);

// the separation speed between the grid points: the grid's least (separation_speed) refined
// on the two intervals beside its point by Brent's minimisation of the point separation
// speed w(theta) (F(theta, w) = 0, from a mode (a) solve at each trial angle), so that
// neither the speed nor its angle depends on the step. The grid's result where the least is
// 0 or +inf, or at a point beside an open lash gap. A failed solve returns its Status.
Status refined_separation_speed(const kin::Mechanism& mech, const Model& model, const RigidSweep& sweep,
                                int connection, Separation& out);

// spring margin of spring s at a point: the part of its load that could be removed
// before the first contact it loads opens,
//     margin = load_s * min_c (F_c / F_c^(s))   over closed contacts with F_c^(s) > 0,
// F_c the contact force at omega and F_c^(s) the part of it due to spring s (= load_s when
// the spring loads no contact there). margin / load_s < 0: a contact is already open;
// the load the spring needs is load_s - margin.
double spring_margin(const RigidSweep& sweep, const Model& model, std::size_t point, int spring, double omega);

}  // namespace camopt::dynamics
