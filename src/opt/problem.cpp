#include "camopt/opt/problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "load_rows.hpp"
#include "problem_detail.hpp"

namespace camopt::opt {

namespace {

std::string num(double v) { return format_value(v, 8); }

bool needs_contact(const OptimizationSpec& s) {
  const auto& l = s.limits;
  const bool peak_contact = s.objective.peak_weight > 0.0 &&
                            (s.objective.peak == Quantity::pressure_angle || s.objective.peak == Quantity::hertz_stress ||
                             s.objective.peak == Quantity::roller_speed || s.objective.peak == Quantity::sliding_speed ||
                             s.objective.peak == Quantity::curvature);
  return peak_contact || l.min_radius_of_curvature_mm || l.grinding_wheel_radius_mm || l.max_pressure_angle_deg ||
         l.max_roller_speed_rpm || l.max_sliding_speed_m_per_s || l.max_hertz_stress_MPa || l.min_separation_speed_rpm ||
         l.min_contact_force_N || l.min_spring_margin || l.max_cam_torque_Nm || l.min_film_thickness_um || l.min_lambda;
}

}  // namespace

CamProblem::CamProblem(const OptimizationSpec& spec) : spec_(spec) {}
CamProblem::~CamProblem() = default;

Status CamProblem::create(const DesignSpec& design, const OptimizationSpec& spec, const PeriodicSpline* target_lift,
                          std::unique_ptr<CamProblem>& out) {
  std::unique_ptr<CamProblem> problem(new CamProblem(spec));
  if (Status st = problem->build(design, target_lift); !st.ok()) return st;
  out = std::move(problem);
  return Status::success();
}

Status CamProblem::build(const DesignSpec& design, const PeriodicSpline* target_lift) {
  // the set's own rules and its controls against the design's
  validate(spec_, design.driver.crank_per_cam);
  if (!spec_.controls.empty() && spec_.controls.size() != design.controls.size())
    throw located_error(spec_, "set.controls: " + std::to_string(spec_.controls.size()) + " value(s) given, but the design " +
                     design.file + " has " + std::to_string(design.controls.size()) +
                     " [[control]] (one value per control, in the design's order)");
  // the lift model: the swing cam's pitch curve, or the acceleration b-spline of the event
  if (Status st = make_lift_model(design); !st.ok()) return st;
  // cam speed [rad/s]
  omega_ = spec_.rpm / design.driver.crank_per_cam * 2.0 * pi / 60.0;
  // ramps against the seating / opening velocity limits
  check_ramp_velocities();
  // the contact model and the loads of the contact rows, when a row or the objective needs them
  make_contact_model(design);
  // the grid, the target there and the starting point
  if (swing_) make_swing_grid(target_lift);
  else make_event_grid(target_lift);
  // variables, their bounds and the closure A u = b
  set_variables_and_closure();
  // the constraint rows and the jacobian's pattern
  build_rows();
  // scales of the area and peak objectives from the initial design
  return scale_objectives();
}

Status CamProblem::make_lift_model(const DesignSpec& design) {
  if (spec_.cam == "swing") {
    if (Status st = SwingCamLift::create(design, spec_.swing, spec_.grid_step_deg, swing_); !st.ok()) return st;
    nv_ = swing_->variables();
  } else {
    lift_.emplace(AccelerationSplineLift::compile(spec_.event));
    nv_ = lift_->variables();
  }
  return Status::success();
}

// the ramps are fixed by the event, so a miss is a contradiction between [event] and [limits]
void CamProblem::check_ramp_velocities() const {
  const auto& lim = spec_.limits;
  const double to_m_per_s = omega_ * deg_per_rad * 1e-3;  // [mm/deg] -> [m/s]
  if (lift_ && lim.max_seating_velocity_m_per_s && lift_->closing_ramp().velocity() * to_m_per_s > *lim.max_seating_velocity_m_per_s)
    throw InputError("event.closing_ramp gives a seating velocity of " +
                     num(lift_->closing_ramp().velocity() * to_m_per_s) + " m/s at " + num(spec_.rpm) +
                     " rpm, above limits.max_seating_velocity_m_per_s = " + num(*lim.max_seating_velocity_m_per_s) +
                     ": lengthen the closing ramp or lower its height");
  if (lift_ && lim.max_opening_ramp_velocity_m_per_s &&
      lift_->opening_ramp().velocity() * to_m_per_s > *lim.max_opening_ramp_velocity_m_per_s)
    throw InputError("event.opening_ramp gives a ramp velocity of " + num(lift_->opening_ramp().velocity() * to_m_per_s) +
                     " m/s at " + num(spec_.rpm) + " rpm, above limits.max_opening_ramp_velocity_m_per_s = " +
                     num(*lim.max_opening_ramp_velocity_m_per_s));
}

void CamProblem::make_contact_model(const DesignSpec& design) {
  const auto& lim = spec_.limits;
  const bool swing = swing_ != nullptr;
  need_contact_ = needs_contact(spec_);
  if (need_contact_) {
    // swing: the model names the contact, its follower and materials; the quantities come
    // from the swing profile itself (SwingContact), never from its envelope
    contact_ = std::make_unique<CamContactModel>(design, spec_.controls, spec_.cam);
    if (!swing) contact_ws_.push_back(contact_->make_workspace());
    if (swing && lim.max_sliding_speed_m_per_s)
      throw InputError("limits.max_sliding_speed_m_per_s: not available for a swing cam (its follower is a roller)");
    if (lim.max_roller_speed_rpm && contact_->follower_shape() != FollowerShape::roller)
      throw InputError("limits.max_roller_speed_rpm: the follower of contact '" + contact_->connection() +
                       "' is not a roller");
    // the loads of the separation, margin, torque, Hertz and film rows: one source (load_rows.hpp)
    std::vector<std::vector<double>> controls;
    if (swing)
      for (std::size_t k = 0; k < swing_->positions().size(); ++k) controls.push_back(swing_->controls(static_cast<int>(k)));
    else
      controls.push_back(contact_->controls());
    load_rows_ = std::make_unique<detail::LoadRows>(design, spec_, *contact_, omega_, controls);
  }
  if (swing && spec_.objective.peak_weight > 0 && spec_.objective.peak != Quantity::acceleration &&
      spec_.objective.peak != Quantity::deceleration && spec_.objective.peak != Quantity::jerk &&
      spec_.objective.peak != Quantity::pressure_angle)
    throw InputError(std::string("objective.peak = ") + to_string(spec_.objective.peak) +
                     ": a swing cam minimises the peak of acceleration, deceleration, jerk or pressure_angle");
}

// swing cam: the working points of every control position (SwingCamLift); the target
// applies at the full-lift position 0; the start is the fit of the design's own profile
void CamProblem::make_swing_grid(const PeriodicSpline* target_lift) {
  for (const SwingPoint& sp : swing_->points()) {
    GridPoint gp;
    gp.deg = sp.cam_deg;
    gp.position = sp.position;
    gp.rows.setZero(4, nv_);
    gp.variable = false;  // the dwell keeps the valve shut: no lift_nonnegative rows
    points_.push_back(std::move(gp));
    grid_.push_back(sp.cam_deg);
    if (target_lift) target_.push_back(sp.position == 0 ? (*target_lift)(sp.cam_deg / deg_per_rad) : 0.0);
  }
  const std::vector<double>& c0 = swing_->initial();
  double cmax = 0.0;
  for (double c : c0) cmax = std::max(cmax, std::abs(c));
  coef_scale_ = spec_.coefficient_bound > 0 ? spec_.coefficient_bound : 1.5 * cmax;
  if (!(coef_scale_ > 0)) coef_scale_ = 1.0;
  start_.resize(static_cast<std::size_t>(nv_));
  for (int j = 0; j < nv_; ++j)
    start_[static_cast<std::size_t>(j)] = std::clamp(c0[static_cast<std::size_t>(j)] / coef_scale_, 0.0, 1.0);
}

// conventional cam: a grid over the event, ramps included; the start is the fit of the
// target, else of a 4-5-6-7 event of the initial lift with the ramps
void CamProblem::make_event_grid(const PeriodicSpline* target_lift) {
  const auto& lim = spec_.limits;
  const double dur = spec_.event.duration_deg;
  const int steps = std::max(8, static_cast<int>(std::ceil(dur / spec_.grid_step_deg - 1e-9)));
  const int nv = nv_;
  points_.resize(static_cast<std::size_t>(steps) + 1);
  grid_.resize(points_.size());
  for (int i = 0; i <= steps; ++i) {
    GridPoint& gp = points_[static_cast<std::size_t>(i)];
    gp.deg = spec_.event.start_deg + dur * i / steps;
    grid_[static_cast<std::size_t>(i)] = gp.deg;
    gp.rows.resize(4, nv);
    lift_->rows(gp.deg, gp.constant, gp.rows);
    gp.variable = gp.rows.cwiseAbs().maxCoeff() > 0.0;
  }

  // initial lift: the target, else a 4-5-6-7 event of the initial lift with the ramps
  std::function<double(double)> initial;
  synthesis::LiftEvent event;
  if (target_lift) {
    for (const auto& gp : points_) target_.push_back((*target_lift)(gp.deg / deg_per_rad));
    initial = [target_lift](double deg) { return (*target_lift)(deg / deg_per_rad); };
  } else {
    synthesis::LiftEventSpec es;
    es.max_lift_mm = spec_.initial_max_lift_mm;
    es.peak_deg = std::fmod(spec_.event.start_deg + 0.5 * dur + 360.0, 360.0);
    es.ramp_blend = spec_.event.ramp_blend;
    es.opening = {synthesis::LawKind::polynomial_4567, 0.5 * dur, spec_.event.opening_ramp.height_mm,
                  spec_.event.opening_ramp.length_deg, {}, 3};
    es.closing = {synthesis::LawKind::polynomial_4567, 0.5 * dur, spec_.event.closing_ramp.height_mm,
                  spec_.event.closing_ramp.length_deg, {}, 3};
    event = synthesis::LiftEvent::compile(es);
    initial = [&event](double deg) { return event.evaluate(deg).lift; };
  }
  const std::vector<double> c0 = lift_->fit(initial, 0.25);
  double cmax = 0.0;
  for (double c : c0) cmax = std::max(cmax, std::abs(c));
  coef_scale_ = spec_.coefficient_bound > 0 ? spec_.coefficient_bound
                : lim.acc_max_mm_per_deg2 || lim.acc_min_mm_per_deg2
                    ? 3.0 * std::max(lim.acc_max_mm_per_deg2.value_or(0.0), -lim.acc_min_mm_per_deg2.value_or(0.0))
                    : 3.0 * cmax;
  if (!(coef_scale_ > 0)) coef_scale_ = 1e-2;
  for (auto& gp : points_) gp.rows *= coef_scale_;
  start_.resize(static_cast<std::size_t>(nv));
  for (int j = 0; j < nv; ++j)
    start_[static_cast<std::size_t>(j)] = std::clamp(c0[static_cast<std::size_t>(j)] / coef_scale_, -1.0, 1.0);
}

// u = the spline variables in [-1, 1] (swing: [0, 1], h >= 0) and the peak variable; the
// closure rows (conventional cam) normalised to O(1)
void CamProblem::set_variables_and_closure() {
  const bool swing = swing_ != nullptr;
  const bool peak = spec_.objective.peak_weight > 0.0;
  n_ = nv_ + (peak ? 1 : 0);
  lower_.assign(static_cast<std::size_t>(n_), -1.0);
  upper_.assign(static_cast<std::size_t>(n_), 1.0);
  start_.resize(static_cast<std::size_t>(n_));
  if (swing) {
    // h >= 0 (the b-spline's convex hull): the working curve never dips below the dwell
    std::fill(lower_.begin(), lower_.begin() + nv_, 0.0);
    eq_a_.setZero(0, n_);
    eq_b_.setZero(0);
  } else {
    eq_a_ = lift_->closure_matrix() * coef_scale_;
    eq_a_.conservativeResize(2, n_);
    if (peak) eq_a_.col(n_ - 1).setZero();
    eq_b_ = lift_->closure_rhs();
    // normalise the closure rows (velocity [mm/deg], lift [mm]) to O(1)
    for (int r = 0; r < 2; ++r) {
      const double s = std::max(eq_a_.row(r).cwiseAbs().maxCoeff(), 1e-300);
      eq_a_.row(r) /= s;
      eq_b_(r) /= s;
    }
  }
}

// the peak objective's scale (the initial design's worst peak row) and its variable's
// start and bounds; the area objective's scale (the initial design's lift area)
Status CamProblem::scale_objectives() {
  const bool peak = spec_.objective.peak_weight > 0.0;
  if (peak) {
    start_[static_cast<std::size_t>(n_ - 1)] = 0.0;
    peak_scale_ = 1.0;
    Evaluation e;
    if (Status st = evaluate(start_, e, false); !st.ok())
      return {st.code, "the initial design: " + st.message, st.where};
    double worst = 0.0;
    for (std::size_t r = 0; r < rows_.size(); ++r)
      if (rows_[r].kind == ConstraintKind::peak_bound) worst = std::max(worst, e.physical(static_cast<Eigen::Index>(r)));
    peak_scale_ = worst > 0 ? worst : 1.0;
    start_[static_cast<std::size_t>(n_ - 1)] = 1.0;
    lower_[static_cast<std::size_t>(n_ - 1)] = -10.0;
    upper_[static_cast<std::size_t>(n_ - 1)] = 10.0;
  }
  Motions motion;
  if (Status st = motions(start_, motion); !st.ok()) return {st.code, "the initial design: " + st.message, st.where};
  double a = 0.0;
  for (std::size_t i = 0; i + 1 < points_.size(); ++i)
    if (scalar_point(i) && adjacent(i)) a += 0.5 * (motion[i][0] + motion[i + 1][0]) * (points_[i + 1].deg - points_[i].deg);
  area0_ = a > 0 ? a : 1.0;
  return Status::success();
}

void CamProblem::build_rows() {
  const auto& lim = spec_.limits;
  const bool peak = spec_.objective.peak_weight > 0.0;
  const int nv = nv_;
  rows_.clear();
  pattern_.clear();
  auto add = [&](ConstraintKind kind, int grid, const std::vector<int>& derivs, bool peak_col) {
    const int r = static_cast<int>(rows_.size());
    rows_.push_back({kind, grid >= 0 ? points_[static_cast<std::size_t>(grid)].deg : 0.0, grid,
                     grid >= 0 ? points_[static_cast<std::size_t>(grid)].position : 0});
    for (int j = 0; j < nv; ++j) {
      // scalar constraints, and every swing-cam row (the contact moves along the profile): dense
      bool nz = grid < 0 || swing_ != nullptr;
      if (grid >= 0)
        for (int k : derivs) nz = nz || points_[static_cast<std::size_t>(grid)].rows(k, j) != 0.0;
      if (nz) pattern_.emplace_back(r, j);
    }
    if (peak_col) pattern_.emplace_back(r, n_ - 1);
  };
  const bool roller_like = contact_ && contact_->follower_shape() != FollowerShape::flat;
  for (int i = 0; i < static_cast<int>(points_.size()); ++i) {
    if (lim.acc_max_mm_per_deg2) add(ConstraintKind::acc_max, i, {2}, false);
    if (lim.acc_min_mm_per_deg2) add(ConstraintKind::acc_min, i, {2}, false);
    if (lim.jerk_max_mm_per_deg3) {
      add(ConstraintKind::jerk_max, i, {3}, false);
      add(ConstraintKind::jerk_max, i, {3}, false);
    }
    if (lim.max_lift_mm) add(ConstraintKind::lift_max, i, {0}, false);
    if (points_[static_cast<std::size_t>(i)].variable) add(ConstraintKind::lift_nonnegative, i, {0}, false);
    if (lim.min_radius_of_curvature_mm) add(ConstraintKind::radius_min, i, {0, 1, 2}, false);
    if (lim.grinding_wheel_radius_mm && roller_like && *lim.grinding_wheel_radius_mm > contact_->follower_radius_mm())
      add(ConstraintKind::concave_radius, i, {0, 1, 2}, false);
    if (lim.max_pressure_angle_deg) add(ConstraintKind::pressure_angle, i, {0, 1, 2}, false);
    if (lim.max_roller_speed_rpm) add(ConstraintKind::roller_speed, i, {0, 1, 2}, false);
    if (lim.max_sliding_speed_m_per_s) add(ConstraintKind::sliding_speed, i, {0, 1, 2}, false);
    if (lim.max_hertz_stress_MPa) add(ConstraintKind::hertz_stress, i, {0, 1, 2}, false);
    if (contact_ && contact_->follower_shape() == FollowerShape::flat && contact_->face_half_width_mm() > 0)
      add(ConstraintKind::face_width, i, {0, 1, 2}, false);
    // the load rows where the valve is off its seat (its load then goes to the cam)
    const GridPoint& gp = points_[static_cast<std::size_t>(i)];
    if (load_rows_ && (swing_ || gp.variable || gp.constant[0] > 0.0))
      for (const detail::LoadRowSpec& lr : load_rows_->point_rows()) {
        add(lr.kind, i, {0, 1, 2}, false);
        rows_.back().item = lr.item;
      }
    if (peak) {
      const Quantity q = spec_.objective.peak;
      const std::vector<int> d = q == Quantity::acceleration || q == Quantity::deceleration ? std::vector<int>{2}
                                 : q == Quantity::jerk                                     ? std::vector<int>{3}
                                                                                           : std::vector<int>{0, 1, 2};
      add(ConstraintKind::peak_bound, i, d, true);
      if (q == Quantity::jerk) add(ConstraintKind::peak_bound, i, d, true);
    }
  }
  if (lim.min_max_lift_mm) add(ConstraintKind::peak_lift_min, -1, {}, false);
  if (lim.duration_check_height_mm && lim.min_duration_deg) add(ConstraintKind::duration_min, -1, {}, false);
  if (lim.duration_check_height_mm && lim.max_duration_deg) add(ConstraintKind::duration_max, -1, {}, false);
}

std::vector<double> CamProblem::coefficients(std::span<const double> u) const {
  std::vector<double> c(static_cast<std::size_t>(nv_));
  for (std::size_t j = 0; j < c.size(); ++j) c[j] = u[j] * coef_scale_;
  return c;
}

Eigen::MatrixXd CamProblem::objective_hessian() const {
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n_, n_);
  if (!(spec_.objective.target_weight > 0.0)) return h;
  std::size_t count = 0;
  for (std::size_t i = 0; i < points_.size(); ++i) count += scalar_point(i) ? 1 : 0;
  const double w = spec_.objective.target_weight / (static_cast<double>(std::max<std::size_t>(count, 1)) * 1e-6);
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (scalar_point(i)) h.topLeftCorner(nv_, nv_).noalias() += 2.0 * w * points_[i].rows.row(0).transpose() * points_[i].rows.row(0);
  return h;
}

