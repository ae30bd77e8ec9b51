#pragma once
// sin and cos of recently seen angles. One kinematic point evaluates the same angles many
// times (value, jacobian and derivative sweeps all share the value point), so a small
// per-thread memo saves most libm calls. Results are bit-identical to std::sin/std::cos,
// except for entries moved by memo_sin_cos_shift or put in by memo_sin_cos_insert.
#include <cmath>
#include <limits>

#include "camopt/core/jet.hpp"

namespace camopt {

struct SinCosMemo {
  struct Entry {
    double x, s, c;
  };
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();  // never equal: empty
  static constexpr unsigned size = 8;
  Entry entries[size] = {{nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0},
                         {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}};
  unsigned next = 0;
  static SinCosMemo& local() noexcept {
    thread_local SinCosMemo memo;
    return memo;
  }
  // (an older entry at the same x may remain: lookups take the first; both are within
  // round-off, and clear() at the start of a computation keeps the choice deterministic)
  void add(double x, double s, double c) noexcept {
    entries[next] = {x, s, c};
    next = (next + 1) % size;
  }
  void clear() noexcept { *this = SinCosMemo{}; }
};

inline void memo_sin_cos(double x, double& s, double& c) noexcept {
  SinCosMemo& memo = SinCosMemo::local();
  for (const auto& e : memo.entries)
    if (e.x == x) {
      s = e.s;
      c = e.c;
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
  for (const auto& e : memo.entries)
    if (e.x == x) {
      const double h2 = h * h;
      const double sh = h * (1.0 - h2 / 6.0 * (1.0 - h2 / 20.0)), ch = 1.0 - h2 / 2.0 * (1.0 - h2 / 12.0);
      const double s = e.s, c = e.c;
      memo.add(x + h, s * ch + c * sh, c * ch - s * sh);
      return;
    }
}

inline void sin_cos(double x, double& s, double& c) noexcept { memo_sin_cos(x, s, c); }

template <int N>
void sin_cos(const Jet<N>& x, Jet<N>& s, Jet<N>& c) noexcept {
  double s0, c0;
  memo_sin_cos(x.value(), s0, c0);
  sincos_from(x, s0, c0, s, c);
}

}  // namespace camopt
