#pragma once
// truncated taylor series in one variable t ("jets"). every kinematic quantity is carried
// as value + velocity + acceleration + jerk with respect to the driver angle, so the
// kernels propagate Jet<3> through every connection instead of differencing.
//
// c[k] = (1/k!) d^k x / dt^k at t = 0. all elementary functions use the O(N^2) taylor
// coefficient recurrences of Griewank & Walther, "Evaluating Derivatives", 2nd ed.,
// sec. 13.2 (arithmetic, sqrt, exp, log, sin/cos), and the same "derivative times
// f'(u)" form v' = u' f'(u) for atan, asin, acos and atan2.
//
// generic code is written once for double and for jets:
//   using std::sin; auto y = sin(x);   // std::sin for double, camopt::sin (adl) for jets
//   double v = value(y);
#include <array>
#include <cmath>
#include <cstddef>

#include "camopt/core/angle.hpp"

namespace camopt {

template <int N>
struct Jet {
  static_assert(N >= 0, "jet order must be non-negative");
  static constexpr int order = N;

  // taylor coefficients c[k] = x^(k) / k!
  std::array<double, N + 1> c{};

  constexpr Jet() noexcept = default;
  // a constant (implicit on purpose: generic code writes Jet x = 0.0, x + 1, ...)
  constexpr Jet(double x) noexcept { c[0] = x; }  // NOLINT(google-explicit-constructor)

  // the independent variable x(t) = x0 + dx * t
  static constexpr Jet variable(double x0, double dx = 1.0) noexcept {
    Jet r(x0);
    if constexpr (N >= 1) r.c[1] = dx;
    return r;
  }

  constexpr double value() const noexcept { return c[0]; }

  // d^k x / dt^k = k! c[k] (0 for k > N)
  constexpr double derivative(int k) const noexcept {
    if (k < 0 || k > N) return 0.0;
    double f = 1.0;
    for (int i = 2; i <= k; ++i) f *= i;
    return f * c[k];
  }

  // ---- arithmetic (hidden friends, found by adl) ----
  friend constexpr Jet operator+(const Jet& a) noexcept { return a; }
  friend constexpr Jet operator-(const Jet& a) noexcept {
    Jet r;
    for (int k = 0; k <= N; ++k) r.c[k] = -a.c[k];
    return r;
  }

  friend constexpr Jet operator+(const Jet& a, const Jet& b) noexcept {
    Jet r;
    for (int k = 0; k <= N; ++k) r.c[k] = a.c[k] + b.c[k];
    return r;
  }
  friend constexpr Jet operator+(const Jet& a, double b) noexcept {
    Jet r = a;
    r.c[0] += b;
    return r;
  }
  friend constexpr Jet operator+(double a, const Jet& b) noexcept { return b + a; }

  friend constexpr Jet operator-(const Jet& a, const Jet& b) noexcept {
    Jet r;
    for (int k = 0; k <= N; ++k) r.c[k] = a.c[k] - b.c[k];
    return r;
  }
  friend constexpr Jet operator-(const Jet& a, double b) noexcept {
    Jet r = a;
    r.c[0] -= b;
    return r;
  }
  friend constexpr Jet operator-(double a, const Jet& b) noexcept {
    Jet r = -b;
    r.c[0] += a;
    return r;
  }

  // cauchy product: v_k = sum_{j=0}^{k} a_j b_{k-j}   (g&w sec. 13.2, as all below)
  friend constexpr Jet operator*(const Jet& a, const Jet& b) noexcept {
    Jet r;
    for (int k = 0; k <= N; ++k) {
      double s = 0.0;
      for (int j = 0; j <= k; ++j) s += a.c[j] * b.c[k - j];
      r.c[k] = s;
    }
    return r;
  }
  friend constexpr Jet operator*(const Jet& a, double b) noexcept {
    Jet r;
    for (int k = 0; k <= N; ++k) r.c[k] = a.c[k] * b;
    return r;
  }
  friend constexpr Jet operator*(double a, const Jet& b) noexcept { return b * a; }

  // v = a / b: v_k = (a_k - sum_{j=0}^{k-1} v_j b_{k-j}) / b_0
  friend constexpr Jet operator/(const Jet& a, const Jet& b) noexcept {
    Jet r;
    const double inv = 1.0 / b.c[0];
    for (int k = 0; k <= N; ++k) {
      double s = a.c[k];
      for (int j = 0; j < k; ++j) s -= r.c[j] * b.c[k - j];
      r.c[k] = s * inv;
    }
    return r;
  }
  friend constexpr Jet operator/(const Jet& a, double b) noexcept { return a * (1.0 / b); }
  friend constexpr Jet operator/(double a, const Jet& b) noexcept {
    Jet r;
    const double inv = 1.0 / b.c[0];
    r.c[0] = a * inv;
    for (int k = 1; k <= N; ++k) {
      double s = 0.0;
      for (int j = 0; j < k; ++j) s -= r.c[j] * b.c[k - j];
      r.c[k] = s * inv;
    }
    return r;
  }

