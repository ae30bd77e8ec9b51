// the inequality rows of CamProblem::evaluate: at every grid point the valve-motion rows
// (linear in u), the contact rows (CamContactModel, or the swing profile's own SwingContact)
// and the load rows (load_rows.hpp), each with its gradient chained through the lift rows;
// then the scalar rows (peak lift, duration at the check height) found on the lift model
// between the grid points.
#include <algorithm>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/opt/problem.hpp"
#include "load_rows.hpp"
#include "problem_detail.hpp"

namespace camopt::opt {

// the rows of one grid point; a row's value is normalised by its limit (g <= 0 feasible),
// its physical value is in the unit of CamProblem::unit_of
struct CamProblem::PointRows {
  CamProblem& p;
  Evaluation& e;
  bool gradients;
  const GridPoint& gp;
  const std::array<double, 4>& mo;  // lift [mm] and its derivatives [mm/deg^k] here
  ContactQuantities& cq;            // the rotational cam's contact quantities, after contact()
  const SwingContact& sc;           // swing: the pitch curve here
  double t;                         // the peak objective's epigraph variable (0 without one)
  bool roller_like;                 // the follower is a roller or a pad (not flat)
  double rf;                        // its radius [mm] (0 when flat)
  double hertz_k;                   // E* / (pi L) [MPa / mm]
  bool have_contact = false;
  Eigen::Index ri = 0;  // the row being set
  static constexpr double r1 = deg_per_rad, r2 = deg_per_rad * deg_per_rad;  // per deg -> per rad

  Status row(std::size_t r);
  void linear_row(ConstraintKind kind, bool second_jerk_row);
  Status peak_row(bool second_jerk_row);
  Status contact_row(ConstraintKind kind, int item);
  void hertz_row();

  // the contact quantities (rotational cam) and the loads at this angle, once
  Status contact() {
    if (have_contact) return Status::success();
    const double lift[3] = {mo[0], mo[1] * r1, mo[2] * r2};
    if (!p.swing_)
      if (Status st = p.contact_->evaluate(gp.deg / deg_per_rad, lift,
                                           p.contact_ws_[static_cast<std::size_t>(gp.position)], cq);
          !st.ok())
        return st;
    if (p.load_rows_)
      if (Status st = p.load_rows_->prepare(gp.deg / deg_per_rad, lift, gp.position); !st.ok()) return st;
    have_contact = true;
    return Status::success();
  }
  // p0^2 = F E* / (pi L R*) [MPa^2] (Johnson, Contact Mechanics, eq. 4.45) with the valve-side
  // force F (the cam contact's generalized force at the set's speed, load_rows.hpp) taken to
  // the contact by virtual work: p0^2 R* = F_n E* / (pi L) [MPa^2 mm]
  Grad3 valve_force() const { return p.load_rows_->cam_force(); }  // [N], after contact()
  Grad3 hertz_load() const { return valve_force() * cq.force_ratio * hertz_k; }
  Grad3 hertz_p0_squared() const { return hertz_load() * cq.inverse_radius_sum; }
  // gradient row of a contact quantity
  Eigen::RowVectorXd chain(const Grad3& q, double scale) const {
    return ((q.d[0] * gp.rows.row(0) + q.d[1] * r1 * gp.rows.row(1) + q.d[2] * r2 * gp.rows.row(2)) * scale).eval();
  }
  // swing: the pitch curvature's gradient row per unit of u
  Eigen::RowVectorXd kappa_u() const { return (sc.curvature_row * p.coef_scale_).eval(); }
  // a row linear in lift derivative k: value, d/du = sign / scale x lift row k
  void set_linear(double value, int k, double sign, double scale, double physical) {
    e.g(ri) = value;
    e.physical(ri) = physical;
    if (gradients) e.jacobian.row(ri).head(p.nv_) = sign / scale * gp.rows.row(k);
  }
  void set_row(double value, const Eigen::RowVectorXd& row_u, double physical) {
    e.g(ri) = value;
    e.physical(ri) = physical;
    if (gradients) e.jacobian.row(ri).head(p.nv_) = row_u;
  }
  void set_contact(const Grad3& q, double physical) {
    e.g(ri) = q.v;
    e.physical(ri) = physical;
    if (gradients) e.jacobian.row(ri).head(p.nv_) = chain(q, 1.0);
  }
};

Status CamProblem::PointRows::row(std::size_t r) {
  const ConstraintKind kind = p.rows_[r].kind;
  ri = static_cast<Eigen::Index>(r);
  // jerk rows come in pairs (+ and -): the second of a pair bounds -jerk
  const bool second_jerk_row = r > 0 && p.rows_[r - 1].grid == p.rows_[r].grid && p.rows_[r - 1].kind == kind;
  switch (kind) {
    case ConstraintKind::acc_max:
    case ConstraintKind::acc_min:
    case ConstraintKind::jerk_max:
    case ConstraintKind::lift_max:
    case ConstraintKind::lift_nonnegative:
      linear_row(kind, second_jerk_row);
      return Status::success();
    case ConstraintKind::peak_bound:
      return peak_row(second_jerk_row);
    default:
      return contact_row(kind, p.rows_[r].item);
  }
}

// acceleration, jerk and lift limits: linear in u
void CamProblem::PointRows::linear_row(ConstraintKind kind, bool second_jerk_row) {
  const auto& lim = p.spec_.limits;
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
      const double l = std::max(p.spec_.initial_max_lift_mm, 1.0);
      set_linear(-mo[0] / l, 0, -1.0, l, mo[0]);
      break;
    }
    default: CAMOPT_ASSERT(false);
  }
}