bool CamProblem::scalar_point(std::size_t i) const noexcept { return points_[i].position == 0; }

bool CamProblem::adjacent(std::size_t i) const noexcept {
  return i + 1 < points_.size() && points_[i].position == points_[i + 1].position &&
         std::abs(points_[i + 1].deg - points_[i].deg - spec_.grid_step_deg) < 1e-6;
}

Status CamProblem::motions(std::span<const double> u, Motions& motion) {
  const Eigen::Map<const Eigen::VectorXd> us(u.data(), nv_);
  motion.resize(points_.size());
  swing_contact_.resize(swing_ ? points_.size() : 1);
  if (!swing_) {
    for (std::size_t i = 0; i < points_.size(); ++i)
      for (int k = 0; k < 4; ++k)
        motion[i][static_cast<std::size_t>(k)] =
            points_[i].constant[static_cast<std::size_t>(k)] + points_[i].rows.row(k).dot(us);
    return Status::success();
  }
  // swing cam: the lift is nonlinear in u; the rows are its gradient at u (per unit of u)
  const std::vector<double> c = coefficients(u);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    GridPoint& gp = points_[i];
    if (Status st = swing_->evaluate(static_cast<int>(i), c, motion[i].data(), gp.rows, &swing_contact_[i]); !st.ok())
      return st;
    gp.rows *= coef_scale_;
  }
  return Status::success();
}

