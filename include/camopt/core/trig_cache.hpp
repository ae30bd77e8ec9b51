#pragma once
// sin and cos of recently seen angles. One kinematic point evaluates the same angles many
// times (value, jacobian and derivative sweeps all share the value point), so a small
// per-thread memo saves most libm calls. Results are bit-identical to std::sin/std::cos.
#include <cmath>
#include <limits>

#include "camopt/core/jet.hpp"

namespace camopt {

inline void memo_sin_cos(double x, double& s, double& c) noexcept {
  struct Entry {
    double x, s, c;
  };
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();  // never equal: empty
  constexpr unsigned size = 8;
  thread_local Entry entries[size] = {{nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0},
                                      {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}, {nan, 0, 0}};
  thread_local unsigned next = 0;
  for (const Entry& e : entries)
    if (e.x == x) {
      s = e.s;
      c = e.c;
      return;
    }
  s = std::sin(x);
  c = std::cos(x);
  entries[next] = {x, s, c};
  next = (next + 1) % size;
}

inline void sin_cos(double x, double& s, double& c) noexcept { memo_sin_cos(x, s, c); }

template <int N>
void sin_cos(const Jet<N>& x, Jet<N>& s, Jet<N>& c) noexcept {
  double s0, c0;
  memo_sin_cos(x.value(), s0, c0);
  sincos_from(x, s0, c0, s, c);
}

}  // namespace camopt
