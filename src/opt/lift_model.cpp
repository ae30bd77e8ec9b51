#include "camopt/opt/lift_model.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>

#include "camopt/core/error.hpp"

namespace camopt::opt {

namespace {

std::string num(double v) { return format_value(v, 10); }

bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

void validate(const EventSpec& spec) {
  if (!std::isfinite(spec.start_deg))
    throw InputError("event.start_deg = " + num(spec.start_deg) + " cam deg: must be finite");
  if (!std::isfinite(spec.duration_deg) || spec.duration_deg <= 0.0 || spec.duration_deg >= 360.0)
    throw InputError("event.duration_deg = " + num(spec.duration_deg) + " cam deg: must be in (0, 360)");
  for (int side = 0; side < 2; ++side) {
    const RampSpec& r = side == 0 ? spec.opening_ramp : spec.closing_ramp;
    const std::string p = side == 0 ? "event.opening_ramp." : "event.closing_ramp.";
    if (!finite_non_negative(r.height_mm))
      throw InputError(p + "height_mm = " + num(r.height_mm) + " mm: must be finite and >= 0");
    if (!finite_non_negative(r.length_deg))
      throw InputError(p + "length_deg = " + num(r.length_deg) + " cam deg: must be finite and >= 0");
    if ((r.height_mm > 0.0) != (r.length_deg > 0.0))
      throw InputError(p + "height_mm = " + num(r.height_mm) + " mm with length_deg = " + num(r.length_deg) +
                       " cam deg: a ramp needs both a height and a length, or neither");
  }
  const double ramps = spec.opening_ramp.length_deg + spec.closing_ramp.length_deg;
  if (ramps >= 0.8 * spec.duration_deg)
    throw InputError("event.opening_ramp.length_deg + event.closing_ramp.length_deg = " + num(ramps) +
                     " cam deg: the ramps must leave at least 20 % of event.duration_deg = " + num(spec.duration_deg) +
                     " cam deg for the main lift");
  if (!std::isfinite(spec.ramp_blend) || spec.ramp_blend <= 0.0 || spec.ramp_blend > 1.0)
    throw InputError("event.ramp_blend = " + num(spec.ramp_blend) + ": must be in (0, 1]");
  if (spec.degree < synthesis::BSplineAcceleration::kMinDegree || spec.degree > synthesis::BSplineAcceleration::kMaxDegree)
    throw InputError("event.degree = " + std::to_string(spec.degree) + ": must be in [" +
                     std::to_string(synthesis::BSplineAcceleration::kMinDegree) + ", " +
                     std::to_string(synthesis::BSplineAcceleration::kMaxDegree) + "]");
  // two end coefficients are zero and closure takes two more: at least 2 free variables
  const int need = std::max(spec.degree + 1, 6);
  if (spec.coefficients < need || spec.coefficients > 200)
    throw InputError("event.coefficients = " + std::to_string(spec.coefficients) + ": must be in [" +
                     std::to_string(need) + ", 200] for degree " + std::to_string(spec.degree));
}

AccelerationSplineLift AccelerationSplineLift::compile(const EventSpec& spec) {
  validate(spec);
  AccelerationSplineLift m;
  m.spec_ = spec;
  m.p_ = spec.degree;
  m.opening_ = synthesis::Ramp(spec.opening_ramp.height_mm, spec.opening_ramp.length_deg, spec.ramp_blend);
  m.closing_ = synthesis::Ramp(spec.closing_ramp.height_mm, spec.closing_ramp.length_deg, spec.ramp_blend);
  m.theta_a_ = spec.start_deg + spec.opening_ramp.length_deg;
  m.theta_b_ = spec.start_deg + spec.duration_deg - spec.closing_ramp.length_deg;
  const int n = spec.coefficients;
  m.t_acc_ = synthesis::clamped_uniform_knots(n, m.p_, m.theta_a_, m.theta_b_);
  const int nv = n - 2;
  m.acc_coef_.assign(nv, std::vector<double>(n, 0.0));
  m.vel_coef_.resize(nv);
  m.lift_coef_.resize(nv);
  m.jerk_coef_.resize(nv);
  for (int j = 0; j < nv; ++j) {
    auto& unit = m.acc_coef_[j];
    unit[j + 1] = 1.0;
    synthesis::bspline_integral(m.t_acc_, unit, m.p_, m.t_vel_, m.vel_coef_[j]);
    synthesis::bspline_integral(m.t_vel_, m.vel_coef_[j], m.p_ + 1, m.t_lift_, m.lift_coef_[j]);
    synthesis::bspline_derivative(m.t_acc_, unit, m.p_, m.t_jerk_, m.jerk_coef_[j]);
  }
  // closure at theta_b: L = H_c and L' = -v_c (the closing ramp runs backwards)
  const double ho = m.opening_.height_mm(), vo = m.opening_.velocity();
  const double hc = m.closing_.height_mm(), vc = m.closing_.velocity();
  m.closure_a_.resize(2, nv);
  for (int j = 0; j < nv; ++j) {
    m.closure_a_(0, j) = m.vel_coef_[j].back();   // velocity spline at the right end
    m.closure_a_(1, j) = m.lift_coef_[j].back();  // lift spline at the right end
  }
  m.closure_b_ = {-vc - vo, hc - ho - vo * (m.theta_b_ - m.theta_a_)};
  return m;
}

double AccelerationSplineLift::unwrap(double cam_deg) const noexcept {
  double d = std::fmod(cam_deg - spec_.start_deg, 360.0);
  if (d < 0.0) d += 360.0;
  return spec_.start_deg + d;
}

void AccelerationSplineLift::rows(double cam_deg, std::array<double, 4>& constant,
                                  Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> r) const {
  CAMOPT_ASSERT(r.cols() == variables());
  r.setZero();
  constant = {0.0, 0.0, 0.0, 0.0};
  const double th = unwrap(cam_deg);
  const double end = event_end_deg();
  if (th >= end) return;  // base circle
  if (th < theta_a_) {
    const synthesis::Motion m = opening_.evaluate(th - spec_.start_deg);
    constant = {m.lift, m.vel, m.acc, m.jerk};
    return;
  }
  if (th > theta_b_) {
    const synthesis::Motion m = closing_.evaluate(end - th);  // mirrored: odd derivatives change sign
    constant = {m.lift, -m.vel, m.acc, -m.jerk};
    return;
  }
  const double vo = opening_.velocity();
  constant = {opening_.height_mm() + vo * (th - theta_a_), vo, 0.0, 0.0};
  // only the p+1 basis functions whose support holds th have nonzero acceleration/jerk
  for (int j = 0; j < variables(); ++j) {
    r(0, j) = synthesis::bspline_value(t_lift_, lift_coef_[j], p_ + 2, th);
    r(1, j) = synthesis::bspline_value(t_vel_, vel_coef_[j], p_ + 1, th);
    const double lo = t_acc_[j + 1], hi = t_acc_[j + 1 + p_ + 1];
    if (th >= lo && th <= hi) {
      r(2, j) = synthesis::bspline_value(t_acc_, acc_coef_[j], p_, th);
      r(3, j) = synthesis::bspline_value(t_jerk_, jerk_coef_[j], p_ - 1, th);
    }
  }
}

synthesis::Motion AccelerationSplineLift::evaluate(std::span<const double> x, double cam_deg) const {
  CAMOPT_ASSERT(static_cast<int>(x.size()) == variables());
  std::array<double, 4> c{};
  Eigen::Matrix<double, 4, Eigen::Dynamic> r(4, variables());
  rows(cam_deg, c, r);
  const Eigen::Map<const Eigen::VectorXd> xv(x.data(), variables());
  const Eigen::Vector4d v = r * xv;
  return {c[0] + v(0), c[1] + v(1), c[2] + v(2), c[3] + v(3)};
}

std::vector<double> AccelerationSplineLift::fit(const std::function<double(double)>& lift, double step_deg) const {
  const int nv = variables();
  const int samples = std::max(2 * nv, static_cast<int>(std::ceil((theta_b_ - theta_a_) / step_deg)) + 1);
  Eigen::MatrixXd design(samples, nv);
  Eigen::VectorXd rhs(samples);
  std::array<double, 4> c{};
  Eigen::Matrix<double, 4, Eigen::Dynamic> r(4, nv);
  for (int i = 0; i < samples; ++i) {
    const double th = theta_a_ + (theta_b_ - theta_a_) * i / (samples - 1);
    rows(th, c, r);
    design.row(i) = r.row(0);
    rhs(i) = lift(th) - c[0];
  }
  // equality-constrained least squares by its kkt system
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(nv + 2, nv + 2);
  kkt.topLeftCorner(nv, nv) = design.transpose() * design;
  kkt.topRightCorner(nv, 2) = closure_a_.transpose();
  kkt.bottomLeftCorner(2, nv) = closure_a_;
  Eigen::VectorXd b(nv + 2);
  b.head(nv) = design.transpose() * rhs;
  b.tail(2) = closure_b_;
  const Eigen::VectorXd sol = kkt.fullPivLu().solve(b);
  return {sol.data(), sol.data() + nv};
}

}  // namespace camopt::opt
