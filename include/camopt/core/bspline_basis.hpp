#pragma once
// b-spline basis functions of degree p at u in knot span `span` (U[span] <= u <= U[span+1],
// nonzero length) and their derivatives. Piegl & Tiller, "The NURBS Book", 2nd ed.,
// algorithm A2.3. Serves the quintic interpolating splines (core) and the swing-cam lift
// b-spline of any degree (opt).
#include <utility>

#include "camopt/core/error.hpp"

namespace camopt {

// the triangle of basis functions of every degree up to p at u (the first half of A2.3):
// ndu[r][j] (r <= j) = N_{span-j+r, j}(u); below the diagonal, knot differences
template <int C>
void bspline_basis_triangle(const double* U, int span, int p, double u, double (&ndu)[C][C]) {
  CAMOPT_ASSERT(p >= 0 && p < C);
  double left[C], right[C];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - U[span + 1 - j];
    right[j] = U[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      // lower triangle: knot differences; upper triangle: basis functions
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
}

// ders[k][r] = d^k/du^k N_{span-p+r, p}(u), k = 0..nd (nd <= p), r = 0..p
template <int R, int C>
void bspline_basis_derivatives(const double* U, int span, int p, double u, int nd, double (&ders)[R][C]) {
  CAMOPT_ASSERT(nd >= 0 && nd < R && nd <= p);
  double ndu[C][C];
  bspline_basis_triangle(U, span, p, u, ndu);
  for (int r = 0; r <= p; ++r) ders[0][r] = ndu[r][p];
  double a[2][C];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= nd; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk, j2 = r - 1 <= pk ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= nd; ++k) {
    for (int r = 0; r <= p; ++r) ders[k][r] *= factor;
    factor *= p - k;
  }
}

}  // namespace camopt
