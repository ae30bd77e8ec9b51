#pragma once
// the optimiser's valve-lift model: one lift event whose main part (between the ramps)
// has its acceleration expressed as a clamped b-spline in cam angle,
//   L''(theta) = sum_j c_j N_{j,p}(theta),   theta in [theta_a, theta_b]  [mm/deg^2]
//   L(theta)   = H_o + v_o (theta - theta_a) + sum_j c_j M_j(theta),  M_j = int int N_j
// with the opening ramp (height H_o, velocity v_o) before theta_a and the closing ramp
// after theta_b (synthesis::Ramp: constant velocity with a cycloidal velocity blend).
// c_0 = c_{n-1} = 0 (zero acceleration where the ramps join: c2), and the variables are
// x = (c_1 .. c_{n-2}). closure: two linear equalities A x = b make the main part end on
// the closing ramp's height and velocity. the lift is linear in x, so every derivative
// at an angle is a row: d^k L / dtheta^k = constant_k + row_k . x (de Boor, A Practical
// Guide to Splines, ch. X: integrals and derivatives of b-splines).
#include <Eigen/Core>
#include <array>
#include <functional>
#include <span>
#include <vector>

#include "camopt/synthesis/lift_law.hpp"
#include "camopt/synthesis/lift_law_event.hpp"

namespace camopt::opt {

struct RampSpec {
  double height_mm = 0.0;   // lift at the ramp's end [mm] (0 with length 0: no ramp)
  double length_deg = 0.0;  // [cam deg]
};

struct EventSpec {
  double start_deg = 0.0;     // cam angle where the opening ramp starts [cam deg]
  double duration_deg = 0.0;  // base circle to base circle, ramps included [cam deg]
  RampSpec opening_ramp, closing_ramp;
  double ramp_blend = 0.5;  // fraction of each ramp spent reaching its velocity, (0, 1]
  int coefficients = 24;    // acceleration b-spline coefficients, the two zero end ones included
  int degree = 3;           // acceleration b-spline degree, 2..5
};

// InputError naming the field (event.*), the value and the rule
void validate(const EventSpec& spec);

class AccelerationSplineLift {
 public:
  static AccelerationSplineLift compile(const EventSpec& spec);

  const EventSpec& spec() const noexcept { return spec_; }
  int variables() const noexcept { return static_cast<int>(lift_coef_.size()); }
  double main_start_deg() const noexcept { return theta_a_; }
  double main_end_deg() const noexcept { return theta_b_; }
  double event_end_deg() const noexcept { return spec_.start_deg + spec_.duration_deg; }
  const synthesis::Ramp& opening_ramp() const noexcept { return opening_; }
  const synthesis::Ramp& closing_ramp() const noexcept { return closing_; }

  // d^k L / dtheta^k, k = 0..3, at cam_deg (unwrapped: start_deg <= cam_deg <= event end
  // gives the event, anything else the base circle) = constant[k] + rows.row(k) . x
  // [mm / deg^k]
  void rows(double cam_deg, std::array<double, 4>& constant, Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows) const;
  // lift and derivatives at cam_deg for the variables x [mm, per cam deg]
  synthesis::Motion evaluate(std::span<const double> x, double cam_deg) const;
  // the event's cam angle for any cam angle: the representative in [start, start + 360)
  double unwrap(double cam_deg) const noexcept;

  // closure A x = b: velocity and lift at the end of the main part match the closing ramp
  const Eigen::Matrix<double, 2, Eigen::Dynamic>& closure_matrix() const noexcept { return closure_a_; }
  const Eigen::Vector2d& closure_rhs() const noexcept { return closure_b_; }

  // least-squares fit of the variables to lift(cam_deg) [mm] sampled every step_deg over
  // the main part, subject to closure (the initial design, or the reference of a test)
  std::vector<double> fit(const std::function<double(double)>& lift, double step_deg) const;

 private:
  EventSpec spec_;
  synthesis::Ramp opening_, closing_;
  double theta_a_ = 0.0, theta_b_ = 0.0;
  int p_ = 3;
  std::vector<double> t_acc_, t_vel_, t_lift_, t_jerk_;  // knots of acceleration, velocity, lift, jerk
  // per variable j: the coefficients of its basis function's acceleration (a unit vector),
  // velocity, lift and jerk splines
  std::vector<std::vector<double>> acc_coef_, vel_coef_, lift_coef_, jerk_coef_;
  Eigen::Matrix<double, 2, Eigen::Dynamic> closure_a_;
  Eigen::Vector2d closure_b_ = Eigen::Vector2d::Zero();
};

}  // namespace camopt::opt
