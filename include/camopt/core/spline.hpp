#pragma once
// quintic (degree 5, c4) interpolating splines with knots at the data sites, so that
// follower acceleration and jerk computed from a table stay continuous.
//
// the b-spline collocation system (de Boor, "A Practical Guide to Splines", rev. ed.,
// ch. IX and XIII) is solved once; the result is stored in piecewise taylor form
// f(x_i + s) = sum_{m=0}^{5} a_{i,m} s^m, so evaluation is one interval lookup plus
// horner sums and never allocates.
//
// x on a knot evaluates the piece to its right (f^(5) is piecewise constant; f..f''''
// are continuous).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "camopt/core/jet.hpp"

namespace camopt {

namespace detail {

// breakpoints and per-interval taylor coefficients shared by both spline kinds
class PiecewiseQuintic {
 public:
  static constexpr int degree = 5;

  // the breakpoints, i.e. the data sites x (x.front() + period closes a periodic spline)
  std::span<const double> knots() const noexcept { return x_; }
  bool empty() const noexcept { return x_.empty(); }
  // smallest and largest value over the pieces: the knot values and every interior
  // extremum where a piece's slope changes sign between its ends (safeguarded newton on f';
  // the value to round-off), except excursions below ~1e-12 of the value (ringing). A piece whose slope has the same sign at both ends but turns twice
  // inside is not searched (a quintic interpolant of table data does not wiggle so).
  // x_end: the right end of the last piece (x.back() for a natural spline, x.front() +
  // period for a periodic one).
  void value_range(double x_end, double& lo, double& hi) const noexcept;

 protected:
  // interval index i with x_[i] <= x < x_[i+1], clamped to [0, pieces - 1]
  std::size_t locate(double x) const noexcept;
  // f^(k)(x_i + s) for k = 0..max_order from the coefficients of interval i
  void evaluate_piece(std::size_t i, double s, int max_order, double* out) const noexcept;
  // int_0^s of piece i
  double integrate_piece(std::size_t i, double s) const noexcept;
  // interval lookup tables for breakpoints covering [x_.front(), x_end]
  void init_lookup(double x_end);

  std::vector<double> x_;                    // breakpoints (the data sites)
  std::vector<std::array<double, 6>> coef_;  // a_{i,m} = f^(m)(x_i+) / m!
  double inv_h_ = 0.0;                       // 1 / spacing if uniform, else 0
  // non-uniform: equal-width buckets over [x0, x_end]; bucket_[b] = piece holding the
  // bucket's left edge, so a lookup scans only the pieces inside one bucket
  std::vector<std::uint32_t> bucket_;
  double inv_w_ = 0.0;  // buckets per unit x
};

// x solving the cyclic system of uniform quintic b-spline interpolation at the knots,
// (x_(i-2) + 26 x_(i-1) + 66 x_i + 26 x_(i+1) + x_(i+2)) / 120 = b_i (indices mod n), by
// recursive filtering (PeriodicSpline::interpolate on evenly spaced data)
void solve_uniform_quintic_cyclic(std::span<const double> b, std::span<double> x);

}  // namespace detail

namespace detail {
// f(x) and f(x(t)) as a jet, written once for both splines from their evaluate()
template <class Derived>
struct SplineCalls {
  double operator()(double x) const noexcept {
    double f;
    static_cast<const Derived&>(*this).evaluate(x, 0, &f);
    return f;
  }
  template <int N>
  Jet<N> operator()(const Jet<N>& x) const noexcept {
    std::array<double, N + 1> d{};
    constexpr int top = N < PiecewiseQuintic::degree ? N : PiecewiseQuintic::degree;
    static_cast<const Derived&>(*this).evaluate(x.value(), top, d.data());
    return compose(d.data(), x);
  }
};
}  // namespace detail

// periodic quintic interpolant: f(x + period) = f(x), c4 everywhere including the seam
class PeriodicSpline : public detail::PiecewiseQuintic, public detail::SplineCalls<PeriodicSpline> {
 public:
  PeriodicSpline() = default;

  // knots at x (strictly increasing, at least 6 points, x.back() - x.front() < period);
  // the point x.front() + period closes the curve with value y.front().
  // Solved in O(n) by a cyclic banded elimination with partial pivoting (the sparse LU below
  // when that is not at round-off). Throws InputError naming the point for data that
  // breaks these rules, or whose x values nearly coincide (a singular collocation system).
  static PeriodicSpline interpolate(std::span<const double> x, std::span<const double> y,
                                    double period);
  // the same spline by a sparse LU of the whole collocation system: the reference solve
  // that interpolate falls back to; its coefficients differ from interpolate's in the last bits
  static PeriodicSpline interpolate_by_sparse_lu(std::span<const double> x, std::span<const double> y,
                                                 double period);

  double period() const noexcept { return period_; }

  // out[k] = f^(k)(x) for k = 0..max_order (max_order <= 5); x is any real number
  void evaluate(double x, int max_order, double* out) const noexcept;

 private:
  static PeriodicSpline interpolate_periodic(std::span<const double> x, std::span<const double> y, double period,
                                             bool banded);
  double period_ = 0.0;
};

// quintic interpolant on [x0, xn] with natural end conditions f''' = f'''' = 0 at both
// ends (the natural spline of degree 5: it minimises int (f''')^2 and reproduces
// quadratics exactly). well-posed for any n >= 3 points, so no lower-degree fallback is
// needed. outside [x0, xn] it continues linearly with the end value and slope (f'' jumps
// to 0 there).
class Spline : public detail::PiecewiseQuintic, public detail::SplineCalls<Spline> {
 public:
  Spline() = default;

  // x strictly increasing, at least 3 points; throws InputError naming the point otherwise,
  // or when x values nearly coincide (a singular collocation system)
  static Spline interpolate(std::span<const double> x, std::span<const double> y);

  // out[k] = f^(k)(x) for k = 0..max_order (max_order <= 5)
  void evaluate(double x, int max_order, double* out) const noexcept;

  // exact int_a^b f (including the linear extrapolation)
  double integral(double a, double b) const noexcept;

  // F(x) = int_{x0}^{x} f as a jet: F' = f, F'' = f', ...
  template <int N>
  Jet<N> antiderivative(const Jet<N>& x) const noexcept {
    std::array<double, N + 1> d{};
    if constexpr (N >= 1) evaluate(x.value(), N - 1 < degree ? N - 1 : degree, d.data() + 1);
    d[0] = antiderivative_value(x.value());
    return compose(d.data(), x);
  }

 private:
  // F(x) = base + local: base = int_{x0}^{anchor} f at a breakpoint, local = int from there
  void antiderivative_parts(double x, double& base, double& local) const noexcept;
  double antiderivative_value(double x) const noexcept {
    double base, local;
    antiderivative_parts(x, base, local);
    return base + local;
  }

  std::vector<double> cumulative_;         // int_{x0}^{x_i} f
  double f_first_ = 0.0, df_first_ = 0.0;  // f, f' at x0 (left extrapolation)
  double f_last_ = 0.0, df_last_ = 0.0;    // f, f' at xn (right extrapolation)
};

}  // namespace camopt