// q_i / peak_scale - t <= 0 of a peak objective
Status CamProblem::PointRows::peak_row(bool second_jerk_row) {
  const auto& lim = p.spec_.limits;
  const int n = p.n_;
  const Quantity q = p.spec_.objective.peak;
  if (q == Quantity::acceleration || q == Quantity::deceleration || q == Quantity::jerk) {
    const int k = q == Quantity::jerk ? 3 : 2;
    const double s = q == Quantity::deceleration || (q == Quantity::jerk && second_jerk_row) ? -1.0 : 1.0;
    set_linear(s * mo[static_cast<std::size_t>(k)] / p.peak_scale_ - t, k, s, p.peak_scale_,
               s * mo[static_cast<std::size_t>(k)]);
  } else {
    if (Status st = contact(); !st.ok()) return st;
    Grad3 v;
    switch (q) {
      case Quantity::pressure_angle:
        v = cq.pressure_angle * deg_per_rad;
        if (p.swing_) {  // the profile's own pressure angle (see SwingContact)
          set_row(sc.pressure_angle * deg_per_rad / p.peak_scale_ - t,
                  sc.pressure_angle_row * (p.coef_scale_ * deg_per_rad / p.peak_scale_), sc.pressure_angle * deg_per_rad);
          if (gradients) e.jacobian(ri, n - 1) = -1.0;
          return Status::success();
        }
        break;
      case Quantity::roller_speed: v = cq.roller_speed * cq.roller_speed; break;
      case Quantity::sliding_speed: v = cq.sliding * cq.sliding; break;
      case Quantity::curvature: v = roller_like ? cq.pitch_curvature : 1.0 / cq.cam_radius; break;
      default:
        if (!roller_like) {
          // flat face: p0^2 / s - t <= 0 times R / R_ref, as the hertz row (no pole at R = 0)
          const double r_ref = lim.min_radius_of_curvature_mm.value_or(1.0);
          set_contact((hertz_load() / p.peak_scale_ - cq.cam_radius * t) / r_ref, hertz_p0_squared().v);
          if (gradients) e.jacobian(ri, n - 1) = -cq.cam_radius.v / r_ref;
          return Status::success();
        }
        v = hertz_p0_squared();
        break;
    }
    set_contact(v / p.peak_scale_, v.v);
    e.g(ri) -= t;
  }
  if (gradients) e.jacobian(ri, n - 1) = -1.0;
  return Status::success();
}

