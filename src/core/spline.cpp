#include "camopt/core/spline.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "camopt/core/bspline_basis.hpp"
#include "camopt/core/error.hpp"

namespace camopt {

namespace {

constexpr int kDegree = detail::PiecewiseQuintic::degree;

// falling factorial m! / (m - k)! for the derivative of s^m
constexpr std::array<std::array<double, 6>, 6> kFalling = [] {
  std::array<std::array<double, 6>, 6> f{};
  for (int m = 0; m <= 5; ++m) {
    double v = 1.0;
    for (int k = 0; k <= m; ++k) {
      f[k][m] = v;
      v *= m - k;
    }
  }
  return f;
}();

constexpr std::array<double, 6> kInvFactorial = {1.0,       1.0,        1.0 / 2.0,
                                                 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0};

std::string fmt(double v) { return format_value(v, 17); }

// size, finiteness and strict monotonicity of the data: an InputError naming the point
void check_data(const char* who, std::span<const double> x, std::span<const double> y,
                std::size_t min_points) {
  CAMOPT_THROW_UNLESS(x.size() == y.size(), std::string(who) + ": x has " + std::to_string(x.size()) +
                                                " points but y has " + std::to_string(y.size()));
  CAMOPT_THROW_UNLESS(x.size() >= min_points, std::string(who) + ": " + std::to_string(x.size()) +
                                                  " points given, at least " + std::to_string(min_points) +
                                                  " required");
  for (std::size_t i = 0; i < x.size(); ++i) {
    CAMOPT_THROW_UNLESS(std::isfinite(x[i]) && std::isfinite(y[i]),
                        std::string(who) + ": point " + std::to_string(i) + " (" + fmt(x[i]) + ", " + fmt(y[i]) +
                            ") is not finite");
    CAMOPT_THROW_UNLESS(i == 0 || x[i] > x[i - 1],
                        std::string(who) + ": x[" + std::to_string(i) + "] = " + fmt(x[i]) +
                            " is not greater than x[" + std::to_string(i - 1) + "] = " +
                            fmt(x[i - 1]) + " (x must be strictly increasing)");
  }
}

// a collocation system that cannot be solved: the data's x values are too close together
// for their spread (the data is at fault, not the solve)
[[noreturn]] void singular_collocation(const char* who) {
  throw InputError(std::string(who) + ": singular collocation system: x values nearly coincide for their spread");
}

Eigen::VectorXd solve(const char* who, const Eigen::SparseMatrix<double>& A,
                      const Eigen::VectorXd& b) {
  if (A.rows() <= 64) {
    // small systems: dense LU with partial pivoting (the sparse LU's ordering and symbolic
    // analysis cost more than the factorisation itself at this size)
    const Eigen::PartialPivLU<Eigen::MatrixXd> dense{Eigen::MatrixXd(A)};
    const auto pivots = dense.matrixLU().diagonal().cwiseAbs();
    if (!(pivots.minCoeff() > 1e-14 * pivots.maxCoeff())) singular_collocation(who);
    Eigen::VectorXd c = dense.solve(b);
    if (!c.allFinite()) singular_collocation(who);
    return c;
  }
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success) singular_collocation(who);
  Eigen::VectorXd c = lu.solve(b);
  if (lu.info() != Eigen::Success || !c.allFinite()) singular_collocation(who);
  return c;
}

// the cyclic pentadiagonal system below (band[i][d] at column (i - 2 + d) mod n) holds at x
// to round-off: else the sparse LU (with its messages) decides
bool cyclic_residual_ok(const std::vector<std::array<double, 5>>& band, const Eigen::VectorXd& b,
                        const Eigen::VectorXd& x) {
  const int n = static_cast<int>(band.size());
  if (!x.allFinite()) return false;
  double residual = 0.0, scale = 0.0;
  for (int i = 0; i < n; ++i) {
    const bool wraps = i < 2 || i >= n - 2;
    double res = -b[i], size = std::abs(b[i]);
    for (int d = 0; d < 5; ++d) {
      const double term =
          band[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)] * x[wraps ? ((i - 2 + d) % n + n) % n : i - 2 + d];
      res += term;
      size += std::abs(term);
    }
    residual = std::max(residual, std::abs(res));
    scale = std::max(scale, size);
  }
  return residual <= 1e-12 * scale;
}

