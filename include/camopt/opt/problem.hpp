#pragma once
// the cam optimisation problem compiled against a design: variables, bounds, objective,
// constraints and their exact gradients, in the form every solver backend takes
//   minimise f(u)  subject to  A u = b (closure),  g(u) <= 0,  lower <= u <= upper.
// u are the acceleration b-spline coefficients (lift_model.hpp) divided by the coefficient
// bound (so |u| <= 1), plus the epigraph variable t of a peak objective (f = t, q_i <= t).
// every inequality is normalised by its limit so g = 0 is the boundary and g = 1 a miss by
// 100 %. the valve-motion constraints are linear in u; the contact constraints come from
// CamContactModel (cam_contact.hpp) at every grid angle with exact gradients, chained
// through the lift rows: dg/du = dg/dL row_0 + dg/dL' row_1 + dg/dL'' row_2.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/opt/cam_contact.hpp"
#include "camopt/opt/lift_model.hpp"
#include "camopt/opt/optimization_spec.hpp"

namespace camopt::opt {

enum class ConstraintKind {
  acc_max,
  acc_min,
  jerk_max,
  lift_max,
  lift_nonnegative,  // the valve stays off its seat between the ramps
  peak_lift_min,
  duration_min,
  duration_max,
  radius_min,
  concave_radius,
  pressure_angle,
  roller_speed,
  sliding_speed,
  hertz_stress,
  face_width,
  separation,      // a contact's least force from rest up to the separation-speed limit >= 0
  contact_force,   // the cam contact's normal force at rpm >= limit
  spring_margin,   // a contact's force >= margin x a spring's part of it, at rpm
  cam_torque,      // +- cam drive torque <= limit, at rpm
  film_thickness,  // EHL minimum film of the cam contact >= limit, at rpm
  lambda,          // film / composite roughness >= limit
  peak_bound,  // q_i - t <= 0 of a peak objective
};
const char* to_string(ConstraintKind kind);
// the constraint-set key that sets a kind's limit ("limits.acc_max_mm_per_deg2"), as the user
// wrote it; null for the rows the user does not set (lift_nonnegative, peak_bound) and
// "design: <what>" for limits taken from the design (face_width)
const char* limit_key(ConstraintKind kind);

struct ConstraintRow {
  ConstraintKind kind;
  double cam_deg = 0.0;  // where it is evaluated [cam deg]; scalar constraints: where it is attained
  int grid = -1;         // grid index (-1: a scalar constraint)
  int position = 0;      // swing cam: control position index (SwingCamLift::positions); scalar rows: 0
  int item = -1;         // load rows: the contact (separation), contact x springs + spring (spring margin)
};

// a value of the design the constraint set replaces (load.override_design = true)
struct LoadOverride {
  std::string key;           // "load.spring_preload_N"
  double set_value = 0.0;
  std::string design_value;  // the design's value with its unit and where it is stated
};

namespace detail {
class LoadRows;
}

struct Evaluation {
  double objective = 0.0;
  Eigen::VectorXd gradient;    // df/du
  Eigen::VectorXd g;           // normalised inequalities (<= 0 feasible)
  Eigen::MatrixXd jacobian;    // dg/du (rows x variables)
  Eigen::VectorXd physical;    // each inequality's quantity in its unit (see unit_of)
  Eigen::VectorXd equality;    // A u - b (closure) [normalised]
  bool have_gradients = false;
};

class CamProblem {
 public:
  // the problem of `spec` on `design`. target_lift: valve lift [mm] against driver angle [rad]
  // (ObjectiveSpec::target_weight > 0 needs one), may be null. InputError for a set that
  // breaks its own rules or needs data the design lacks. A kinematic solve that fails while
  // building (the swing cam's traces and drive; the initial design's rows, "the initial
  // design: ...") is the returned Status, and `out` is left as it was.
  [[nodiscard]] static Status create(const DesignSpec& design, const OptimizationSpec& spec,
                                     const PeriodicSpline* target_lift, std::unique_ptr<CamProblem>& out);
  ~CamProblem();
  CamProblem(const CamProblem&) = delete;
  CamProblem& operator=(const CamProblem&) = delete;

  int variables() const noexcept { return n_; }
  int spline_variables() const noexcept { return nv_; }
  bool has_peak_variable() const noexcept { return n_ > nv_; }
  bool is_swing() const noexcept { return swing_ != nullptr; }
  const std::vector<ConstraintRow>& rows() const noexcept { return rows_; }
  const std::vector<double>& lower() const noexcept { return lower_; }
  const std::vector<double>& upper() const noexcept { return upper_; }
  const std::vector<double>& start() const noexcept { return start_; }
  // closure A u = b (conventional cam: 2 rows; swing cam: none)
  const Eigen::MatrixXd& equality_matrix() const noexcept { return eq_a_; }
  const Eigen::VectorXd& equality_rhs() const noexcept { return eq_b_; }
  // structural nonzeros of the inequality jacobian, row-major (row, column)
  const std::vector<std::pair<int, int>>& jacobian_pattern() const noexcept { return pattern_; }
  const std::vector<double>& grid_deg() const noexcept { return grid_; }

