#pragma once
// LU factorisation with partial pivoting for the small dense blocks of the kinematics
// kernel (n <= 16): no heap, no expression templates; Golub & Van Loan, Matrix
// Computations, 4th ed., alg. 3.4.1. The kernel factors one block per point, so the
// constant overhead of a general library routine dominated at n = 2 or 3.
#include <algorithm>
#include <cmath>

namespace camopt::kin {

template <int MaxN>
class SmallLU {
 public:
  // factor the n x n matrix a(i, j); returns false if a pivot is exactly zero
  template <class Matrix>
  bool factor(int n, const Matrix& a) {
    n_ = n;
    norm1_ = 0.0;
    for (int j = 0; j < n; ++j) {
      double col = 0.0;
      for (int i = 0; i < n; ++i) {
        lu_[i][j] = a(i, j);
        col += std::abs(a(i, j));
      }
      norm1_ = std::max(norm1_, col);
    }
    ok_ = true;
    for (int k = 0; k < n; ++k) {
      int p = k;
      for (int i = k + 1; i < n; ++i)
        if (std::abs(lu_[i][k]) > std::abs(lu_[p][k])) p = i;
      piv_[k] = p;
      if (p != k)
        for (int j = 0; j < n; ++j) std::swap(lu_[k][j], lu_[p][j]);
      if (lu_[k][k] == 0.0) {
        ok_ = false;
        continue;
      }
      const double inv = 1.0 / lu_[k][k];
      for (int i = k + 1; i < n; ++i) {
        const double l = lu_[i][k] *= inv;
        for (int j = k + 1; j < n; ++j) lu_[i][j] -= l * lu_[k][j];
      }
    }
    return ok_;
  }

  bool ok() const { return ok_; }

  // x = A^-1 b (x may alias b)
  void solve(const double* b, double* x) const {
    double y[MaxN];
    for (int i = 0; i < n_; ++i) y[i] = b[i];
    for (int k = 0; k < n_; ++k)
      if (piv_[k] != k) std::swap(y[k], y[piv_[k]]);
    for (int i = 0; i < n_; ++i)
      for (int j = 0; j < i; ++j) y[i] -= lu_[i][j] * y[j];
    for (int i = n_ - 1; i >= 0; --i) {
      for (int j = i + 1; j < n_; ++j) y[i] -= lu_[i][j] * y[j];
      y[i] /= lu_[i][i];
    }
    for (int i = 0; i < n_; ++i) x[i] = y[i];
  }

  // inverse into inv(i, j)
  template <class Matrix>
  void inverse(Matrix& inv) const {
    double e[MaxN], x[MaxN];
    for (int j = 0; j < n_; ++j) {
      for (int i = 0; i < n_; ++i) e[i] = i == j ? 1.0 : 0.0;
      solve(e, x);
      for (int i = 0; i < n_; ++i) inv(i, j) = x[i];
    }
  }

  // 1-norm condition number |A|_1 |A^-1|_1 (exact: the blocks are tiny)
  double condition() const {
    if (!ok_) return INFINITY;
    double e[MaxN], x[MaxN], worst = 0.0;
    for (int j = 0; j < n_; ++j) {
      for (int i = 0; i < n_; ++i) e[i] = i == j ? 1.0 : 0.0;
      solve(e, x);
      double col = 0.0;
      for (int i = 0; i < n_; ++i) col += std::abs(x[i]);
      worst = std::max(worst, col);
    }
    return norm1_ * worst;
  }

 private:
  int n_ = 0;
  double lu_[MaxN][MaxN] = {};
  int piv_[MaxN] = {};
  double norm1_ = 0.0;
  bool ok_ = false;
};

}  // namespace camopt::kin
