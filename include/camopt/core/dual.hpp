#pragma once
// vector-mode forward dual numbers: a value and M directional first derivatives.
// One residual sweep on Dual<n + 1> gives the whole n-column jacobian of a block and its
// first-order residual r_1 (direction 0 carries the known variables' true rates), where
// Jet<1> needs n + 1 sweeps. Same exact derivative rules as Jet<1> (Griewank & Walther,
// "Evaluating Derivatives", 2nd ed., ch. 3), applied to every direction at once.
//
// the elementary functions are hidden friends (found by adl only), so generic code keeps
// writing `using std::sqrt; sqrt(x)` and `sin_cos(x, s, c)` for double, Jet and Dual.
#include <array>
#include <cmath>

#include "camopt/core/jet.hpp"
#include "camopt/core/trig_cache.hpp"

namespace camopt {

template <int M>
struct Dual {
  static_assert(M >= 1, "a dual needs at least one direction");
  static constexpr int directions = M;

  double v = 0.0;
  std::array<double, M> d{};  // d[k] = derivative along direction k

  constexpr Dual() noexcept = default;
  constexpr Dual(double x) noexcept : v(x) {}  // NOLINT(google-explicit-constructor): a constant

  constexpr double value() const noexcept { return v; }

  // f(u) from f(u0) and f'(u0): the chain rule along every direction
  friend constexpr Dual chain(const Dual& u, double f0, double f1) noexcept {
    Dual r(f0);
    for (int k = 0; k < M; ++k) r.d[k] = f1 * u.d[k];
    return r;
  }

  friend constexpr Dual operator+(const Dual& a) noexcept { return a; }
  friend constexpr Dual operator-(const Dual& a) noexcept {
    Dual r(-a.v);
    for (int k = 0; k < M; ++k) r.d[k] = -a.d[k];
    return r;
  }
  friend constexpr Dual operator+(const Dual& a, const Dual& b) noexcept {
    Dual r(a.v + b.v);
    for (int k = 0; k < M; ++k) r.d[k] = a.d[k] + b.d[k];
    return r;
  }
  friend constexpr Dual operator+(const Dual& a, double b) noexcept {
    Dual r = a;
    r.v += b;
    return r;
  }
  friend constexpr Dual operator+(double a, const Dual& b) noexcept { return b + a; }
  friend constexpr Dual operator-(const Dual& a, const Dual& b) noexcept {
    Dual r(a.v - b.v);
    for (int k = 0; k < M; ++k) r.d[k] = a.d[k] - b.d[k];
    return r;
  }
  friend constexpr Dual operator-(const Dual& a, double b) noexcept {
    Dual r = a;
    r.v -= b;
    return r;
  }
  friend constexpr Dual operator-(double a, const Dual& b) noexcept {
    Dual r = -b;
    r.v += a;
    return r;
  }
  friend constexpr Dual operator*(const Dual& a, const Dual& b) noexcept {
    Dual r(a.v * b.v);
    for (int k = 0; k < M; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
    return r;
  }
  friend constexpr Dual operator*(const Dual& a, double b) noexcept {
    Dual r(a.v * b);
    for (int k = 0; k < M; ++k) r.d[k] = a.d[k] * b;
    return r;
  }
  friend constexpr Dual operator*(double a, const Dual& b) noexcept { return b * a; }
  // (a / b)' = (a' - (a / b) b') / b
  friend constexpr Dual operator/(const Dual& a, const Dual& b) noexcept {
    const double inv = 1.0 / b.v;
    Dual r(a.v * inv);
    for (int k = 0; k < M; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * inv;
    return r;
  }
  friend constexpr Dual operator/(const Dual& a, double b) noexcept { return a * (1.0 / b); }
  friend constexpr Dual operator/(double a, const Dual& b) noexcept {
    const double inv = 1.0 / b.v;
    Dual r(a * inv);
    for (int k = 0; k < M; ++k) r.d[k] = -r.v * b.d[k] * inv;
    return r;
  }

  constexpr Dual& operator+=(const Dual& b) noexcept { return *this = *this + b; }
  constexpr Dual& operator-=(const Dual& b) noexcept { return *this = *this - b; }
  constexpr Dual& operator*=(const Dual& b) noexcept { return *this = *this * b; }
  constexpr Dual& operator/=(const Dual& b) noexcept { return *this = *this / b; }
  constexpr Dual& operator+=(double b) noexcept {
    v += b;
    return *this;
  }
  constexpr Dual& operator-=(double b) noexcept {
    v -= b;
    return *this;
  }
  constexpr Dual& operator*=(double b) noexcept { return *this = *this * b; }
  constexpr Dual& operator/=(double b) noexcept { return *this = *this * (1.0 / b); }

  friend constexpr double value(const Dual& u) noexcept { return u.v; }

  friend Dual sqrt(const Dual& u) noexcept {
    const double r = std::sqrt(u.v);
    return chain(u, r, 0.5 / r);
  }
  // exp' = exp, log' = 1/u, (u^p)' = p u^(p-1) for a constant exponent p (u > 0; at u = 0
  // the value is 0 for p > 0 and the derivative p 0^(p-1): 0 for p > 1, inf for p < 1)
  friend Dual exp(const Dual& u) noexcept {
    const double e = std::exp(u.v);
    return chain(u, e, e);
  }
  friend Dual log(const Dual& u) noexcept { return chain(u, std::log(u.v), 1.0 / u.v); }
  friend Dual pow(const Dual& u, double p) noexcept {
    return chain(u, std::pow(u.v, p), p * std::pow(u.v, p - 1.0));
  }
  friend void sin_cos(const Dual& u, Dual& s, Dual& c) noexcept {
    double s0, c0;
    memo_sin_cos(u.v, s0, c0);  // bit-identical to std::sin / std::cos
    s = chain(u, s0, c0);
    c = chain(u, c0, -s0);
  }
  // f(x) from f(x0), f'(x0) (the layout of camopt::compose for jets)
  friend constexpr Dual compose(const double* f_derivatives, const Dual& x) noexcept {
    return chain(x, f_derivatives[0], f_derivatives[1]);
  }
};

// the taylor order a scalar type carries (how many derivatives of a spline it needs)
template <class T>
inline constexpr int taylor_order = 0;
template <int N>
inline constexpr int taylor_order<Jet<N>> = N;
template <int M>
inline constexpr int taylor_order<Dual<M>> = 1;

}  // namespace camopt