// a cyclic pentadiagonal system: row i holds band[i][d] at column (i - 2 + d) mod n, d = 0..4
// (n >= 6). Block elimination: the first N = n - 4 unknowns form a plain pentadiagonal
// block A11 (no wrap), solved by banded LU without pivoting (stable: it is a contiguous
// block of a totally positive b-spline collocation matrix, de Boor, "A Practical Guide to
// Splines", ch. XIII), the last 4 through their 4 x 4 Schur complement (partial pivoting).
// O(n) against the general sparse LU's ordering and symbolic analysis. Returns false when a
// pivot vanishes or the residual is not at round-off; the caller then uses the sparse LU.
bool solve_cyclic_pentadiagonal(const std::vector<std::array<double, 5>>& band, const Eigen::VectorXd& b,
                                Eigen::VectorXd& x) {
  constexpr int m = 4;
  const int n = static_cast<int>(band.size());
  const int N = n - m;
  // column of band[i][d] (rows near the ends wrap)
  auto column = [n](int i, int d) { return ((i - 2 + d) % n + n) % n; };
  // A11 (band, N rows), [b1 | A12] (N x 5, column-major: rhs[c * N + i]), A21 (4 x N), A22 (4 x 4)
  std::vector<std::array<double, 5>> lu(band.begin(), band.begin() + N);
  std::vector<double> rhs(static_cast<std::size_t>(5 * N), 0.0);
  Eigen::Matrix<double, m, Eigen::Dynamic> a21 = Eigen::Matrix<double, m, Eigen::Dynamic>::Zero(m, N);
  Eigen::Matrix4d a22 = Eigen::Matrix4d::Zero();
  // rows of A11 whose band wraps past column N (the first two and the last two)
  for (int i : {0, 1, N - 2, N - 1})
    for (int d = 0; d < 5; ++d) {
      const int k = column(i, d);
      if (k < N) continue;
      rhs[static_cast<std::size_t>((1 + k - N) * N + i)] = band[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)];
      lu[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)] = 0.0;
    }
  for (int i = N; i < n; ++i)
    for (int d = 0; d < 5; ++d) {
      const int k = column(i, d);
      const double v = band[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)];
      if (k < N) a21(i - N, k) += v;
      else a22(i - N, k - N) += v;
    }
  for (int i = 0; i < N; ++i) rhs[static_cast<std::size_t>(i)] = b[i];
  double* const r = rhs.data();
  // banded LU (no pivoting), applied to the 5 right-hand sides as it goes
  for (int i = 0; i < N; ++i) {
    const double pivot = lu[static_cast<std::size_t>(i)][2];
    if (!(std::abs(pivot) > 0.0) || !std::isfinite(pivot)) return false;
    for (int j = i + 1; j <= std::min(i + 2, N - 1); ++j) {
      auto& row = lu[static_cast<std::size_t>(j)];
      const double l = row[static_cast<std::size_t>(2 - (j - i))] / pivot;
      if (l == 0.0) continue;
      for (int c = i; c <= std::min(i + 2, N - 1); ++c)
        row[static_cast<std::size_t>(c - j + 2)] -= l * lu[static_cast<std::size_t>(i)][static_cast<std::size_t>(c - i + 2)];
      for (int c = 0; c < 5; ++c) r[c * N + j] -= l * r[c * N + i];
    }
  }
  for (int i = N - 1; i >= 0; --i) {
    const auto& row = lu[static_cast<std::size_t>(i)];
    for (int c = i + 1; c <= std::min(i + 2, N - 1); ++c)
      for (int q = 0; q < 5; ++q) r[q * N + i] -= row[static_cast<std::size_t>(c - i + 2)] * r[q * N + c];
    for (int q = 0; q < 5; ++q) r[q * N + i] /= row[2];
  }
  // Schur complement S = A22 - A21 A11^-1 A12; x2 = S^-1 (b2 - A21 A11^-1 b1)
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 5>> solved(r, N, 5);
  const Eigen::Matrix4d schur = a22 - a21 * solved.rightCols<4>();
  Eigen::Vector4d b2;
  for (int i = 0; i < m; ++i) b2[i] = b[N + i];
  b2 -= a21 * solved.col(0);
  const Eigen::PartialPivLU<Eigen::Matrix4d> s_lu(schur);
  const Eigen::Vector4d x2 = s_lu.solve(b2);
  x.resize(n);
  x.head(N) = solved.col(0) - solved.rightCols<4>() * x2;
  x.tail(m) = x2;
  return cyclic_residual_ok(band, b, x);
}

}  // namespace

