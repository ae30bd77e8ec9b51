#pragma once
// the valve lift of a swing-cam variable valve lift (VVA) mechanism as a function of the
// swing cam's own profile, at every control position at once.
//
// design variable: the swing cam's pitch curve (the path of the follower roller centre in
// the swing-cam frame), polar about the swing-cam pivot:
//   rho(s) = rho_0 + h(s),   s = sigma * (polar angle from the rest contact) [rad]
// rho_0: the dwell (idle) arc through the roller centre of the drawing; h = 0 for s <= s_a
// (dwell), a clamped b-spline of degree p on [s_a, s_b] beyond; its first 4 coefficients are
// zero (h, h', h'', h''' = 0 at s_a: the working curve joins the dwell c3, so the valve
// acceleration and jerk are continuous). sigma: the side the roller runs onto while opening.
//
// at cam angle theta and control position k: the upstream part (driver -> swing cam,
// synthesis::MechanismCut) gives the swing angle psi(theta) and the pivot P_s, independent
// of the profile: solved once per position and grid angle. the follower (finger, rotational)
// angle q then solves the contact closure
//   G(q, theta) = |p| - rho(s(p)) = 0,   p = R(-psi) (F(q) - P_s),  F: roller centre
// by newton; its taylor coefficients in theta follow order by order, q_k = -G_k / G_q
// (implicit differentiation, as kin::solve does). the valve follows the finger through a
// circle (pad) on a line (valve tip): L(q) = (n . (C(q) - P_0) - r_pad) / (n . d), exact to
// every order. sensitivity to the coefficients: G(q(theta; c), theta; c) = 0 for every theta
// gives dq/dc_j (theta) = N_j(s(theta)) / G_q(theta) as a function of theta, so
//   d/dc_j d^k L / dtheta^k = d^k/dtheta^k [ L_q(q(theta)) N_j(s(theta)) / G_q(theta) ]
// in closed form (jets), k = 0..3. the lift is the valve coordinate of the kinematic solver
// (kin::solve on the full design gives the same to 1e-9 mm on the bundled CVVL, whose
// pad/valve lash it does not subtract there).
#include <Eigen/Core>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"

namespace camopt::opt {

struct SwingProfileSpec {
  double start_deg = 1.0;   // s_a: working curve starts this far past the rest contact [swing deg]
  double end_deg = 0.0;     // s_b [swing deg]; 0: 3 deg past the farthest contact of the design's own profile
  int coefficients = 20;    // b-spline coefficients of h, the 4 zero ones at s_a included
  int degree = 5;           // 4..7 (the sensitivity of the jerk needs the 4th derivative of h)
  std::vector<double> positions;  // positions of the design's first control [deg or mm] (empty: 17 over its range)
};

// InputError naming the field (swing_profile.*), the value and the rule
void validate(const SwingProfileSpec& spec);

// the swing cam's pitch curve at the contact, straight from rho(s) (well conditioned where
// the swing reverses and an envelope of the follower motion would divide 0 by 0):
//   kappa = (rho^2 + 2 rho_phi^2 - rho rho_phiphi) / (rho^2 + rho_phi^2)^(3/2)  (+ convex)
// its gradient includes the contact's own shift ds/dc_j = s_q N_j / G_q.
struct SwingContact {
  double s_rad = 0.0;             // contact polar angle from the rest direction [rad]
  double curvature = 0.0;         // pitch-curve curvature [1/mm]
  Eigen::RowVectorXd curvature_row;  // d kappa / d c_j [1/mm per mm]
  // pressure angle between the pitch-curve normal and the follower roller centre's path
  // (the normal n = rho e_r - rho_phi e_phi, the path p_q = r_q e_r + r phi_q e_phi) [rad]
  double pressure_angle = 0.0;
  Eigen::RowVectorXd pressure_angle_row;  // [rad per mm]
  // contact normal force per unit valve force (virtual work): |L_q| |n| / |n . p_q| [-]
  double force_ratio = 0.0;
  Eigen::RowVectorXd force_ratio_row;
  // roller spin relative to the follower for perfect rolling: s |p'| / r + psi' - q'
  // (p' the roller centre's velocity in the swing frame, s = sign(p x p')) [rad per cam rad]
  double roller_speed = 0.0;
  Eigen::RowVectorXd roller_speed_row;
};

struct SwingPoint {
  int position = 0;     // index into positions()
  double cam_deg = 0.0;
};

class SwingCamLift {
 public:
  // cuts the design at its swing cam; grid_step_deg: the cam-angle grid. points on the dwell
  // at every admissible design (the roller on the dwell arc short of s_a) are left out.
  // InputError when the design is not a swing cam driving a rotational follower that moves
  // the output node through a circle on a line. A kinematic solve that fails (tracing the
  // design's own swing profile, or the drive at a grid point) is the returned Status, and
  // `out` is left as it was.
  static Status create(const DesignSpec& design, const SwingProfileSpec& spec, double grid_step_deg,
                       std::unique_ptr<SwingCamLift>& out);
  // the same, a failing solve thrown as NumericalError
  SwingCamLift(const DesignSpec& design, const SwingProfileSpec& spec, double grid_step_deg);
  ~SwingCamLift();
  SwingCamLift(SwingCamLift&&) noexcept;
  SwingCamLift(const SwingCamLift&) = delete;
  SwingCamLift& operator=(const SwingCamLift&) = delete;

  int variables() const noexcept;  // free coefficients of h
  const std::vector<double>& positions() const noexcept;
  // every control value [design order] at position k
  const std::vector<double>& controls(int k) const;
  const std::vector<SwingPoint>& points() const noexcept;
  // free coefficients fitted (least squares) to the pitch curve of the design's own swing
  // profile, traced by the kinematic solver at position 0 [mm]
  const std::vector<double>& initial() const noexcept;
  double start_rad() const noexcept;
  double end_rad() const noexcept;
  double dwell_radius_mm() const noexcept;  // rho_0 [mm]
  double roller_radius_mm() const noexcept;

  // valve lift and derivatives d^k L / dtheta^k [mm/deg^k] at grid point i
  // for free coefficients c, and their gradients rows(k, j) = d(motion k)/d c_j [per mm].
  // a failing solve returns its status (where: cam angle and control position).
  Status evaluate(int point, std::span<const double> c, double motion[4], Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows,
                  SwingContact* contact = nullptr);
  // the same off the grid (solves the upstream part at cam_deg)
  Status evaluate_at(int position, double cam_deg, std::span<const double> c, double motion[4],
                     Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows);

  // h^(m)(s) for m = 0..4 at s [rad] (s <= s_a: 0) [mm / rad^m]
  void pitch_lift(std::span<const double> c, double s_rad, double out[5]) const;
  // the swing cam's working surface: the pitch curve offset inward by the roller radius,
  // as a polar table about the profile's origin in its own frame (orientation), over the
  // whole revolution (dwell arc elsewhere) [deg, mm]. Past the farthest contact a nose
  // turns the pitch curve back with a convex surface radius >= min_convex_radius_mm [mm].
  // A Status (undercut) when no nose up to 48 swing deg can, or the surface folds.
  Status profile_table(std::span<const double> c, int points, double min_convex_radius_mm,
                       std::vector<double>& angle_deg, std::vector<double>& radius_mm) const;
  const std::string& profile_name() const noexcept;
  const std::string& connection() const noexcept;

 private:
  SwingCamLift();  // an empty model for create()
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camopt::opt