Status CamProblem::evaluate(std::span<const double> u, Evaluation& e, bool gradients) {
  CAMOPT_ASSERT(static_cast<int>(u.size()) == n_);
  const std::size_t m = rows_.size();
  // the outputs' shapes, and the closure rows
  e.g.resize(static_cast<Eigen::Index>(m));
  e.physical.resize(static_cast<Eigen::Index>(m));
  e.have_gradients = gradients;
  if (gradients) {
    e.jacobian.setZero(static_cast<Eigen::Index>(m), n_);
    e.gradient.setZero(n_);
  }
  e.equality = eq_a_ * Eigen::Map<const Eigen::VectorXd>(u.data(), n_) - eq_b_;
  // valve lift and its derivatives at every grid point
  Motions motion;
  if (Status st = motions(u, motion); !st.ok()) return st;
  // objective: target least squares, lift area and the peak epigraph variable
  objective(u, motion, e, gradients);
  // per-angle constraints
  std::size_t r = 0;
  if (Status st = grid_rows(u, motion, e, gradients, r); !st.ok()) return st;
  // scalar constraints: peak lift and duration at the check height
  return scalar_rows(u, motion, e, gradients, r);
}

void CamProblem::objective(std::span<const double> u, const Motions& motion, Evaluation& e, bool gradients) const {
  const int nv = nv_;
  const bool peak = spec_.objective.peak_weight > 0.0;
  const double t = peak ? u[static_cast<std::size_t>(n_ - 1)] : 0.0;
  double f = 0.0;
  Eigen::VectorXd df = Eigen::VectorXd::Zero(n_);
  const std::size_t np = points_.size();
  if (spec_.objective.target_weight > 0.0) {
    // mean squared error in um^2: 1 um is the scale of interest of a lift match. swing cam:
    // at the full-lift position, and where the target is closed only an open valve counts
    std::size_t count = 0;
    for (std::size_t i = 0; i < np; ++i) count += scalar_point(i) ? 1 : 0;
    const double w = spec_.objective.target_weight / (static_cast<double>(std::max<std::size_t>(count, 1)) * 1e-6);
    for (std::size_t i = 0; i < np; ++i) {
      if (!scalar_point(i)) continue;
      const double d = swing_ && target_[i] <= 0.0 ? std::max(motion[i][0], 0.0) : motion[i][0] - target_[i];
      f += w * d * d;
      if (gradients) df.head(nv) += 2.0 * w * d * points_[i].rows.row(0).transpose();
    }
  }
  if (spec_.objective.area_weight > 0.0) {
    const double w = spec_.objective.area_weight / area0_;
    for (std::size_t i = 0; i + 1 < np; ++i) {
      if (!scalar_point(i) || !adjacent(i)) continue;
      const double h = 0.5 * (points_[i + 1].deg - points_[i].deg);
      f -= w * h * (motion[i][0] + motion[i + 1][0]);
      if (gradients) df.head(nv) -= w * h * (points_[i].rows.row(0) + points_[i + 1].rows.row(0)).transpose();
    }
  }
  if (peak) {
    f += spec_.objective.peak_weight * t;
    df(n_ - 1) += spec_.objective.peak_weight;
  }
  e.objective = f;
  if (gradients) e.gradient = df;
}

}  // namespace camopt::opt
