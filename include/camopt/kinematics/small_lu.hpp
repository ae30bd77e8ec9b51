#pragma once
// LU factorisation with partial pivoting for the small dense blocks of the kinematics
// kernel (n <= MaxN): no heap, no expression templates; Golub & Van Loan, Matrix
// Computations, 4th ed., alg. 3.4.1. The kernel factors one block per point, so the
// constant overhead of a general library routine dominated at n = 2 or 3: sizes 1 to 4
// run on loops with compile-time bounds (fully unrolled), larger ones on runtime bounds.
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
    switch (n) {
      case 1: ok_ = factor_in_place<1>(); break;
      case 2: ok_ = factor_in_place<2>(); break;
      case 3: ok_ = factor_in_place<3>(); break;
      case 4: ok_ = factor_in_place<4>(); break;
      default: ok_ = factor_in_place<0>();
    }
    return ok_;
  }

  bool ok() const { return ok_; }
  int size() const { return n_; }

  // sign of the determinant (+1 / -1), 0 when the factorisation failed
  int determinant_sign() const {
    if (!ok_) return 0;
    int sign = 1;
    for (int k = 0; k < n_; ++k) {
      if (piv_[k] != k) sign = -sign;
      if (lu_[k][k] < 0.0) sign = -sign;
    }
    return sign;
  }

  // x = A^-1 b (x may alias b)
  void solve(const double* b, double* x) const {
    switch (n_) {
      case 1: return solve_n<1>(b, x);
      case 2: return solve_n<2>(b, x);
      case 3: return solve_n<3>(b, x);
      case 4: return solve_n<4>(b, x);
      default: return solve_n<0>(b, x);
    }
  }

  // inverse into inv(i, j); returns the 1-norm condition number |A|_1 |A^-1|_1 (exact:
  // the blocks are tiny), infinite when the factorisation failed
  template <class Matrix>
  double inverse(Matrix& inv) const {
    return inverse_columns([&](int j, const double* x) {
      for (int i = 0; i < n_; ++i) inv(i, j) = x[i];
    });
  }

  // 1-norm condition number |A|_1 |A^-1|_1
  double condition() const {
    return inverse_columns([](int, const double*) {});
  }

 private:
  // column(j, x) for every column x of the inverse; returns the condition number
  template <class Column>
  double inverse_columns(Column&& column) const {
    double e[MaxN], x[MaxN], worst = 0.0;
    for (int j = 0; j < n_; ++j) {
      for (int i = 0; i < n_; ++i) e[i] = i == j ? 1.0 : 0.0;
      solve(e, x);
      double col = 0.0;
      for (int i = 0; i < n_; ++i) col += std::abs(x[i]);
      worst = std::max(worst, col);
      column(j, x);
    }
    return ok_ ? norm1_ * worst : INFINITY;
  }

  // N > 0: compile-time size, N = 0: n_
  template <int N>
  bool factor_in_place() {
    const int n = N > 0 ? N : n_;
    bool ok = true;
    for (int k = 0; k < n; ++k) {
      int p = k;
      for (int i = k + 1; i < n; ++i)
        if (std::abs(lu_[i][k]) > std::abs(lu_[p][k])) p = i;
      piv_[k] = p;
      if (p != k)
        for (int j = 0; j < n; ++j) std::swap(lu_[k][j], lu_[p][j]);
      if (lu_[k][k] == 0.0) {
        ok = false;
        continue;
      }
      const double inv = 1.0 / lu_[k][k];
      for (int i = k + 1; i < n; ++i) {
        const double l = lu_[i][k] *= inv;
        for (int j = k + 1; j < n; ++j) lu_[i][j] -= l * lu_[k][j];
      }
    }
    return ok;
  }

  template <int N>
  void solve_n(const double* b, double* x) const {
    const int n = N > 0 ? N : n_;
    double y[MaxN];
    for (int i = 0; i < n; ++i) y[i] = b[i];
    for (int k = 0; k < n; ++k)
      if (piv_[k] != k) std::swap(y[k], y[piv_[k]]);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < i; ++j) y[i] -= lu_[i][j] * y[j];
    for (int i = n - 1; i >= 0; --i) {
      for (int j = i + 1; j < n; ++j) y[i] -= lu_[i][j] * y[j];
      y[i] /= lu_[i][i];
    }
    for (int i = 0; i < n; ++i) x[i] = y[i];
  }

  int n_ = 0;
  double lu_[MaxN][MaxN] = {};
  int piv_[MaxN] = {};
  double norm1_ = 0.0;
  bool ok_ = false;
};

}  // namespace camopt::kin