  // ---- compound assignment ----
  constexpr Jet& operator+=(const Jet& b) noexcept {
    for (int k = 0; k <= N; ++k) c[k] += b.c[k];
    return *this;
  }
  constexpr Jet& operator-=(const Jet& b) noexcept {
    for (int k = 0; k <= N; ++k) c[k] -= b.c[k];
    return *this;
  }
  constexpr Jet& operator*=(const Jet& b) noexcept { return *this = *this * b; }
  constexpr Jet& operator/=(const Jet& b) noexcept { return *this = *this / b; }
  constexpr Jet& operator+=(double b) noexcept {
    c[0] += b;
    return *this;
  }
  constexpr Jet& operator-=(double b) noexcept {
    c[0] -= b;
    return *this;
  }
  constexpr Jet& operator*=(double b) noexcept {
    for (int k = 0; k <= N; ++k) c[k] *= b;
    return *this;
  }
  constexpr Jet& operator/=(double b) noexcept { return *this *= (1.0 / b); }
};

// ---- value access for generic code ----
constexpr double value(double x) noexcept { return x; }
template <int N>
constexpr double value(const Jet<N>& x) noexcept {
  return x.c[0];
}

// true for a Jet<N> (generic code that treats jets apart from doubles and duals)
template <class T>
inline constexpr bool is_jet_v = false;
template <int N>
inline constexpr bool is_jet_v<Jet<N>> = true;

// the first M+1 coefficients of a jet (M <= N)
template <int M, int N>
constexpr Jet<M> truncate(const Jet<N>& x) noexcept {
  static_assert(M >= 0 && M <= N, "truncate: target order must be in [0, N]");
  Jet<M> r;
  for (int k = 0; k <= M; ++k) r.c[k] = x.c[k];
  return r;
}

namespace detail {

// 1/k! for k = 0..N
template <int N>
inline constexpr std::array<double, N + 1> kInvFactorial = [] {
  std::array<double, N + 1> f{};
  double v = 1.0;
  for (int k = 0; k <= N; ++k) {
    if (k > 0) v /= k;
    f[static_cast<std::size_t>(k)] = v;
  }
  return f;
}();

// taylor coefficients of dx/dt, one order lower: (dx/dt)_k = (k+1) x_{k+1}
template <int N>
constexpr Jet<N - 1> dt(const Jet<N>& x) noexcept {
  Jet<N - 1> r;
  for (int k = 0; k < N; ++k) r.c[k] = (k + 1) * x.c[k + 1];
  return r;
}

// v = v0 + int_0^t g: v_k = g_{k-1} / k
template <int N>
constexpr Jet<N> integrate(const Jet<N - 1>& g, double v0) noexcept {
  Jet<N> r(v0);
  for (int k = 1; k <= N; ++k) r.c[k] = g.c[k - 1] / k;
  return r;
}

// v = f(u) with v' = u' g, g = f'(u) given to order N-1:
// v_k = (1/k) sum_{j=1}^{k} j u_j g_{k-j}   (g&w sec. 13.2)
template <int N>
constexpr Jet<N> chain(const Jet<N>& u, double v0, const Jet<N - 1>& g) noexcept {
  Jet<N> r(v0);
  for (int k = 1; k <= N; ++k) {
    double s = 0.0;
    for (int j = 1; j <= k; ++j) s += j * u.c[j] * g.c[k - j];
    r.c[k] = s / k;
  }
  return r;
}

}  // namespace detail

// ---- elementary functions (found by adl) ----

template <int N>
constexpr Jet<N> square(const Jet<N>& x) noexcept {
  // v_k = sum_j x_j x_{k-j}, using the symmetry of the sum
  Jet<N> r;
  for (int k = 0; k <= N; ++k) {
    double s = 0.0;
    for (int j = 0; 2 * j < k; ++j) s += x.c[j] * x.c[k - j];
    s *= 2.0;
    if (k % 2 == 0) s += x.c[k / 2] * x.c[k / 2];
    r.c[k] = s;
  }
  return r;
}
constexpr double square(double x) noexcept { return x * x; }

// integer power by repeated squaring (exact for x0 = 0 and n >= 0)
template <int N>
constexpr Jet<N> pow(const Jet<N>& x, int n) noexcept {
  long long e = n;
  const bool negative = e < 0;
  if (negative) e = -e;
  Jet<N> r(1.0);
  Jet<N> b = x;
  while (e > 0) {
    if (e & 1) r *= b;
    e >>= 1;
    if (e > 0) b = square(b);
  }
  return negative ? 1.0 / r : r;
}

// v = sqrt(u): v_k = (u_k - sum_{j=1}^{k-1} v_j v_{k-j}) / (2 v_0)
// the same recurrence given the root's value (hypot passes std::hypot, safe from overflow)
template <int N>
inline Jet<N> sqrt_from(const Jet<N>& u, double root) noexcept {
  Jet<N> r(root);
  const double inv = 0.5 / r.c[0];
  for (int k = 1; k <= N; ++k) {
    double s = u.c[k];
    for (int j = 1; j < k; ++j) s -= r.c[j] * r.c[k - j];
    r.c[k] = s * inv;
  }
  return r;
}
template <int N>
inline Jet<N> sqrt(const Jet<N>& u) noexcept {
  return sqrt_from(u, std::sqrt(u.c[0]));
}

// v = exp(u): v_k = (1/k) sum_{j=1}^{k} j u_j v_{k-j}
template <int N>
inline Jet<N> exp(const Jet<N>& u) noexcept {
  Jet<N> r(std::exp(u.c[0]));
  for (int k = 1; k <= N; ++k) {
    double s = 0.0;
    for (int j = 1; j <= k; ++j) s += j * u.c[j] * r.c[k - j];
    r.c[k] = s / k;
  }
  return r;
}

// v = log(u): v_k = (u_k - (1/k) sum_{j=1}^{k-1} j v_j u_{k-j}) / u_0
template <int N>
inline Jet<N> log(const Jet<N>& u) noexcept {
  Jet<N> r(std::log(u.c[0]));
  const double inv = 1.0 / u.c[0];
  for (int k = 1; k <= N; ++k) {
    double s = 0.0;
    for (int j = 1; j < k; ++j) s += j * r.c[j] * u.c[k - j];
    r.c[k] = (u.c[k] - s / k) * inv;
  }
  return r;
}

// coupled recurrence: s_k = (1/k) sum j u_j c_{k-j}, c_k = -(1/k) sum j u_j s_{k-j}
template <int N>
inline void sincos_from(const Jet<N>& u, double sin_u0, double cos_u0, Jet<N>& s, Jet<N>& c) noexcept {
  // the recurrence of sincos, given sin and cos of the value (callers that already
  // know them skip the libm calls)
  Jet<N> ss(sin_u0);
  Jet<N> cc(cos_u0);
  for (int k = 1; k <= N; ++k) {
    double a = 0.0;
    double b = 0.0;
    for (int j = 1; j <= k; ++j) {
      const double ju = j * u.c[j];
      a += ju * cc.c[k - j];
      b += ju * ss.c[k - j];
    }
    ss.c[k] = a / k;
    cc.c[k] = -b / k;
  }
  s = ss;
  c = cc;
}

template <int N>
inline void sincos(const Jet<N>& u, Jet<N>& s, Jet<N>& c) noexcept {
  sincos_from(u, std::sin(u.c[0]), std::cos(u.c[0]), s, c);
}

template <int N>
inline Jet<N> sin(const Jet<N>& u) noexcept {
  Jet<N> s, c;
  sincos(u, s, c);
  return s;
}

template <int N>
inline Jet<N> cos(const Jet<N>& u) noexcept {
  Jet<N> s, c;
  sincos(u, s, c);
  return c;
}

// atan(u)' = u' / (1 + u^2)
template <int N>
inline Jet<N> atan(const Jet<N>& u) noexcept {
  if constexpr (N == 0) {
    return Jet<0>(std::atan(u.c[0]));
  } else {
    const Jet<N - 1> ut = truncate<N - 1>(u);
    return detail::chain(u, std::atan(u.c[0]), 1.0 / (1.0 + square(ut)));
  }
}

// asin(u)' = u' / sqrt(1 - u^2)
template <int N>
inline Jet<N> asin(const Jet<N>& u) noexcept {
  if constexpr (N == 0) {
    return Jet<0>(std::asin(u.c[0]));
  } else {
    const Jet<N - 1> ut = truncate<N - 1>(u);
    return detail::chain(u, std::asin(u.c[0]), 1.0 / sqrt(1.0 - square(ut)));
  }
}

// acos(u)' = -u' / sqrt(1 - u^2)
template <int N>
inline Jet<N> acos(const Jet<N>& u) noexcept {
  if constexpr (N == 0) {
    return Jet<0>(std::acos(u.c[0]));
  } else {
    const Jet<N - 1> ut = truncate<N - 1>(u);
    return detail::chain(u, std::acos(u.c[0]), -1.0 / sqrt(1.0 - square(ut)));
  }
}

// atan2(y, x)' = (x y' - y x') / (x^2 + y^2); the value keeps the quadrant of std::atan2
// (atan2_by_atan: within 2 ulp of it)
template <int N>
inline Jet<N> atan2(const Jet<N>& y, const Jet<N>& x) noexcept {
  if constexpr (N == 0) {
    return Jet<0>(atan2_by_atan(y.c[0], x.c[0]));
  } else {
    const Jet<N - 1> xt = truncate<N - 1>(x);
    const Jet<N - 1> yt = truncate<N - 1>(y);
    const Jet<N - 1> g = (xt * detail::dt(y) - yt * detail::dt(x)) / (square(xt) + square(yt));
    return detail::integrate<N>(g, atan2_by_atan(y.c[0], x.c[0]));
  }
}

// hypot(x, y) = sqrt(x^2 + y^2), value by std::hypot (no overflow in c[0])
template <int N>
inline Jet<N> hypot(const Jet<N>& x, const Jet<N>& y) noexcept {
  return sqrt_from(square(x) + square(y), std::hypot(x.c[0], y.c[0]));
}

// the same truncated series about t = h: c_k <- sum_j binom(j, k) c_j h^(j - k) (taylor shift
// by repeated synthetic division, O(N^2)); exact for a polynomial of degree <= N
template <int N>
constexpr void taylor_shift(Jet<N>& x, double h) noexcept {
  for (int i = 0; i < N; ++i)
    for (int k = N - 1; k >= i; --k) x.c[k] += h * x.c[k + 1];
}

// the jet of f at a point from f, f', ..., f^(N) there: taylor coefficients f^(k) / k!
template <int N>
constexpr Jet<N> jet_from_derivatives(const double* f_derivatives) noexcept {
  Jet<N> r(f_derivatives[0]);
  for (int k = 1; k <= N; ++k) r.c[k] = f_derivatives[k] * detail::kInvFactorial<N>[static_cast<std::size_t>(k)];
  return r;
}

// f(x(t)) from f, f', ..., f^(N) at x0 = x.value():
// f(x) = sum_k f^(k)(x0) / k! (x - x0)^k, truncated at order N (faa di bruno by powers)
template <int N>
constexpr Jet<N> compose(const double* f_derivatives, const Jet<N>& x) noexcept {
  Jet<N> r(f_derivatives[0]);
  if constexpr (N == 3) {
    // the loop below written out (the kinematics' order), in its order of operations, so
    // the result is the same to the bit: r_1 = a_1 x_1, r_2 = a_1 x_2 + a_2 x_1^2,
    // r_3 = a_1 x_3 + a_2 (x_1 x_2 + x_2 x_1) + a_3 x_1 (x_1 x_1), a_k = f^(k) / k!
    const double x1 = x.c[1], x2 = x.c[2], x3 = x.c[3];
    const double a1 = f_derivatives[1] * detail::kInvFactorial<3>[1];
    const double a2 = f_derivatives[2] * detail::kInvFactorial<3>[2];
    const double a3 = f_derivatives[3] * detail::kInvFactorial<3>[3];
    r.c[1] = 0.0 + a1 * x1;
    r.c[2] = (0.0 + a1 * x2) + a2 * (x1 * x1);
    r.c[3] = ((0.0 + a1 * x3) + a2 * (x1 * x2 + x2 * x1)) + a3 * (x1 * (x1 * x1));
  } else if constexpr (N >= 1) {
    Jet<N> d = x;
    d.c[0] = 0.0;
    Jet<N> p = d;  // (x - x0)^k, zero below order k
    for (int k = 1; k <= N; ++k) {
      const double a = f_derivatives[k] * detail::kInvFactorial<N>[static_cast<std::size_t>(k)];
      for (int m = k; m <= N; ++m) r.c[m] += a * p.c[m];
      if (k < N) {
        // p <- p * d, using p_m = 0 for m < k and d_0 = 0
        for (int m = N; m >= k + 1; --m) {
          double s = 0.0;
          for (int j = 1; j <= m - k; ++j) s += d.c[j] * p.c[m - j];
          p.c[m] = s;
        }
        p.c[k] = 0.0;
      }
    }
  }
  return r;
}

}  // namespace camopt
