#include "camopt/kinematics/grid_refine.hpp"

#include <algorithm>
#include <cmath>

#include "camopt/core/error.hpp"

namespace camopt::kin {

namespace {

// j! / (j - k)!: the k-th derivative of t^j at t = 1 (0 for k > j)
double falling(int j, int k) {
  double f = 1.0;
  for (int i = 0; i < k; ++i) f *= j - i;
  return f;
}

// inverses of the end conditions' matrices M[k][j - n - 1] = j! / (j - k)!, k = 0..n,
// j = n + 1 .. 2n + 1 (the upper coefficients from the value and derivatives at t = 1)
constexpr double kInverse1[2][2] = {{3, -1}, {-2, 1}};
constexpr double kInverse2[3][3] = {{10, -4, 0.5}, {-15, 7, -1}, {6, -3, 0.5}};
constexpr double kInverse3[4][4] = {
    {35, -15, 2.5, -1.0 / 6}, {-84, 39, -7, 0.5}, {70, -34, 6.5, -0.5}, {-20, 10, -2, 1.0 / 6}};

double inverse(int n, int r, int k) {
  switch (n) {
    case 1:
      return kInverse1[r][k];
    case 2:
      return kInverse2[r][k];
    default:
      return kInverse3[r][k];
  }
}

constexpr int kSubintervals = 64;
}  // namespace

HermiteInterval HermiteInterval::fit(double x0, double x1, const GridJet& a, const GridJet& b, int order) {
  CAMOPT_ASSERT(x1 > x0 && order >= 0 && order <= 3);
  HermiteInterval p;
  p.x0_ = x0;
  p.h_ = x1 - x0;
  p.degree_ = 2 * order + 1;
  // lower coefficients from the left end: c_k = h^k a_k / k!
  double hk = 1.0, kf = 1.0;
  for (int k = 0; k <= order; ++k, hk *= p.h_, kf *= k) p.c_[k] = hk * a[k] / kf;
  // upper coefficients from the right end: M c_upper = h^k b_k - (lower part's k-th derivative at 1)
  double rhs[4];
  hk = 1.0;
  for (int k = 0; k <= order; ++k, hk *= p.h_) {
    rhs[k] = hk * b[k];
    for (int j = k; j <= order; ++j) rhs[k] -= falling(j, k) * p.c_[j];
  }
  if (order == 0) {
    p.c_[1] = rhs[0];
    return p;
  }
  for (int r = 0; r <= order; ++r) {
    double s = 0.0;
    for (int k = 0; k <= order; ++k) s += inverse(order, r, k) * rhs[k];
    p.c_[order + 1 + r] = s;
  }
  return p;
}

double HermiteInterval::poly(int k, double t) const {
  double s = 0.0;
  for (int j = degree_; j >= k; --j) s = s * t + falling(j, k) * c_[j];
  return s;
}

double HermiteInterval::derivative(int k, double x) const {
  return poly(k, (x - x0_) / h_) / std::pow(h_, k);
}

void HermiteInterval::solve(int k, double level, double lo, double hi, std::vector<double>& roots) const {
  roots.clear();
  if (k > degree_) return;
  const double scale = std::pow(h_, k);  // the level in the t variable
  auto f = [&](double t) { return poly(k, t) - level * scale; };
  const double t_lo = (lo - x0_) / h_, t_hi = (hi - x0_) / h_;
  double a = t_lo, fa = f(a);
  if (fa == 0.0) roots.push_back(x0_ + h_ * a);
  for (int i = 1; i <= kSubintervals; ++i) {
    const double b = t_lo + (t_hi - t_lo) * i / kSubintervals, fb = f(b);
    if (fb == 0.0) {
      roots.push_back(x0_ + h_ * b);
    } else if (fa != 0.0 && (fa < 0) != (fb < 0)) {
      // bracket [l, r] with f(l) f(r) < 0: newton from its midpoint, bisection when a step leaves it
      double l = a, r = b, fl = fa, t = 0.5 * (a + b);
      for (int it = 0; it < 100; ++it) {
        const double ft = f(t);
        if (ft == 0.0) break;
        if ((ft < 0) == (fl < 0)) l = t, fl = ft;
        else r = t;
        const double d = poly(k + 1, t);
        double next = d != 0.0 ? t - ft / d : 0.5 * (l + r);
        if (!(next > l && next < r)) next = 0.5 * (l + r);
        const bool converged = std::abs(next - t) <= 1e-16 * std::max(1.0, std::abs(t)) || r - l <= 1e-16;
        t = next;
        if (converged) break;
      }
      roots.push_back(x0_ + h_ * t);
    }
    a = b;
    fa = fb;
  }
}

void HermiteInterval::stationary(int k, std::vector<double>& at) const {
  solve(k + 1, 0.0, x0_, x0_ + h_, at);
  // roots at the ends are the grid points themselves
  std::erase_if(at, [&](double x) { return x <= x0_ || x >= x0_ + h_; });
}

double HermiteInterval::integral() const {
  double s = 0.0;
  for (int j = 0; j <= degree_; ++j) s += c_[j] / (j + 1);
  return s * h_;
}

}  // namespace camopt::kin
