// compiled vector and dense-matrix kernels for SUNDIALS' serial N_Vector and dense SUNMatrix
// (see cvode_support.hpp, use_fast_ops). Semantics as in the SUNDIALS 6 user guide, "Description
// of the NVECTOR operations" and "The SUNMATRIX_DENSE module"; the stock serial
// implementations are the reference in tests/dynamics/cvode_fast_ops_test.cpp.
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "cvode_support.hpp"

namespace camopt::dynamics::detail {

namespace {

inline double* data(N_Vector v) { return NV_DATA_S(v); }
inline sunindextype size(N_Vector v) { return NV_LENGTH_S(v); }

void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  const sunindextype n = size(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] + b * yd[i];
}
void constant(double c, N_Vector z) { std::fill(data(z), data(z) + size(z), c); }
void product(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = xd[i] * yd[i];
}
void divide(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = xd[i] / yd[i];
}
void scale(double c, N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = c * xd[i];
}
void absolute(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = std::abs(xd[i]);
}
void inverse(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = 1.0 / xd[i];
}
void add_constant(N_Vector x, double b, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = xd[i] + b;
}
double dot(N_Vector x, N_Vector y) {
  const double *xd = data(x), *yd = data(y);
  double s = 0.0;
  for (sunindextype i = 0, n = size(x); i < n; ++i) s += xd[i] * yd[i];
  return s;
}
double max_norm(N_Vector x) {
  const double* xd = data(x);
  double m = 0.0;
  for (sunindextype i = 0, n = size(x); i < n; ++i) m = std::max(m, std::abs(xd[i]));
  return m;
}
// four partial sums (the vector unit's width: the serial sum is a chain of dependent adds)
double weighted_square_sum(N_Vector x, N_Vector w) {
  const double *xd = data(x), *wd = data(w);
  const sunindextype n = size(x);
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  sunindextype i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) {
      const double p = xd[i + k] * wd[i + k];
      s[k] += p * p;
    }
  for (; i < n; ++i) {
    const double p = xd[i] * wd[i];
    s[0] += p * p;
  }
  return (s[0] + s[1]) + (s[2] + s[3]);
}
double weighted_square_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const double *xd = data(x), *wd = data(w), *idd = data(id);
  double s = 0.0;
  for (sunindextype i = 0, n = size(x); i < n; ++i)
    if (idd[i] > 0.0) {
      const double p = xd[i] * wd[i];
      s += p * p;
    }
  return s;
}
double wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(size(x)));
}
double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(weighted_square_sum_mask(x, w, id) / static_cast<double>(size(x)));
}
double minimum(N_Vector x) {
  const double* xd = data(x);
  double m = xd[0];
  for (sunindextype i = 1, n = size(x); i < n; ++i) m = std::min(m, xd[i]);
  return m;
}
double wl2_norm(N_Vector x, N_Vector w) { return std::sqrt(weighted_square_sum(x, w)); }
double l1_norm(N_Vector x) {
  const double* xd = data(x);
  double s = 0.0;
  for (sunindextype i = 0, n = size(x); i < n; ++i) s += std::abs(xd[i]);
  return s;
}
void compare(double c, N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = size(x); i < n; ++i) zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
}
sunbooleantype inverse_test(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  bool ok = true;
  for (sunindextype i = 0, n = size(x); i < n; ++i) {
    if (xd[i] == 0.0) ok = false;
    else zd[i] = 1.0 / xd[i];
  }
  return ok ? SUNTRUE : SUNFALSE;
}
// constraint c_i: 2 x > 0, 1 x >= 0, -1 x <= 0, -2 x < 0, 0 none; m_i = 1 where violated
sunbooleantype constraint_mask(N_Vector c, N_Vector x, N_Vector m) {
  const double *cd = data(c), *xd = data(x);
  double* md = data(m);
  bool ok = true;
  for (sunindextype i = 0, n = size(x); i < n; ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    const bool strict = std::abs(cd[i]) > 1.5;
    const double signed_x = cd[i] > 0 ? xd[i] : -xd[i];
    if (strict ? signed_x <= 0.0 : signed_x < 0.0) md[i] = 1.0, ok = false;
  }
  return ok ? SUNTRUE : SUNFALSE;
}
double min_quotient(N_Vector num, N_Vector denom) {
  const double *nd = data(num), *dd = data(denom);
  double m = DBL_MAX;
  for (sunindextype i = 0, n = size(num); i < n; ++i)
    if (dd[i] != 0.0) m = std::min(m, nd[i] / dd[i]);
  return m;
}
// z = sum_j c_j X_j (z may be X_0)
int linear_combination(int nv, double* c, N_Vector* x, N_Vector z) {
  double* zd = data(z);
  const sunindextype n = size(z);
  for (sunindextype i = 0; i < n; ++i) {
    double s = 0.0;
    for (int j = 0; j < nv; ++j) s += c[j] * data(x[j])[i];
    zd[i] = s;
  }
  return 0;
}
// Z_j = a_j x + Y_j
int scale_add_multi(int nv, double* a, N_Vector x, N_Vector* y, N_Vector* z) {
  const double* xd = data(x);
  const sunindextype n = size(x);
  for (int j = 0; j < nv; ++j) {
    const double* yd = data(y[j]);
    double* zd = data(z[j]);
    for (sunindextype i = 0; i < n; ++i) zd[i] = a[j] * xd[i] + yd[i];
  }
  return 0;
}
int dot_multi(int nv, N_Vector x, N_Vector* y, double* d) {
  for (int j = 0; j < nv; ++j) d[j] = dot(x, y[j]);
  return 0;
}