// the rows of the contact quantities and the loads
Status CamProblem::PointRows::contact_row(ConstraintKind kind, int item) {
  const auto& lim = p.spec_.limits;
  const double omega = p.omega_;
  if (Status st = contact(); !st.ok()) return st;
  switch (kind) {
    case ConstraintKind::radius_min: {
      const double rho = *lim.min_radius_of_curvature_mm;
      if (p.swing_) set_row(sc.curvature * (rho + rf) - 1.0, kappa_u() * (rho + rf), 1.0 / sc.curvature - rf);
      else if (roller_like) set_contact(cq.pitch_curvature * (rho + rf) - 1.0, cq.cam_radius.v);
      else set_contact((rho - cq.cam_radius) / rho, cq.cam_radius.v);
      break;
    }
    case ConstraintKind::concave_radius: {
      const double rw = *lim.grinding_wheel_radius_mm;
      if (p.swing_) set_row(-sc.curvature * (rw - rf) - 1.0, -kappa_u() * (rw - rf), 1.0 / sc.curvature - rf);
      else set_contact(-cq.pitch_curvature * (rw - rf) - 1.0, cq.cam_radius.v);
      break;
    }
    case ConstraintKind::pressure_angle: {
      const double a = *lim.max_pressure_angle_deg / deg_per_rad;
      if (p.swing_)
        set_row((sc.pressure_angle - a) / a, sc.pressure_angle_row * (p.coef_scale_ / a), sc.pressure_angle * deg_per_rad);
      else set_contact((cq.pressure_angle - a) / a, cq.pressure_angle.v * deg_per_rad);
      break;
    }
    case ConstraintKind::roller_speed: {
      const double lim_rad = *lim.max_roller_speed_rpm * 2.0 * pi / 60.0 / omega;  // [rad/rad]
      if (p.swing_) {
        const double w = sc.roller_speed;
        set_row((w * w - lim_rad * lim_rad) / (lim_rad * lim_rad),
                sc.roller_speed_row * (2.0 * w * p.coef_scale_ / (lim_rad * lim_rad)),
                std::abs(w) * omega * 60.0 / (2.0 * pi));
        break;
      }
      set_contact((cq.roller_speed * cq.roller_speed - lim_rad * lim_rad) / (lim_rad * lim_rad),
                  std::abs(cq.roller_speed.v) * omega * 60.0 / (2.0 * pi));
      break;
    }
    case ConstraintKind::sliding_speed: {
      const double lim_mm = *lim.max_sliding_speed_m_per_s * 1e3 / omega;  // [mm/rad]
      set_contact((cq.sliding * cq.sliding - lim_mm * lim_mm) / (lim_mm * lim_mm), std::abs(cq.sliding.v) * omega * 1e-3);
      break;
    }
    case ConstraintKind::hertz_stress: hertz_row(); break;
    case ConstraintKind::face_width: {
      const double hw = p.contact_->face_half_width_mm();
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
      const detail::LoadRowValue v = p.load_rows_->row({kind, item}, p.swing_ ? Grad3(sc.force_ratio) : cq.force_ratio,
                                                       p.swing_ ? nullptr : &cq);
      if (p.swing_) set_row(v.g.v, chain(v.g, 1.0) + v.d_ratio * p.coef_scale_ * sc.force_ratio_row, v.physical);
      else set_contact(v.g, v.physical);
      break;
    }
    default: CAMOPT_ASSERT(false);
  }
  return Status::success();
}