// recursive filtering (Unser, Aldroubi & Eden, IEEE Trans. Signal Processing 41(2), 1993):
// the symbol of (1, 26, 66, 26, 1) / 120 factors as (1 - l z)(1 - l / z)(1 - m z)(1 - m / z)
// / (120 l m), l and m the roots of z^4 + 26 z^3 + 66 z^2 + 26 z + 1 inside the unit circle,
// so x is 120 l m times a causal and an anticausal first-order recursion per root, each
// started from its periodic sum (64 terms reach |l|^64 = 4e-24). O(n), about 20 flops per
// row; PeriodicSpline::interpolate checks the residual.
void detail::solve_uniform_quintic_cyclic(std::span<const double> b, std::span<double> x) {
  // z + 1/z = w = -13 -+ sqrt(105) (the quartic is palindromic); the root inside the unit
  // circle as 2 / (w - sqrt(w^2 - 4)), free of cancellation
  static const double w1 = -13.0 + std::sqrt(105.0), w2 = -13.0 - std::sqrt(105.0);
  static const double roots[2] = {2.0 / (w1 - std::sqrt(w1 * w1 - 4)), 2.0 / (w2 - std::sqrt(w2 * w2 - 4))};
  // the gain 120 l m, as (1 - l)^2 (1 - m)^2 (the symbol at z = 1 is 1): a constant then
  // passes exactly whatever the roots' last bits
  static const double gain = (1 - roots[0]) * (1 - roots[0]) * (1 - roots[1]) * (1 - roots[1]);
  const int n = static_cast<int>(b.size());
  CAMOPT_ASSERT(x.size() == b.size() && n >= 1);
  for (int k = 0; k < n; ++k) x[k] = b[k] * gain;
  const int terms = std::min(n, 64);
  for (const double z : roots) {
    const double periodic = 1.0 / (1.0 - std::pow(z, n));
    // causal: u_k = x_k + z u_(k-1), u_0 = sum_m z^m x_(-m) / (1 - z^n)
    double sum = 0.0, power = 1.0;
    for (int m = 0; m < terms; ++m, power *= z) sum += power * x[(n - m) % n];
    x[0] = sum * periodic;
    for (int k = 1; k < n; ++k) x[k] += z * x[k - 1];
    // anticausal: w_k = u_k + z w_(k+1), w_(n-1) = sum_m z^m u_(n-1+m) / (1 - z^n)
    sum = 0.0, power = 1.0;
    for (int m = 0; m < terms; ++m, power *= z) sum += power * x[(n - 1 + m) % n];
    x[n - 1] = sum * periodic;
    for (int k = n - 2; k >= 0; --k) x[k] += z * x[k + 1];
  }
}