// dense matrix: column-major SM_DATA_D of SM_LDATA_D entries
int matrix_zero(SUNMatrix a) {
  std::fill(SM_DATA_D(a), SM_DATA_D(a) + SM_LDATA_D(a), 0.0);
  return 0;
}
int matrix_copy(SUNMatrix a, SUNMatrix b) {  // b = a
  if (SM_ROWS_D(a) != SM_ROWS_D(b) || SM_COLUMNS_D(a) != SM_COLUMNS_D(b)) return SUNMAT_ILL_INPUT;
  std::copy(SM_DATA_D(a), SM_DATA_D(a) + SM_LDATA_D(a), SM_DATA_D(b));
  return 0;
}
int matrix_scale_add_identity(double c, SUNMatrix a) {  // a = c a + I
  double* d = SM_DATA_D(a);
  const sunindextype rows = SM_ROWS_D(a), cols = SM_COLUMNS_D(a);
  for (sunindextype k = 0, n = SM_LDATA_D(a); k < n; ++k) d[k] *= c;
  for (sunindextype j = 0; j < std::min(rows, cols); ++j) d[j * rows + j] += 1.0;
  return 0;
}
int matrix_scale_add(double c, SUNMatrix a, SUNMatrix b) {  // a = c a + b
  if (SM_ROWS_D(a) != SM_ROWS_D(b) || SM_COLUMNS_D(a) != SM_COLUMNS_D(b)) return SUNMAT_ILL_INPUT;
  double* d = SM_DATA_D(a);
  const double* e = SM_DATA_D(b);
  for (sunindextype k = 0, n = SM_LDATA_D(a); k < n; ++k) d[k] = c * d[k] + e[k];
  return 0;
}
SUNMatrix matrix_clone(SUNMatrix a) {
  SUNMatrix b = SUNDenseMatrix(SM_ROWS_D(a), SM_COLUMNS_D(a), a->sunctx);
  if (b) use_fast_ops(b);
  return b;
}

}  // namespace

void use_fast_ops(N_Vector v) {
  CAMOPT_ASSERT(N_VGetVectorID(v) == SUNDIALS_NVEC_SERIAL);
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = linear_sum;
  o->nvconst = constant;
  o->nvprod = product;
  o->nvdiv = divide;
  o->nvscale = scale;
  o->nvabs = absolute;
  o->nvinv = inverse;
  o->nvaddconst = add_constant;
  o->nvdotprod = dot;
  o->nvmaxnorm = max_norm;
  o->nvwrmsnorm = wrms_norm;
  o->nvwrmsnormmask = wrms_norm_mask;
  o->nvmin = minimum;
  o->nvwl2norm = wl2_norm;
  o->nvl1norm = l1_norm;
  o->nvcompare = compare;
  o->nvinvtest = inverse_test;
  o->nvconstrmask = constraint_mask;
  o->nvminquotient = min_quotient;
  o->nvlinearcombination = linear_combination;
  o->nvscaleaddmulti = scale_add_multi;
  o->nvdotprodmulti = dot_multi;
  // serial: the local reductions are the global ones
  o->nvdotprodlocal = dot;
  o->nvmaxnormlocal = max_norm;
  o->nvminlocal = minimum;
  o->nvl1normlocal = l1_norm;
  o->nvinvtestlocal = inverse_test;
  o->nvconstrmasklocal = constraint_mask;
  o->nvminquotientlocal = min_quotient;
  o->nvwsqrsumlocal = weighted_square_sum;
  o->nvwsqrsummasklocal = weighted_square_sum_mask;
}

void use_fast_ops(SUNMatrix a) {
  CAMOPT_ASSERT(SUNMatGetID(a) == SUNMATRIX_DENSE);
  a->ops->clone = matrix_clone;
  a->ops->zero = matrix_zero;
  a->ops->copy = matrix_copy;
  a->ops->scaleadd = matrix_scale_add;
  a->ops->scaleaddi = matrix_scale_add_identity;
}

}  // namespace camopt::dynamics::detail
