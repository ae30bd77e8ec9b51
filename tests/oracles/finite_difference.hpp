#pragma once
// central finite-difference stencils for derivative checks in tests (never in the kernel,
// STYLE.md §4). weights by fornberg's recurrence: B. Fornberg, "Generation of finite
// difference formulas on arbitrarily spaced grids", Math. Comp. 51 (1988) 699-706.
// a central stencil of half-width m for the k-th derivative is accurate to order
// 2 * floor((2m + 1 - k + 1) / 2): m = 4 gives 8th order for k = 1, 2, m = 5 for k = 3.
#include <cmath>
#include <functional>
#include <vector>

namespace camopt::oracles {

// weights w[j], j = 0..2m, for d^k f / dx^k (x0) ~ sum_j w[j] f(x0 + (j - m) h) / h^k
inline std::vector<double> central_weights(int k, int m) {
  const int n = 2 * m;  // nodes 0..n at offsets j - m
  std::vector<std::vector<double>> c(static_cast<std::size_t>(k + 1), std::vector<double>(static_cast<std::size_t>(n + 1), 0.0));
  auto x = [m](int j) { return static_cast<double>(j - m); };
  double c1 = 1.0, c4 = x(0);
  c[0][0] = 1.0;
  for (int i = 1; i <= n; ++i) {
    const int mn = i < k ? i : k;
    double c2 = 1.0;
    const double c5 = c4;
    c4 = x(i);
    for (int j = 0; j < i; ++j) {
      const double c3 = x(i) - x(j);
      c2 *= c3;
      if (j == i - 1) {
        for (int d = mn; d >= 1; --d)
          c[static_cast<std::size_t>(d)][static_cast<std::size_t>(i)] =
              c1 * (d * c[static_cast<std::size_t>(d - 1)][static_cast<std::size_t>(i - 1)] -
                    c5 * c[static_cast<std::size_t>(d)][static_cast<std::size_t>(i - 1)]) / c2;
        c[0][static_cast<std::size_t>(i)] = -c1 * c5 * c[0][static_cast<std::size_t>(i - 1)] / c2;
      }
      for (int d = mn; d >= 1; --d)
        c[static_cast<std::size_t>(d)][static_cast<std::size_t>(j)] =
            (c4 * c[static_cast<std::size_t>(d)][static_cast<std::size_t>(j)] -
             d * c[static_cast<std::size_t>(d - 1)][static_cast<std::size_t>(j)]) / c3;
      c[0][static_cast<std::size_t>(j)] = c4 * c[0][static_cast<std::size_t>(j)] / c3;
    }
    c1 = c2;
  }
  return c[static_cast<std::size_t>(k)];
}

// d^k f / dx^k at x0 from a central stencil of half-width m and step h
inline double central_difference(const std::function<double(double)>& f, double x0, int k, int m, double h) {
  const std::vector<double> w = central_weights(k, m);
  double s = 0.0;
  for (int j = 0; j <= 2 * m; ++j)
    if (w[static_cast<std::size_t>(j)] != 0.0) s += w[static_cast<std::size_t>(j)] * f(x0 + (j - m) * h);
  return s / std::pow(h, k);
}

// the same from samples f(x0 + (j - m) h), j = 0..2m, already evaluated
inline double central_difference(const std::vector<double>& samples, int k, double h) {
  const int m = static_cast<int>(samples.size() / 2);
  const std::vector<double> w = central_weights(k, m);
  double s = 0.0;
  for (std::size_t j = 0; j < samples.size(); ++j) s += w[j] * samples[j];
  return s / std::pow(h, k);
}

}  // namespace camopt::oracles