namespace {

// A x = b for a band matrix (kl sub-, ku super-diagonals) by gaussian elimination with
// partial pivoting (Golub & Van Loan, "Matrix Computations", 4th ed., sec. 4.3.5): the row
// interchanges widen U to kl + ku super-diagonals, so each row keeps columns i - kl ..
// i + kl + ku: band[i * w + (j - i + kl)], w = 2 kl + ku + 1. O(n kl (kl + ku)). b is
// overwritten by x. false when a pivot is below 1e-14 of the largest (singular).
bool solve_banded(int n, int kl, int ku, std::vector<double>& band, Eigen::VectorXd& b) {
  const int w = 2 * kl + ku + 1;
  auto at = [&](int i, int j) -> double& { return band[static_cast<std::size_t>(i * w + (j - i + kl))]; };
  double largest = 0.0, smallest = INFINITY;
  for (int k = 0; k < n; ++k) {
    const int last_row = std::min(k + kl, n - 1), last_col = std::min(k + kl + ku, n - 1);
    int pivot = k;
    for (int i = k + 1; i <= last_row; ++i)
      if (std::abs(at(i, k)) > std::abs(at(pivot, k))) pivot = i;
    if (pivot != k) {
      for (int j = k; j <= last_col; ++j) std::swap(at(k, j), at(pivot, j));
      std::swap(b[k], b[pivot]);
    }
    const double d = at(k, k);
    largest = std::max(largest, std::abs(d));
    smallest = std::min(smallest, std::abs(d));
    if (!(d != 0.0) || !std::isfinite(d)) return false;
    for (int i = k + 1; i <= last_row; ++i) {
      const double l = at(i, k) / d;
      if (l == 0.0) continue;
      for (int j = k + 1; j <= last_col; ++j) at(i, j) -= l * at(k, j);
      b[i] -= l * b[k];
    }
  }
  if (!(smallest > 1e-14 * largest)) return false;
  for (int k = n - 1; k >= 0; --k) {
    double v = b[k];
    for (int j = k + 1; j <= std::min(k + kl + ku, n - 1); ++j) v -= at(k, j) * b[j];
    b[k] = v / at(k, k);
  }
  return b.allFinite();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// shared piecewise taylor form

void detail::PiecewiseQuintic::init_lookup(double x_end) {
  const std::size_t pieces = coef_.size();
  inv_h_ = 0.0;
  inv_w_ = 0.0;
  bucket_.clear();
  // uniform if every piece length (except a periodic closing piece) matches the first
  const std::size_t last = std::min(pieces, x_.size() - 1);  // spacings x_[i+1] - x_[i]
  const double h = x_[1] - x_[0];
  bool uniform = true;
  for (std::size_t i = 1; i < last && uniform; ++i) {
    uniform = std::abs((x_[i + 1] - x_[i]) - h) <= 1e-9 * h;
  }
  if (uniform) {
    inv_h_ = 1.0 / h;
    return;
  }
  // one bucket per piece; the edge of bucket b is x0 + b w
  const double w = (x_end - x_.front()) / static_cast<double>(pieces);
  inv_w_ = 1.0 / w;
  bucket_.resize(pieces + 1);
  std::size_t i = 0;
  for (std::size_t b = 0; b <= pieces; ++b) {
    const double edge = x_.front() + static_cast<double>(b) * w;
    while (i + 1 < pieces && x_[i + 1] <= edge) ++i;
    bucket_[b] = static_cast<std::uint32_t>(i);
  }
}

std::size_t detail::PiecewiseQuintic::locate(double x) const noexcept {
  const std::size_t last = coef_.size() - 1;
  // first guess from floor((x - x0) / width), clamped
  const double r = (x - x_[0]) * (inv_h_ > 0.0 ? inv_h_ : inv_w_);
  std::size_t g = 0;
  if (r >= static_cast<double>(last)) {
    g = last;
  } else if (r > 0.0) {
    g = static_cast<std::size_t>(r);
  }
  std::size_t i = g;
  if (inv_h_ <= 0.0) {
    // pieces bucket_[g] .. bucket_[g + 1] hold the bucket; binary search if it is crowded
    std::size_t lo = bucket_[g];
    const std::size_t hi = bucket_[g + 1];
    if (hi - lo > 8) {
      const auto first = x_.begin() + static_cast<std::ptrdiff_t>(lo) + 1;
      lo += static_cast<std::size_t>(
          std::upper_bound(first, x_.begin() + static_cast<std::ptrdiff_t>(hi) + 1, x) - first);
    }
    i = lo;
  }
  // exact placement (also absorbs rounding in the guess)
  while (i < last && x >= x_[i + 1]) ++i;
  while (i > 0 && x < x_[i]) --i;
  return i;
}

namespace {
// f^(k)(s) = sum_{m=k}^{5} m!/(m-k)! a_m s^(m-k), by horner (k fixed: the loop unrolls and
// the unit factors of k = 0 fold away)
template <int K>
double piece_derivative(const std::array<double, 6>& a, double s) noexcept {
  double v = kFalling[K][5] * a[5];
  for (int m = 4; m >= K; --m) v = v * s + kFalling[K][m] * a[m];
  return v;
}
}  // namespace

void detail::PiecewiseQuintic::evaluate_piece(std::size_t i, double s, int max_order,
                                              double* out) const noexcept {
  const std::array<double, 6>& a = coef_[i];
  switch (max_order) {
    case 5: out[5] = piece_derivative<5>(a, s); [[fallthrough]];
    case 4: out[4] = piece_derivative<4>(a, s); [[fallthrough]];
    case 3: out[3] = piece_derivative<3>(a, s); [[fallthrough]];
    case 2: out[2] = piece_derivative<2>(a, s); [[fallthrough]];
    case 1: out[1] = piece_derivative<1>(a, s); [[fallthrough]];
    default: out[0] = piece_derivative<0>(a, s);
  }
}

void detail::PiecewiseQuintic::value_range(double x_end, double& lo, double& hi) const noexcept {
  lo = hi = coef_.front()[0];
  for (std::size_t i = 0; i < coef_.size(); ++i) {
    const double h = (i + 1 < x_.size() ? x_[i + 1] : x_end) - x_[i];
    double right[2];
    evaluate_piece(i, h, 1, right);
    lo = std::min({lo, coef_[i][0], right[0]});
    hi = std::max({hi, coef_[i][0], right[0]});
    const double d0 = coef_[i][1], d1 = right[1];
    // a slope that changes sign: an extremum inside, beyond the ends by about max |f'| h / 4
    // at most (skipped below 1e-12 of the value: a spline's ringing on a base circle)
    if (!(d0 * d1 < 0) || std::max(std::abs(d0), std::abs(d1)) * h <= 1e-12 * (std::abs(coef_[i][0]) + 1.0)) continue;
    double a = 0.0, b = h, s = h * d0 / (d0 - d1);  // bracket [a, b] of the slope's root
    for (int it = 0; it < 60; ++it) {
      double f[3];
      evaluate_piece(i, s, 2, f);
      ((f[1] > 0) == (d0 > 0) ? a : b) = s;
      double next = f[2] != 0.0 ? s - f[1] / f[2] : 0.5 * (a + b);
      if (!(next > a && next < b)) next = 0.5 * (a + b);
      // the value at the extremum is quadratic in the place: 1e-9 h of it is round-off
      const bool done = std::abs(next - s) <= 1e-9 * h;
      s = next;
      if (done) break;
    }
    double v;
    evaluate_piece(i, s, 0, &v);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
}

double detail::PiecewiseQuintic::integrate_piece(std::size_t i, double s) const noexcept {
  const std::array<double, 6>& a = coef_[i];
  // int_0^s sum a_m u^m du = sum a_m s^(m+1) / (m+1)
  double v = a[5] / 6.0;
  for (int m = 4; m >= 0; --m) v = v * s + a[m] / (m + 1);
  return v * s;
}

// ---------------------------------------------------------------------------------------
// periodic spline

PeriodicSpline PeriodicSpline::interpolate(std::span<const double> x, std::span<const double> y,
                                           double period) {
  return interpolate_periodic(x, y, period, true);
}

PeriodicSpline PeriodicSpline::interpolate_by_sparse_lu(std::span<const double> x, std::span<const double> y,
                                                        double period) {
  return interpolate_periodic(x, y, period, false);
}

PeriodicSpline PeriodicSpline::interpolate_periodic(std::span<const double> x, std::span<const double> y,
                                                    double period, bool banded) {
  constexpr const char* who = "PeriodicSpline::interpolate";
  check_data(who, x, y, 6);
  CAMOPT_THROW_UNLESS(std::isfinite(period) && x.back() - x.front() < period,
                      std::string(who) + ": period = " + fmt(period) +
                          " must exceed the data span x.back() - x.front() = " + fmt(x.back() - x.front()));
  const int n = static_cast<int>(x.size());
  constexpr int p = kDegree;

  // periodic knots t_m = x_{m mod n} + floor(m / n) * period for m = -p .. n + p,
  // stored as T[m + p]
  std::vector<double> T(static_cast<std::size_t>(n + 2 * p + 1));
  for (int m = -p; m <= n + p; ++m) {
    const int q = (m % n + n) % n;
    const int wraps = (m - q) / n;
    T[static_cast<std::size_t>(m + p)] = x[static_cast<std::size_t>(q)] + wraps * period;
  }
  const auto wrap = [n](int j) { return (j % n + n) % n; };

  // collocation at the knots: row i uses b-splines i-5 .. i (b_i(t_i) = 0), so with the
  // unknowns shifted by 3 (b-spline j -> column j + 3) the system is cyclic pentadiagonal
  // (the basis triangle at each knot is kept for the taylor coefficients below:
  // triangle[i][q (q + 1) / 2 + r] = N_{i-q+r, q}(t_i))
  // evenly spaced data (to round-off of the period: x_i = x_0 + i period / n, as every
  // sampled table in camopt) share one triangle, that of the uniform knots
  bool uniform = true;
  for (int i = 0; i < n && uniform; ++i)
    uniform = std::abs(x[static_cast<std::size_t>(i)] - (x.front() + i * (period / n))) <= 1e-13 * period;
  const int triangles = uniform ? 1 : n;
  std::vector<std::array<double, (p + 1) * (p + 2) / 2>> triangle(static_cast<std::size_t>(triangles));
  std::vector<std::array<double, 5>> band(static_cast<std::size_t>(n));
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    if (i < triangles) {
      double ndu[p + 1][p + 1];
      if (uniform) {
        double knots[2 * p + 1];
        for (int m = 0; m <= 2 * p; ++m) knots[m] = (m - p) * (period / n);
        bspline_basis_triangle(knots, p, p, 0.0, ndu);
      } else {
        bspline_basis_triangle(T.data(), i + p, p, T[static_cast<std::size_t>(i + p)], ndu);
      }
      CAMOPT_ASSERT(ndu[p][p] == 0.0);
      auto& tri = triangle[static_cast<std::size_t>(i)];
      for (int q = 0; q <= p; ++q)
        for (int r = 0; r <= q; ++r) tri[static_cast<std::size_t>(q * (q + 1) / 2 + r)] = ndu[r][q];
    }
    const auto& tri = triangle[static_cast<std::size_t>(uniform ? 0 : i)];
    for (int r = 0; r < p; ++r)
      band[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)] = tri[static_cast<std::size_t>(p * (p + 1) / 2 + r)];
    b[i] = y[static_cast<std::size_t>(i)];
  }
  Eigen::VectorXd shifted, c(n);
  bool solved = false;
  if (banded && uniform) {
    shifted.resize(n);
    detail::solve_uniform_quintic_cyclic({b.data(), static_cast<std::size_t>(n)},
                                         {shifted.data(), static_cast<std::size_t>(n)});
    solved = cyclic_residual_ok(band, b, shifted);
  }
  if (solved || (banded && solve_cyclic_pentadiagonal(band, b, shifted))) {
    for (int j = 0; j < n; ++j) c[j] = shifted[wrap(j + 3)];
  } else {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(n) * p);
    for (int i = 0; i < n; ++i)
      for (int r = 0; r < p; ++r) {
        const double v = band[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)];
        if (v != 0.0) triplets.emplace_back(i, wrap(i - p + r), v);
      }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(triplets.begin(), triplets.end());  // sums duplicates
    c = solve(who, A, b);
  }

  // taylor coefficients at the left end of each piece. The k-th derivative is a spline of
  // degree p - k with the differenced coefficients (The NURBS Book, eq. 3.8)
  //   c^(k)_j = (p - k + 1) (c^(k-1)_j - c^(k-1)_{j-1}) / (t_{j+p-k+1} - t_j),
  // so f^(k)(t_i) = sum_r N_{i-q+r, q}(t_i) c^(k)_{i-q+r}, q = p - k: one basis triangle per
  // knot instead of the basis derivatives
  auto knot = [&](int m) { return T[static_cast<std::size_t>(m + p)]; };  // t_m, m = -p .. n + p
  std::vector<std::array<double, p + 1>> diff(static_cast<std::size_t>(n));  // [j mod n][k] = c^(k)_j
  for (int j = 0; j < n; ++j) diff[static_cast<std::size_t>(j)][0] = c[j];
  for (int k = 1; k <= p; ++k) {
    const int q = p - k;
    // c^(k)_j for j = 0 .. n - 1 from c^(k-1)_j and c^(k-1)_{j-1} (periodic in j); the knot
    // difference t_{j+q+1} - t_j is periodic too (it only needs j in 0 .. n - 1, j - 1 wraps)
    double prev = diff[static_cast<std::size_t>(n - 1)][static_cast<std::size_t>(k - 1)];
    for (int j = 0; j < n; ++j) {
      const double cur = diff[static_cast<std::size_t>(j)][static_cast<std::size_t>(k - 1)];
      diff[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)] = (q + 1) * (cur - prev) / (knot(j + q + 1) - knot(j));
      prev = cur;
    }
  }
  PeriodicSpline s;
  s.period_ = period;
  s.x_.assign(x.begin(), x.end());
  s.coef_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto& tri = triangle[static_cast<std::size_t>(uniform ? 0 : i)];
    for (int k = 0; k <= p; ++k) {
      const int q = p - k;
      double v = 0.0;
      for (int r = 0; r <= q; ++r) {
        const int j = i - q + r;  // in i - p .. i: wraps below 0 only (no integer division here)
        v += tri[static_cast<std::size_t>(q * (q + 1) / 2 + r)] * diff[static_cast<std::size_t>(j < 0 ? j + n : j)][static_cast<std::size_t>(k)];
      }
      s.coef_[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = v * kInvFactorial[k];
    }
  }
  s.init_lookup(x.front() + period);
  return s;
}

