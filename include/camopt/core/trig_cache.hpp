#pragma once
// sin and cos of recently seen angles. One kinematic point evaluates the same angles many
// times (value, jacobian and derivative sweeps all share the value point), so a small
// per-thread memo saves most libm calls. Results are bit-identical to std::sin/std::cos,
// except for entries moved by memo_sin_cos_shift or put in by memo_sin_cos_insert.
#include <bit>
#include <cmath>
#include <limits>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "camopt/core/jet.hpp"

namespace camopt {

struct SinCosMemo {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();  // never equal: empty
  static constexpr unsigned size = 8;
  // the angles apart from their values, so a lookup compares all of them at once
  alignas(64) double x[size] = {nan, nan, nan, nan, nan, nan, nan, nan};
  double s[size] = {}, c[size] = {};
  unsigned next = 0;
  static SinCosMemo& local() noexcept {
    thread_local SinCosMemo memo;
    return memo;
  }
  // the first entry (lowest index) holding angle `at`, or -1. (An older entry at the same
  // angle may remain: lookups take the first; both are within round-off, and clear() at the
  // start of a computation keeps the choice deterministic)
  int find(double at) const noexcept {
    unsigned mask = 0;  // bit k: x[k] == at
#if defined(__SSE2__)
    const __m128d a = _mm_set1_pd(at);
    for (unsigned k = 0; k < size; k += 2)
      mask |= static_cast<unsigned>(_mm_movemask_pd(_mm_cmpeq_pd(_mm_load_pd(x + k), a))) << k;
#else
    for (unsigned k = 0; k < size; ++k) mask |= static_cast<unsigned>(x[k] == at) << k;
#endif
    return mask == 0 ? -1 : std::countr_zero(mask);
  }
  void add(double at, double sin_at, double cos_at) noexcept {
    x[next] = at;
    s[next] = sin_at;
    c[next] = cos_at;
    next = (next + 1) % size;
  }
  void clear() noexcept { *this = SinCosMemo{}; }
};

inline void memo_sin_cos(double x, double& s, double& c) noexcept {
  SinCosMemo& memo = SinCosMemo::local();
  if (const int k = memo.find(x); k >= 0) {
    s = memo.s[k];
    c = memo.c[k];
    return;
  }
  s = std::sin(x);
  c = std::cos(x);
  memo.add(x, s, c);
}

// sin and cos of x known from elsewhere (e.g. a unit vector at angle x): later calls at x
// take them from the memo
inline void memo_sin_cos_insert(double x, double s, double c) noexcept { SinCosMemo::local().add(x, s, c); }

// the memo's entry at x, if any, rotated to x + h (|h| <= 1e-3 rad: the series of sin h
// and cos h below are exact to round-off; the result is within an ulp or two of libm)
inline void memo_sin_cos_shift(double x, double h) noexcept {
  if (!(std::abs(h) <= 1e-3)) return;
  SinCosMemo& memo = SinCosMemo::local();
  if (const int k = memo.find(x); k >= 0) {
    const double h2 = h * h;
    const double sh = h * (1.0 - h2 / 6.0 * (1.0 - h2 / 20.0)), ch = 1.0 - h2 / 2.0 * (1.0 - h2 / 12.0);
    const double s = memo.s[k], c = memo.c[k];
    memo.add(x + h, s * ch + c * sh, c * ch - s * sh);
  }
}

inline void sin_cos(double x, double& s, double& c) noexcept { memo_sin_cos(x, s, c); }

// sin and cos of 2 pi i / n, i = 0 .. n - 1 (an evenly sampled revolution): for n divisible
// by 8 from the first octant by the quarter-turn and octant symmetries (n / 8 + 1 libm
// calls; each within an ulp of libm's at 2 pi i / n rounded), else by libm at every i
inline void revolution_sin_cos(int n, std::vector<double>& s, std::vector<double>& c) {
  s.resize(static_cast<std::size_t>(n));
  c.resize(static_cast<std::size_t>(n));
  const double two_pi = 6.283185307179586476925286766559;
  if (n % 8 != 0) {
    for (int i = 0; i < n; ++i) {
      s[static_cast<std::size_t>(i)] = std::sin(two_pi * i / n);
      c[static_cast<std::size_t>(i)] = std::cos(two_pi * i / n);
    }
    return;
  }
  const int octant = n / 8, quarter = n / 4;
  for (int j = 0; j <= octant; ++j) {  // the first octant
    s[static_cast<std::size_t>(j)] = std::sin(two_pi * j / n);
    c[static_cast<std::size_t>(j)] = std::cos(two_pi * j / n);
  }
  for (int j = octant + 1; j < quarter; ++j) {  // the second: sin t = cos (pi / 2 - t)
    s[static_cast<std::size_t>(j)] = c[static_cast<std::size_t>(quarter - j)];
    c[static_cast<std::size_t>(j)] = s[static_cast<std::size_t>(quarter - j)];
  }
  for (int i = quarter; i < n; ++i) {  // later quarters: turned by a quarter from the one before
    s[static_cast<std::size_t>(i)] = c[static_cast<std::size_t>(i - quarter)];
    c[static_cast<std::size_t>(i)] = 0.0 - s[static_cast<std::size_t>(i - quarter)];  // (no -0.0)
  }
}

template <int N>
void sin_cos(const Jet<N>& x, Jet<N>& s, Jet<N>& c) noexcept {
  double s0, c0;
  memo_sin_cos(x.value(), s0, c0);
  sincos_from(x, s0, c0, s, c);
}

}  // namespace camopt