  // f, g and (gradients = true) their derivatives at u (u.size() == variables()); a failing
  // contact inversion or envelope returns its status (the caller rejects the step)
  Status evaluate(std::span<const double> u, Evaluation& out, bool gradients);

  // hessian of the objective at the last evaluate(): the target term's gauss-newton matrix
  // 2 w sum_i r_i r_i^T (exact for a conventional cam, whose lift is linear in u); the area
  // and peak terms are linear (zero). n x n
  Eigen::MatrixXd objective_hessian() const;

  // coefficients of the lift model (conventional: acceleration [mm/deg^2]; swing: pitch-curve
  // lift h [mm]) for u
  std::vector<double> coefficients(std::span<const double> u) const;
  const AccelerationSplineLift& lift_model() const noexcept { return *lift_; }
  // swing cam: the pitch-curve model (null for a conventional cam); every evaluation solves it
  SwingCamLift* swing() const noexcept { return swing_.get(); }
  const CamContactModel& contact() const noexcept { return *contact_; }
  const OptimizationSpec& spec() const noexcept { return spec_; }
  // unit and limit of a row's physical value, and whether the limit is an upper bound
  const char* unit_of(ConstraintKind kind) const;
  double limit_of(ConstraintKind kind) const;
  bool is_upper_limit(ConstraintKind kind) const;
  double cam_speed_rad_per_s() const noexcept { return omega_; }
  // where the load-based rows take their loads from ("" without such rows), and what the set overrides
  std::string load_source() const;
  std::vector<LoadOverride> load_overrides() const;
  // the contact or "contact / spring" a load row is about ("" for other rows)
  std::string item_name(const ConstraintRow& row) const;

 private:
  struct GridPoint;  // problem_detail.hpp
  struct PointRows;  // the rows of one grid point (problem_rows.cpp)
  struct LiftProbe;  // the lift model between the grid points, for the scalar rows
  using Motions = std::vector<std::array<double, 4>>;  // per grid point: lift [mm], d^k/dtheta^k [mm/deg^k]

  explicit CamProblem(const OptimizationSpec& spec);  // the steps below fill it (create)

  // ---- construction steps (problem.cpp) ----
  Status build(const DesignSpec& design, const PeriodicSpline* target_lift);
  Status make_lift_model(const DesignSpec& design);
  void check_ramp_velocities() const;
  void make_contact_model(const DesignSpec& design);
  void make_swing_grid(const PeriodicSpline* target_lift);
  void make_event_grid(const PeriodicSpline* target_lift);
  void set_variables_and_closure();
  void build_rows();
  Status scale_objectives();

  // ---- evaluation steps ----
  // valve lift and derivatives at every grid point [mm/deg^k] (swing: also the rows)
  Status motions(std::span<const double> u, Motions& motion);
  // objective and its gradient: target least squares, lift area, peak epigraph
  void objective(std::span<const double> u, const Motions& motion, Evaluation& e, bool gradients) const;
  // the rows of every grid point (problem_rows.cpp); r: the first row after them
  Status grid_rows(std::span<const double> u, const Motions& motion, Evaluation& e, bool gradients, std::size_t& r);
  // the scalar rows r.. (problem_rows.cpp)
  Status scalar_rows(std::span<const double> u, const Motions& motion, Evaluation& e, bool gradients, std::size_t r);
  void peak_lift_row(const Motions& motion, LiftProbe& lift_at, Evaluation& e, bool gradients, std::size_t r);
  void duration_row(const Motions& motion, LiftProbe& lift_at, Evaluation& e, bool gradients, std::size_t r);

  // scalar constraints look at these points only (swing: the full-lift position 0)
  bool scalar_point(std::size_t i) const noexcept;
  // consecutive grid points i, i + 1 of one position one grid step apart
  bool adjacent(std::size_t i) const noexcept;
  OptimizationSpec spec_;
  std::optional<AccelerationSplineLift> lift_;
  std::unique_ptr<SwingCamLift> swing_;
  std::unique_ptr<CamContactModel> contact_;
  std::unique_ptr<detail::LoadRows> load_rows_;
  std::vector<ContactWorkspace> contact_ws_;  // per control position
  std::vector<SwingContact> swing_contact_;   // swing: the pitch curve at each grid point
  std::vector<double> grid_;                // event grid [cam deg]
  std::vector<GridPoint> points_;
  std::vector<ConstraintRow> rows_;
  std::vector<std::pair<int, int>> pattern_;
  std::vector<double> lower_, upper_, start_;
  Eigen::MatrixXd eq_a_;
  Eigen::VectorXd eq_b_;
  std::vector<double> target_;              // target lift at the grid [mm]
  int n_ = 0, nv_ = 0;
  double coef_scale_ = 1.0;                 // [mm/deg^2] per unit of u
  double omega_ = 0.0;                      // cam speed [rad/s]
  double area0_ = 1.0, peak_scale_ = 1.0;
  bool need_contact_ = false;
};

}  // namespace camopt::opt
