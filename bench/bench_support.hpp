#pragma once
// shared by the benchmarks: compact numbers for csv/markdown and best-of-N timing
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "camopt/core/process_memory.hpp"

namespace camopt::bench {

// compact number (std::to_string prints 6 fixed decimals: 1e-14 -> 0.000000)
inline std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

// best wall time of `repeat` runs of f [s]
inline double seconds_of(const std::function<void()>& f, int repeat) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace camopt::bench
