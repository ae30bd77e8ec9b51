// acceleration designed as a b-spline: closure by the least change of the control values,
// exact integration to velocity and lift [deboor ch. X].
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "camopt/core/error.hpp"
#include "camopt/synthesis/lift_law.hpp"

namespace camopt::synthesis {

namespace {

std::string num(double v) { return format_value(v, 10); }

}  // namespace

std::vector<double> clamped_uniform_knots(int n, int p, double a, double b) {
  std::vector<double> t(static_cast<std::size_t>(n + p + 1));
  const int spans = n - p;
  for (int i = 0; i < n + p + 1; ++i) {
    const int j = std::clamp(i - p, 0, spans);
    t[static_cast<std::size_t>(i)] = j == spans ? b : a + (b - a) * static_cast<double>(j) / spans;
  }
  return t;
}

void bspline_integral(const std::vector<double>& t, const std::vector<double>& c, int p, std::vector<double>& t_out,
                      std::vector<double>& d_out) {
  t_out.clear();
  t_out.push_back(t.front());
  t_out.insert(t_out.end(), t.begin(), t.end());
  t_out.push_back(t.back());
  d_out.assign(c.size() + 1, 0.0);
  for (std::size_t i = 0; i < c.size(); ++i)
    d_out[i + 1] = d_out[i] + c[i] * (t[i + static_cast<std::size_t>(p) + 1] - t[i]) / (p + 1);
}

void bspline_derivative(const std::vector<double>& t, const std::vector<double>& c, int p, std::vector<double>& t_out,
                        std::vector<double>& g_out) {
  t_out.assign(t.begin() + 1, t.end() - 1);
  g_out.assign(c.size() - 1, 0.0);
  for (std::size_t i = 0; i + 1 < c.size(); ++i)
    g_out[i] = p * (c[i + 1] - c[i]) / (t[i + static_cast<std::size_t>(p) + 1] - t[i + 1]);
}

double bspline_value(std::span<const double> t, std::span<const double> c, int p, double x) noexcept {
  const int n = static_cast<int>(c.size());
  // span k with t_k <= x < t_{k+1}, clamped to [p, n-1]
  const auto first = t.begin() + p + 1, last = t.begin() + n;
  const int k = static_cast<int>(std::upper_bound(first, last, x) - t.begin()) - 1;
  std::array<double, 8> d{};
  for (int j = 0; j <= p; ++j) d[static_cast<std::size_t>(j)] = c[static_cast<std::size_t>(j + k - p)];
  for (int r = 1; r <= p; ++r) {
    for (int j = p; j >= r; --j) {
      const double left = t[static_cast<std::size_t>(j + k - p)];
      const double right = t[static_cast<std::size_t>(j + 1 + k - r)];
      const double alpha = (x - left) / (right - left);
      d[static_cast<std::size_t>(j)] =
          (1.0 - alpha) * d[static_cast<std::size_t>(j - 1)] + alpha * d[static_cast<std::size_t>(j)];
    }
  }
  return d[static_cast<std::size_t>(p)];
}

BSplineAcceleration::BSplineAcceleration(double height_mm, double duration_deg,
                                         std::span<const double> control_values, int degree)
    : RiseLaw(height_mm, duration_deg), p_(degree) {
  if (degree < kMinDegree || degree > kMaxDegree)
    throw InputError("bspline_degree = " + std::to_string(degree) + ": must be in [" + std::to_string(kMinDegree) +
                     ", " + std::to_string(kMaxDegree) + "]");
  const int n = static_cast<int>(control_values.size());
  const int need = std::max(degree + 1, 4);
  if (n < need)
    throw InputError("acc_controls: " + std::to_string(n) + " values: a degree-" + std::to_string(degree) +
                     " acceleration b-spline needs at least " + std::to_string(need));
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(control_values[static_cast<std::size_t>(i)]))
      throw InputError("acc_controls: value " + std::to_string(i + 1) + " = " +
                       num(control_values[static_cast<std::size_t>(i)]) + ": must be finite");

  t_ = clamped_uniform_knots(n, p_);
  const Eigen::Map<const Eigen::VectorXd> given(control_values.data(), n);

  // closure constraints A c = 0: c_0 = 0, c_{n-1} = 0, sum_i c_i w_i = 0 with
  // w_i = int N_i = (t_{i+p+1} - t_i) / (p+1)
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3, n);
  a(0, 0) = 1.0;
  a(1, n - 1) = 1.0;
  for (int i = 0; i < n; ++i)
    a(2, i) = (t_[static_cast<std::size_t>(i + p_ + 1)] - t_[static_cast<std::size_t>(i)]) / (p_ + 1);
  // least change: c = given - A^T (A A^T)^{-1} A given (projection onto the null space of A)
  const Eigen::Matrix3d gram = a * a.transpose();
  const Eigen::Vector3d lambda = gram.ldlt().solve(a * given);
  const Eigen::VectorXd delta = a.transpose() * lambda;
  Eigen::VectorXd closed = given - delta;
  closed(0) = 0.0;  // exact, not 1e-17
  closed(n - 1) = 0.0;
  const double given_norm = given.norm();
  change_ = given_norm > 0.0 ? delta.norm() / given_norm : 0.0;

  // rise of the closed shape: y(1) = sum_i c_i m_i with m_i the second integral of N_i at 1
  c_.assign(closed.data(), closed.data() + n);
  bspline_integral(t_, c_, p_, tv_, d_);
  bspline_integral(tv_, d_, p_ + 1, ty_, e_);
  const double rise = e_.back();
  double magnitude = 0.0;  // the rise if every value pushed the same way
  for (int i = 0; i < n; ++i) magnitude += std::abs(closed(i)) * a(2, i);
  if (!(rise > 1e-9 * magnitude) || magnitude == 0.0)
    throw InputError("acc_controls: after closure (zero acceleration at both ends, zero velocity at the end) the "
                     "values give a net rise of " +
                     num(rise) +
                     ": the acceleration shape must rise, i.e. be positive early in the flank and negative late");

  // scale to the unit rise and build the exact integrals and the derivative
  scale_ = 1.0 / rise;
  for (double& v : c_) v *= scale_;
  bspline_integral(t_, c_, p_, tv_, d_);
  bspline_integral(tv_, d_, p_ + 1, ty_, e_);
  bspline_derivative(t_, c_, p_, tj_, g_);
}

std::vector<double> BSplineAcceleration::breakpoints() const {
  std::vector<double> b;
  for (double k : t_)
    if (k > 0.0 && k < 1.0 && (b.empty() || b.back() != k)) b.push_back(k);
  return b;
}

Motion BSplineAcceleration::unit_inside(double x) const noexcept {
  return {bspline_value(ty_, e_, p_ + 2, x), bspline_value(tv_, d_, p_ + 1, x), bspline_value(t_, c_, p_, x),
          bspline_value(tj_, g_, p_ - 1, x)};
}

}  // namespace camopt::synthesis