// the hertz stress p0 <= limit, as (p0^2 - s^2) / s^2 <= 0 [MPa^2]
void CamProblem::PointRows::hertz_row() {
  const auto& lim = p.spec_.limits;
  const double s2 = *lim.max_hertz_stress_MPa * *lim.max_hertz_stress_MPa;
  if (p.swing_) {
    // 1/R* from the profile's own curvature: p0^2 = (F n) / (r (1 - r kappa))
    const Grad3 fv = valve_force();
    const double fn = fv.v * sc.force_ratio * hertz_k;
    const Eigen::RowVectorXd fn_row = (chain(fv, 1.0) * sc.force_ratio + fv.v * p.coef_scale_ * sc.force_ratio_row) * hertz_k;
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
}

// the rows of every grid point, in row order; r: the first row after them
Status CamProblem::grid_rows(std::span<const double> u, const Motions& motion, Evaluation& e,
                             bool gradients, std::size_t& r) {
  const std::size_t m = rows_.size(), np = points_.size();
  const bool peak = spec_.objective.peak_weight > 0.0;
  const double t = peak ? u[static_cast<std::size_t>(n_ - 1)] : 0.0;
  ContactQuantities cq;
  const bool roller_like = contact_ && contact_->follower_shape() != FollowerShape::flat;
  const double rf = roller_like ? contact_->follower_radius_mm() : 0.0;
  for (std::size_t i = 0; i < np && r < m; ++i) {
    const double hertz_k = load_rows_ ? load_rows_->e_star_MPa() / (pi * load_rows_->width_mm()) : 0.0;
    PointRows point{*this, e, gradients, points_[i], motion[i], cq, swing_contact_[swing_ ? i : 0],
                    t,     roller_like, rf, hertz_k};
    for (; r < m && rows_[r].grid == static_cast<int>(i); ++r)
      if (Status st = point.row(r); !st.ok()) return st;
  }
  return Status::success();
}

// the lift model between the grid points for the scalar rows: the lift's k-th derivative
// at a cam angle [mm/deg^k] and its rows per unit of u (rows4, of the last call)
struct CamProblem::LiftProbe {
  CamProblem& p;
  Eigen::VectorXd us;  // u without the peak variable
  std::vector<double> coef;
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows4;
  std::array<double, 4> cst{};
  Status status = Status::success();  // the first failed swing evaluation

  double operator()(double deg, int k) {
    if (p.swing_) {  // at the full-lift position
      double mo[4];
      if (Status st = p.swing_->evaluate_at(0, deg, coef, mo, rows4); !st.ok()) {
        if (status.ok()) status = st;
        return 0.0;
      }
      return mo[k];
    }
    p.lift_->rows(deg, cst, rows4);
    return cst[static_cast<std::size_t>(k)] + rows4.row(k).dot(us * p.coef_scale_);
  }
};

// the peak lift >= limit: the grid's highest point refined by newton on L' = 0
void CamProblem::peak_lift_row(const Motions& motion, LiftProbe& lift_at, Evaluation& e,
                               bool gradients, std::size_t r) {
  const auto ri = static_cast<Eigen::Index>(r);
  std::size_t best = 0;
  for (std::size_t i = 1; i < points_.size(); ++i)
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
  const double lm = *spec_.limits.min_max_lift_mm;
  e.g(ri) = (lm - peak_lift) / lm;
  e.physical(ri) = peak_lift;
  rows_[r].cam_deg = th;
  if (gradients) e.jacobian.row(ri).head(nv_) = -lift_at.rows4.row(0) * coef_scale_ / lm;
}

// the duration at the check height between its first and last crossing, each refined by
// newton on the lift model, against its minimum or maximum
void CamProblem::duration_row(const Motions& motion, LiftProbe& lift_at, Evaluation& e,
                              bool gradients, std::size_t r) {
  const auto& lim = spec_.limits;
  const auto ri = static_cast<Eigen::Index>(r);
  const std::size_t np = points_.size();
  const double h = *lim.duration_check_height_mm;
  int first = -1, last = -1;
  for (std::size_t i = 0; i + 1 < np; ++i) {
    if (!scalar_point(i) || !adjacent(i)) continue;
    if (first < 0 && motion[i][0] < h && motion[i + 1][0] >= h) first = static_cast<int>(i);
    if (motion[i][0] >= h && motion[i + 1][0] < h) last = static_cast<int>(i);
  }
  double duration = 0.0;
  Eigen::RowVectorXd grad = Eigen::RowVectorXd::Zero(nv_);
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
      grad += sign * (-lift_at.rows4.row(0) * coef_scale_ / d1);
      return th;
    };
    const double open = crossing(first, -1.0);
    const double close = crossing(last, 1.0);
    duration = close - open;
  }
  const bool is_min = rows_[r].kind == ConstraintKind::duration_min;
  const double lim_d = is_min ? *lim.min_duration_deg : *lim.max_duration_deg;
  e.g(ri) = is_min ? (lim_d - duration) / lim_d : (duration - lim_d) / lim_d;
  e.physical(ri) = duration;
  if (gradients) e.jacobian.row(ri).head(nv_) = (is_min ? -grad : grad) / lim_d;
}

// rows r.. (the scalar rows); a failed swing evaluation between the grid points is returned
Status CamProblem::scalar_rows(std::span<const double> u, const Motions& motion,
                               Evaluation& e, bool gradients, std::size_t r) {
  const Eigen::Map<const Eigen::VectorXd> uv(u.data(), n_);
  LiftProbe lift_at{*this, uv.head(nv_), coefficients(u), Eigen::Matrix<double, 4, Eigen::Dynamic>(4, nv_)};
  for (; r < rows_.size(); ++r) {
    if (rows_[r].kind == ConstraintKind::peak_lift_min)
      peak_lift_row(motion, lift_at, e, gradients, r);
    else
      duration_row(motion, lift_at, e, gradients, r);
  }
  return lift_at.status;
}

}  // namespace camopt::opt
