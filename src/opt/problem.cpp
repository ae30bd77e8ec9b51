#include "camopt/opt/problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "camopt/synthesis/lift_law_event.hpp"
#include "load_rows.hpp"

namespace camopt::opt {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

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

struct CamProblem::GridPoint {
  double deg = 0.0;
  int position = 0;                               // swing: control position index
  std::array<double, 4> constant{};
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows;  // d^k L / dtheta^k per unit of u [mm/deg^k]
  bool variable = false;                          // inside the main part (rows not all zero)
};

CamProblem::~CamProblem() = default;

CamProblem::CamProblem(const DesignSpec& design, const OptimizationSpec& spec, const PeriodicSpline* target_lift)
    : spec_(spec) {
  validate(spec_, design.driver.crank_per_cam);
  if (!spec_.controls.empty() && spec_.controls.size() != design.controls.size())
    throw located_error(spec_, "set.controls: " + std::to_string(spec_.controls.size()) + " value(s) given, but the design " +
                     design.file + " has " + std::to_string(design.controls.size()) +
                     " [[control]] (one value per control, in the design's order)");
  const bool swing = spec_.cam == "swing";
  if (swing) {
    swing_ = std::make_unique<SwingCamLift>(design, spec_.swing, spec_.grid_step_deg);
    nv_ = swing_->variables();
  } else {
    lift_.emplace(AccelerationSplineLift::compile(spec_.event));
    nv_ = lift_->variables();
  }
  const auto& lim = spec_.limits;
  omega_ = spec_.rpm / design.driver.crank_per_cam * 2.0 * std::numbers::pi / 60.0;

  // ramps against the seating / opening velocity limits: fixed by the event, so a miss is a
  // contradiction between [event] and [limits]
  const double to_m_per_s = omega_ * kDegPerRad * 1e-3;  // [mm/deg] -> [m/s]
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

  if (swing) {
    // grid: the working points of every control position (SwingCamLift); the target applies
    // at the full-lift position 0
    for (const SwingPoint& sp : swing_->points()) {
      GridPoint gp;
      gp.deg = sp.cam_deg;
      gp.position = sp.position;
      gp.rows.setZero(4, nv_);
      gp.variable = false;  // the dwell keeps the valve shut: no lift_nonnegative rows
      points_.push_back(std::move(gp));
      grid_.push_back(sp.cam_deg);
      if (target_lift) target_.push_back(sp.position == 0 ? (*target_lift)(sp.cam_deg / kDegPerRad) : 0.0);
    }
    const std::vector<double>& c0 = swing_->initial();
    double cmax = 0.0;
    for (double c : c0) cmax = std::max(cmax, std::abs(c));
    coef_scale_ = spec_.coefficient_bound > 0 ? spec_.coefficient_bound : 1.5 * cmax;
    if (!(coef_scale_ > 0)) coef_scale_ = 1.0;
    start_.resize(static_cast<std::size_t>(nv_));
    for (int j = 0; j < nv_; ++j)
      start_[static_cast<std::size_t>(j)] = std::clamp(c0[static_cast<std::size_t>(j)] / coef_scale_, 0.0, 1.0);
  } else {
    // grid over the event, ramps included
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
      for (const auto& gp : points_) target_.push_back((*target_lift)(gp.deg / kDegPerRad));
      initial = [target_lift](double deg) { return (*target_lift)(deg / kDegPerRad); };
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

  build_rows();

  // scales of the area and peak objectives from the initial design
  if (peak) {
    start_[static_cast<std::size_t>(n_ - 1)] = 0.0;
    peak_scale_ = 1.0;
    Evaluation e;
    if (Status st = evaluate(start_, e, false); !st.ok())
      throw NumericalError({st.code, "the initial design: " + st.message, st.where});
    double worst = 0.0;
    for (std::size_t r = 0; r < rows_.size(); ++r)
      if (rows_[r].kind == ConstraintKind::peak_bound) worst = std::max(worst, e.physical(static_cast<Eigen::Index>(r)));
    peak_scale_ = worst > 0 ? worst : 1.0;
    start_[static_cast<std::size_t>(n_ - 1)] = 1.0;
    lower_[static_cast<std::size_t>(n_ - 1)] = -10.0;
    upper_[static_cast<std::size_t>(n_ - 1)] = 10.0;
  }
  {
    std::vector<std::array<double, 4>> motion;
    if (Status st = motions(start_, motion); !st.ok())
      throw NumericalError({st.code, "the initial design: " + st.message, st.where});
    double a = 0.0;
    for (std::size_t i = 0; i + 1 < points_.size(); ++i)
      if (scalar_point(i) && adjacent(i))
        a += 0.5 * (motion[i][0] + motion[i + 1][0]) * (points_[i + 1].deg - points_[i].deg);
    area0_ = a > 0 ? a : 1.0;
  }
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

Status CamProblem::motions(std::span<const double> u, std::vector<std::array<double, 4>>& motion) {
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
  const int nv = nv_;
  const auto& lim = spec_.limits;
  const Eigen::Map<const Eigen::VectorXd> uv(u.data(), n_);
  const Eigen::VectorXd us = uv.head(nv);
  const std::size_t m = rows_.size();
  e.g.resize(static_cast<Eigen::Index>(m));
  e.physical.resize(static_cast<Eigen::Index>(m));
  e.have_gradients = gradients;
  if (gradients) {
    e.jacobian.setZero(static_cast<Eigen::Index>(m), n_);
    e.gradient.setZero(n_);
  }
  e.equality = eq_a_ * uv - eq_b_;
  const bool peak = spec_.objective.peak_weight > 0.0;
  const double t = peak ? u[static_cast<std::size_t>(n_ - 1)] : 0.0;
  const double r1 = kDegPerRad, r2 = kDegPerRad * kDegPerRad;

  // objective: target least squares and lift area over the grid
  double f = 0.0;
  Eigen::VectorXd df = Eigen::VectorXd::Zero(n_);
  const std::size_t np = points_.size();
  std::vector<std::array<double, 4>> motion;
  if (Status st = motions(u, motion); !st.ok()) return st;
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

  // per-angle constraints
  ContactQuantities cq;
  std::size_t r = 0;
  const bool roller_like = contact_ && contact_->follower_shape() != FollowerShape::flat;
  const double rf = roller_like ? contact_->follower_radius_mm() : 0.0;
  for (std::size_t i = 0; i < np && r < m; ++i) {
    const GridPoint& gp = points_[i];
    const auto& mo = motion[i];
    bool have_contact = false;
    // the contact quantities (rotational cam) and the loads at this angle, once
    auto contact = [&]() -> Status {
      if (have_contact) return Status::success();
      const double lift[3] = {mo[0], mo[1] * r1, mo[2] * r2};
      if (!swing_)
        if (Status st = contact_->evaluate(gp.deg / kDegPerRad, lift, contact_ws_[static_cast<std::size_t>(gp.position)], cq);
            !st.ok())
          return st;
      if (load_rows_)
        if (Status st = load_rows_->prepare(gp.deg / kDegPerRad, lift, gp.position); !st.ok()) return st;
      have_contact = true;
      return Status::success();
    };
    // p0^2 = F E* / (pi L R*) [MPa^2] (Johnson, Contact Mechanics, eq. 4.45) with the valve-side
    // force F (the cam contact's generalized force at the set's speed, load_rows.hpp) taken to
    // the contact by virtual work: p0^2 R* = F_n E* / (pi L) [MPa^2 mm]
    auto valve_force = [&]() { return load_rows_->cam_force(); };  // [N], after contact()
    const double hertz_k = load_rows_ ? load_rows_->e_star_MPa() / (std::numbers::pi * load_rows_->width_mm()) : 0.0;
    auto hertz_load = [&]() { return valve_force() * cq.force_ratio * hertz_k; };
    auto hertz_p0_squared = [&]() { return hertz_load() * cq.inverse_radius_sum; };
    // gradient row of a contact quantity
    auto chain = [&](const Grad3& q, double scale) {
      return ((q.d[0] * gp.rows.row(0) + q.d[1] * r1 * gp.rows.row(1) + q.d[2] * r2 * gp.rows.row(2)) * scale).eval();
    };
    for (; r < m && rows_[r].grid == static_cast<int>(i); ++r) {
      const ConstraintKind kind = rows_[r].kind;
      const auto ri = static_cast<Eigen::Index>(r);
      auto set_linear = [&](double value, int k, double sign, double scale, double physical) {
        e.g(ri) = value;
        e.physical(ri) = physical;
        if (gradients) e.jacobian.row(ri).head(nv) = sign / scale * gp.rows.row(k);
      };
      // swing: the pitch curvature and its gradient row per unit of u
      const SwingContact& sc = swing_contact_[swing_ ? i : 0];
      auto kappa_u = [&] { return (sc.curvature_row * coef_scale_).eval(); };
      auto set_row = [&](double value, const Eigen::RowVectorXd& row_u, double physical) {
        e.g(ri) = value;
        e.physical(ri) = physical;
        if (gradients) e.jacobian.row(ri).head(nv) = row_u;
      };
      auto set_contact = [&](const Grad3& q, double physical) {
        e.g(ri) = q.v;
        e.physical(ri) = physical;
        if (gradients) e.jacobian.row(ri).head(nv) = chain(q, 1.0);
      };
      const bool second_jerk_row = r > 0 && rows_[r - 1].grid == rows_[r].grid && rows_[r - 1].kind == kind;
      switch (kind) {
        case ConstraintKind::acc_max: {
          const double a = *lim.acc_max_mm_per_deg2;
          set_linear((mo[2] - a) / a, 2, 1.0, a, mo[2]);
          break;
        }
        case ConstraintKind::acc_min: {
          const double a = -*lim.acc_min_mm_per_deg2;
          set_linear((-a - mo[2]) / a, 2, -1.0, a, mo[2]);
          break;
        }
        case ConstraintKind::jerk_max: {
          const double j = *lim.jerk_max_mm_per_deg3;
          const double s = second_jerk_row ? -1.0 : 1.0;
          set_linear((s * mo[3] - j) / j, 3, s, j, std::abs(mo[3]));
          break;
        }
        case ConstraintKind::lift_max: {
          const double l = *lim.max_lift_mm;
          set_linear((mo[0] - l) / l, 0, 1.0, l, mo[0]);
          break;
        }
        case ConstraintKind::lift_nonnegative: {
          const double l = std::max(spec_.initial_max_lift_mm, 1.0);
          set_linear(-mo[0] / l, 0, -1.0, l, mo[0]);
          break;
        }
        case ConstraintKind::peak_bound: {
          const Quantity q = spec_.objective.peak;
          if (q == Quantity::acceleration || q == Quantity::deceleration || q == Quantity::jerk) {
            const int k = q == Quantity::jerk ? 3 : 2;
            const double s = q == Quantity::deceleration || (q == Quantity::jerk && second_jerk_row) ? -1.0 : 1.0;
            set_linear(s * mo[static_cast<std::size_t>(k)] / peak_scale_ - t, k, s, peak_scale_,
                       s * mo[static_cast<std::size_t>(k)]);
          } else {
            if (Status st = contact(); !st.ok()) return st;
            Grad3 v;
            switch (q) {
              case Quantity::pressure_angle:
                v = cq.pressure_angle * kDegPerRad;
                if (swing_) {  // the profile's own pressure angle (see SwingContact)
                  set_row(sc.pressure_angle * kDegPerRad / peak_scale_ - t,
                          sc.pressure_angle_row * (coef_scale_ * kDegPerRad / peak_scale_), sc.pressure_angle * kDegPerRad);
                  if (gradients) e.jacobian(ri, n_ - 1) = -1.0;
                  continue;
                }
                break;
              case Quantity::roller_speed: v = cq.roller_speed * cq.roller_speed; break;
              case Quantity::sliding_speed: v = cq.sliding * cq.sliding; break;
              case Quantity::curvature: v = roller_like ? cq.pitch_curvature : 1.0 / cq.cam_radius; break;
              default:
                if (!roller_like) {
                  // flat face: p0^2 / s - t <= 0 times R / R_ref, as the hertz row (no pole at R = 0)
                  const double r_ref = lim.min_radius_of_curvature_mm.value_or(1.0);
                  set_contact((hertz_load() / peak_scale_ - cq.cam_radius * t) / r_ref, hertz_p0_squared().v);
                  if (gradients) e.jacobian(ri, n_ - 1) = -cq.cam_radius.v / r_ref;
                  continue;
                }
                v = hertz_p0_squared();
                break;
            }
            set_contact(v / peak_scale_, v.v);
            e.g(ri) -= t;
          }
          if (gradients) e.jacobian(ri, n_ - 1) = -1.0;
          break;
        }
        default: {
          if (Status st = contact(); !st.ok()) return st;
          switch (kind) {
            case ConstraintKind::radius_min: {
              const double rho = *lim.min_radius_of_curvature_mm;
              if (swing_) set_row(sc.curvature * (rho + rf) - 1.0, kappa_u() * (rho + rf), 1.0 / sc.curvature - rf);
              else if (roller_like) set_contact(cq.pitch_curvature * (rho + rf) - 1.0, cq.cam_radius.v);
              else set_contact((rho - cq.cam_radius) / rho, cq.cam_radius.v);
              break;
            }
            case ConstraintKind::concave_radius: {
              const double rw = *lim.grinding_wheel_radius_mm;
              if (swing_) set_row(-sc.curvature * (rw - rf) - 1.0, -kappa_u() * (rw - rf), 1.0 / sc.curvature - rf);
              else set_contact(-cq.pitch_curvature * (rw - rf) - 1.0, cq.cam_radius.v);
              break;
            }
            case ConstraintKind::pressure_angle: {
              const double a = *lim.max_pressure_angle_deg / kDegPerRad;
              if (swing_) set_row((sc.pressure_angle - a) / a, sc.pressure_angle_row * (coef_scale_ / a), sc.pressure_angle * kDegPerRad);
              else set_contact((cq.pressure_angle - a) / a, cq.pressure_angle.v * kDegPerRad);
              break;
            }
            case ConstraintKind::roller_speed: {
              const double lim_rad = *lim.max_roller_speed_rpm * 2.0 * std::numbers::pi / 60.0 / omega_;  // [rad/rad]
              if (swing_) {
                const double w = sc.roller_speed;
                set_row((w * w - lim_rad * lim_rad) / (lim_rad * lim_rad),
                        sc.roller_speed_row * (2.0 * w * coef_scale_ / (lim_rad * lim_rad)),
                        std::abs(w) * omega_ * 60.0 / (2.0 * std::numbers::pi));
                break;
              }
              set_contact((cq.roller_speed * cq.roller_speed - lim_rad * lim_rad) / (lim_rad * lim_rad),
                          std::abs(cq.roller_speed.v) * omega_ * 60.0 / (2.0 * std::numbers::pi));
              break;
            }
            case ConstraintKind::sliding_speed: {
              const double lim_mm = *lim.max_sliding_speed_m_per_s * 1e3 / omega_;  // [mm/rad]
              set_contact((cq.sliding * cq.sliding - lim_mm * lim_mm) / (lim_mm * lim_mm),
                          std::abs(cq.sliding.v) * omega_ * 1e-3);
              break;
            }
            case ConstraintKind::hertz_stress: {
              const double s2 = *lim.max_hertz_stress_MPa * *lim.max_hertz_stress_MPa;
              if (swing_) {
                // 1/R* from the profile's own curvature: p0^2 = (F n) / (r (1 - r kappa))
                const Grad3 fv = valve_force();
                const double fn = fv.v * sc.force_ratio * hertz_k;
                const Eigen::RowVectorXd fn_row =
                    (chain(fv, 1.0) * sc.force_ratio + fv.v * coef_scale_ * sc.force_ratio_row) * hertz_k;
                const double inv = 1.0 / (rf - rf * rf * sc.curvature), dinv = rf * rf * inv * inv;
                const double p2 = fn * inv;
                set_row((p2 - s2) / s2, (fn_row * inv + fn * dinv * kappa_u()) / s2, std::sqrt(std::max(0.0, p2)));
              } else if (!roller_like) {
                // flat face: p0^2 = F' / R, R = r_b + L + L'' linear in the lift, has a pole
                // at R = 0 on the way from a pointed initial lobe (R < 0) to a feasible one,
                // which stalls an interior-point solver. the row times R / R_ref instead:
                // (F' - s2 R) / (s2 R_ref), linear in the lift; the same sign wherever R > 0,
                // and at least as large as (p0^2 - s2) / s2 wherever R >= R_ref (the radius limit)
                const Grad3 p2 = hertz_p0_squared();
                const double r_ref = lim.min_radius_of_curvature_mm.value_or(1.0);
                set_contact((hertz_load() - cq.cam_radius * s2) / (s2 * r_ref), std::sqrt(std::max(0.0, p2.v)));
              } else {
                const Grad3 p2 = hertz_p0_squared();
                set_contact((p2 - s2) / s2, std::sqrt(std::max(0.0, p2.v)));
              }
              break;
            }
            case ConstraintKind::face_width: {
              const double hw = contact_->face_half_width_mm();
              set_contact((cq.face_offset * cq.face_offset - hw * hw) / (hw * hw), std::abs(cq.face_offset.v));
              break;
            }
            case ConstraintKind::separation:
            case ConstraintKind::contact_force:
            case ConstraintKind::spring_margin:
            case ConstraintKind::cam_torque:
            case ConstraintKind::film_thickness:
            case ConstraintKind::lambda: {
              // swing: the force ratio is a value here, its u-row added through d_ratio
              const detail::LoadRowValue v = load_rows_->row({kind, rows_[r].item}, swing_ ? Grad3(sc.force_ratio) : cq.force_ratio,
                                                             swing_ ? nullptr : &cq);
              if (swing_) set_row(v.g.v, chain(v.g, 1.0) + v.d_ratio * coef_scale_ * sc.force_ratio_row, v.physical);
              else set_contact(v.g, v.physical);
              break;
            }
            default: CAMOPT_ASSERT(false);
          }
        }
      }
    }
  }

  // scalar constraints: peak lift and duration at the check height
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows4(4, nv);
  std::array<double, 4> cst{};
  Status scalar_status = Status::success();
  const std::vector<double> coef = coefficients(u);
  auto lift_at = [&](double deg, int k) {
    if (swing_) {  // at the full-lift position
      double mo[4];
      if (Status st = swing_->evaluate_at(0, deg, coef, mo, rows4); !st.ok()) {
        if (scalar_status.ok()) scalar_status = st;
        return 0.0;
      }
      return mo[k];
    }
    lift_->rows(deg, cst, rows4);
    return cst[static_cast<std::size_t>(k)] + rows4.row(k).dot(us * coef_scale_);
  };
  for (; r < m; ++r) {
    const auto ri = static_cast<Eigen::Index>(r);
    const ConstraintKind kind = rows_[r].kind;
    if (kind == ConstraintKind::peak_lift_min) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < np; ++i)
        if (scalar_point(i) && motion[i][0] > motion[best][0]) best = i;
      double th = points_[best].deg;
      for (int it = 0; it < 20; ++it) {  // newton on L' = 0
        const double d1 = lift_at(th, 1), d2 = lift_at(th, 2);
        if (!(d2 < 0)) break;
        const double step = std::clamp(-d1 / d2, -spec_.grid_step_deg, spec_.grid_step_deg);
        th += step;
        if (std::abs(step) < 1e-12) break;
      }
      const double peak_lift = lift_at(th, 0);
      const double lm = *lim.min_max_lift_mm;
      e.g(ri) = (lm - peak_lift) / lm;
      e.physical(ri) = peak_lift;
      rows_[r].cam_deg = th;
      if (gradients) e.jacobian.row(ri).head(nv) = -rows4.row(0) * coef_scale_ / lm;
    } else {
      const double h = *lim.duration_check_height_mm;
      // first and last crossing of the check height, refined by newton on the lift model
      int first = -1, last = -1;
      for (std::size_t i = 0; i + 1 < np; ++i) {
        if (!scalar_point(i) || !adjacent(i)) continue;
        if (first < 0 && motion[i][0] < h && motion[i + 1][0] >= h) first = static_cast<int>(i);
        if (motion[i][0] >= h && motion[i + 1][0] < h) last = static_cast<int>(i);
      }
      double duration = 0.0;
      Eigen::RowVectorXd grad = Eigen::RowVectorXd::Zero(nv);
      if (first >= 0 && last >= 0) {
        auto crossing = [&](int i, double sign) {
          double th = points_[static_cast<std::size_t>(i)].deg;
          const double lo = th, hi = points_[static_cast<std::size_t>(i) + 1].deg;
          for (int it = 0; it < 30; ++it) {
            const double v = lift_at(th, 0) - h, d1 = lift_at(th, 1);
            const double next = std::clamp(th - v / d1, lo, hi);
            if (std::abs(next - th) < 1e-13) break;
            th = next;
          }
          const double d1 = lift_at(th, 1);  // also leaves rows4 at the crossing
          // d(theta*)/du = -dL/du / L'(theta*)
          grad += sign * (-rows4.row(0) * coef_scale_ / d1);
          return th;
        };
        const double open = crossing(first, -1.0);
        const double close = crossing(last, 1.0);
        duration = close - open;
      }
      const bool is_min = kind == ConstraintKind::duration_min;
      const double lim_d = is_min ? *lim.min_duration_deg : *lim.max_duration_deg;
      e.g(ri) = is_min ? (lim_d - duration) / lim_d : (duration - lim_d) / lim_d;
      e.physical(ri) = duration;
      if (gradients) e.jacobian.row(ri).head(nv) = (is_min ? -grad : grad) / lim_d;
    }
  }
  return scalar_status;
}

}  // namespace camopt::opt