void PeriodicSpline::evaluate(double x, int max_order, double* out) const noexcept {
  CAMOPT_ASSERT_MSG(!x_.empty(), "evaluate on an empty PeriodicSpline");
  CAMOPT_ASSERT(max_order >= 0 && max_order <= degree);
  const double x0 = x_.front();
  // wrap into [x0, x0 + period) (fast path: already there)
  if (!(x >= x0 && x < x0 + period_)) x -= std::floor((x - x0) / period_) * period_;
  const std::size_t i = locate(x);
  evaluate_piece(i, x - x_[i], max_order, out);
}

// ---------------------------------------------------------------------------------------
// natural spline

Spline Spline::interpolate(std::span<const double> x, std::span<const double> y) {
  constexpr const char* who = "Spline::interpolate";
  check_data(who, x, y, 3);
  const int n = static_cast<int>(x.size());
  constexpr int p = kDegree;
  const int nb = n + 4;  // number of b-splines

  // clamped knots: x0 (p+1 times), x1 .. x_{n-2}, x_{n-1} (p+1 times)
  std::vector<double> U;
  U.reserve(static_cast<std::size_t>(n + 2 * p));
  for (int k = 0; k < p; ++k) U.push_back(x.front());
  U.insert(U.end(), x.begin(), x.end());
  for (int k = 0; k < p; ++k) U.push_back(x.back());
  const int last_span = n + p - 2;  // piece n-2: [x_{n-2}, x_{n-1}]

  // rows: f''' = f'''' = 0 at x0 (scaled by h^k of the end piece for conditioning), the
  // interpolation at every site, then f''' = f'''' = 0 at xn: in this order the system is
  // banded (row r holds columns r - 5 .. r + 5), solved by banded elimination with pivoting
  constexpr int kl = p, ku = p;
  constexpr int w = 2 * kl + ku + 1;
  std::vector<double> band(static_cast<std::size_t>(nb * w), 0.0);
  auto put = [&](int r, int col, double v) {
    CAMOPT_ASSERT(col - r >= -kl && col - r <= ku);
    band[static_cast<std::size_t>(r * w + (col - r + kl))] = v;
  };
  double ders[6][6];
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nb);
  const double h_first = x[1] - x[0];
  const double h_last = x[static_cast<std::size_t>(n - 1)] - x[static_cast<std::size_t>(n - 2)];
  auto end_rows = [&](int span, int row) {
    const bool first = span == p;
    const double h = first ? h_first : h_last;
    bspline_basis_derivatives(U.data(), span, p, first ? x.front() : x.back(), 4, ders);
    for (int k = 3; k <= 4; ++k, ++row) {
      const double scale = std::pow(h, k);
      for (int r = 0; r <= p; ++r) put(row, span - p + r, ders[k][r] * scale);
    }
  };
  end_rows(p, 0);
  // the basis triangle at every knot but the last (kept for the taylor coefficients below:
  // triangle[i][q (q + 1) / 2 + r] = N_{i+p-q+r, q}(x_i), span i + p)
  std::vector<std::array<double, (p + 1) * (p + 2) / 2>> triangle(static_cast<std::size_t>(n - 1));
  for (int i = 0; i < n; ++i) {
    const int span = std::min(i + p, last_span);
    if (i + 1 < n) {
      double ndu[p + 1][p + 1];
      bspline_basis_triangle(U.data(), span, p, x[static_cast<std::size_t>(i)], ndu);
      auto& tri = triangle[static_cast<std::size_t>(i)];
      for (int q = 0; q <= p; ++q)
        for (int r = 0; r <= q; ++r) tri[static_cast<std::size_t>(q * (q + 1) / 2 + r)] = ndu[r][q];
      for (int r = 0; r <= p; ++r) ders[0][r] = ndu[r][p];
    } else {
      bspline_basis_derivatives(U.data(), span, p, x[static_cast<std::size_t>(i)], 0, ders);
    }
    for (int r = 0; r <= p; ++r)
      if (ders[0][r] != 0.0) put(i + 2, span - p + r, ders[0][r]);
    b[i + 2] = y[static_cast<std::size_t>(i)];
  }
  end_rows(last_span, n + 2);
  Eigen::VectorXd c = b;
  if (!solve_banded(nb, kl, ku, band, c)) singular_collocation(who);

  // taylor coefficients at the left end of each piece from the differenced coefficients
  // (as PeriodicSpline::interpolate_periodic) c^(k)_j = (q + 1) (c^(k-1)_j - c^(k-1)_{j-1}) /
  // (U_{j+q+1} - U_j), q = p - k: f^(k)(x_i) = sum_r N_{i+p-q+r, q}(x_i) c^(k)_{i+p-q+r}. The
  // knot differences it needs (j >= i + k) are >= x_{i+1} - x_i > 0; the clamped ends' zero
  // ones belong to basis functions that vanish on the domain.
  std::vector<std::array<double, p + 1>> diff(static_cast<std::size_t>(nb));  // [j][k] = c^(k)_j
  for (int j = 0; j < nb; ++j) diff[static_cast<std::size_t>(j)][0] = c[j];
  for (int k = 1; k <= p; ++k) {
    const int q = p - k;
    for (int j = k; j < nb; ++j) {
      const double den = U[static_cast<std::size_t>(j + q + 1)] - U[static_cast<std::size_t>(j)];
      diff[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)] =
          den > 0 ? (q + 1) * (diff[static_cast<std::size_t>(j)][static_cast<std::size_t>(k - 1)] -
                               diff[static_cast<std::size_t>(j - 1)][static_cast<std::size_t>(k - 1)]) / den
                  : 0.0;
    }
  }
  Spline s;
  s.x_.assign(x.begin(), x.end());
  s.coef_.resize(static_cast<std::size_t>(n - 1));
  for (int i = 0; i < n - 1; ++i) {
    const auto& tri = triangle[static_cast<std::size_t>(i)];
    for (int k = 0; k <= p; ++k) {
      const int q = p - k;
      double v = 0.0;
      for (int r = 0; r <= q; ++r)
        v += tri[static_cast<std::size_t>(q * (q + 1) / 2 + r)] * diff[static_cast<std::size_t>(i + p - q + r)][static_cast<std::size_t>(k)];
      s.coef_[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = v * kInvFactorial[k];
    }
  }
  s.init_lookup(x.back());

  // end data for the linear extrapolation and the cumulative integral at the knots
  s.f_first_ = s.coef_.front()[0];
  s.df_first_ = s.coef_.front()[1];
  double end[2];
  s.evaluate_piece(static_cast<std::size_t>(n - 2), h_last, 1, end);
  s.f_last_ = end[0];
  s.df_last_ = end[1];
  s.cumulative_.assign(static_cast<std::size_t>(n), 0.0);
  for (std::size_t i = 0; i + 1 < static_cast<std::size_t>(n); ++i) {
    s.cumulative_[i + 1] = s.cumulative_[i] + s.integrate_piece(i, s.x_[i + 1] - s.x_[i]);
  }
  return s;
}

void Spline::evaluate(double x, int max_order, double* out) const noexcept {
  CAMOPT_ASSERT_MSG(!x_.empty(), "evaluate on an empty Spline");
  CAMOPT_ASSERT(max_order >= 0 && max_order <= degree);
  // linear extrapolation with the end value and slope
  const bool before = x < x_.front();
  if (before || x > x_.back()) {
    const double d = before ? x - x_.front() : x - x_.back();
    const double f = before ? f_first_ : f_last_;
    const double df = before ? df_first_ : df_last_;
    out[0] = f + df * d;
    if (max_order >= 1) out[1] = df;
    for (int k = 2; k <= max_order; ++k) out[k] = 0.0;
    return;
  }
  const std::size_t i = locate(x);
  evaluate_piece(i, x - x_[i], max_order, out);
}

void Spline::antiderivative_parts(double x, double& base, double& local) const noexcept {
  CAMOPT_ASSERT_MSG(!x_.empty(), "antiderivative of an empty Spline");
  if (x < x_.front()) {
    // int_{x0}^{x} (f0 + f0' (u - x0)) du
    const double d = x - x_.front();
    base = 0.0;
    local = d * (f_first_ + 0.5 * df_first_ * d);
  } else if (x > x_.back()) {
    const double d = x - x_.back();
    base = cumulative_.back();
    local = d * (f_last_ + 0.5 * df_last_ * d);
  } else {
    const std::size_t i = locate(x);
    base = cumulative_[i];
    local = integrate_piece(i, x - x_[i]);
  }
}

double Spline::integral(double a, double b) const noexcept {
  // grouped so that a shared anchor cancels exactly
  double base_a, local_a, base_b, local_b;
  antiderivative_parts(a, base_a, local_a);
  antiderivative_parts(b, base_b, local_b);
  return (base_b - base_a) + (local_b - local_a);
}

}  // namespace camopt
