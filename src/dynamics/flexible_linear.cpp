// the flexible model's structured matrices and CVODE's Newton system (flexible_system.hpp)
#include <algorithm>
#include <memory>

#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

void Structured::resize(int core_size, const std::vector<Chain>& chains) {
  core.setZero(core_size, core_size);
  bands.clear();
  for (const Chain& ch : chains)
    if (ch.masses > 0) bands.push_back({std::vector<double>(ch.masses, 0.0), std::vector<double>(ch.masses - 1, 0.0), 0.0});
}

void Structured::set_zero() {
  core.setZero();
  for (Band& b : bands) {
    std::fill(b.diag.begin(), b.diag.end(), 0.0);
    std::fill(b.off.begin(), b.off.end(), 0.0);
    b.couple = 0.0;
  }
}

void Structured::add(double s, const Structured& o) {
  core += s * o.core;
  for (std::size_t i = 0; i < bands.size(); ++i) {
    for (std::size_t j = 0; j < bands[i].diag.size(); ++j) bands[i].diag[j] += s * o.bands[i].diag[j];
    for (std::size_t j = 0; j < bands[i].off.size(); ++j) bands[i].off[j] += s * o.bands[i].off[j];
    bands[i].couple += s * o.bands[i].couple;
  }
}

void Structured::copy_from(const Structured& o) {
  core = o.core;
  for (std::size_t i = 0; i < bands.size(); ++i) bands[i] = o.bands[i];
}

void Structured::multiply(const std::vector<Chain>& chains, const double* x, double* y) const {
  const int nc = static_cast<int>(core.rows());
  Eigen::Map<const Eigen::VectorXd> xc(x, nc);
  Eigen::Map<Eigen::VectorXd>(y, nc).noalias() = core * xc;
  for (const Chain& ch : chains) {
    if (ch.masses == 0) continue;
    const Band& b = bands[ch.band];
    const int m = ch.masses, f = ch.first;
    for (int i = 0; i < m; ++i) {
      double s = b.diag[i] * x[f + i];
      if (i > 0) s += b.off[i - 1] * x[f + i - 1];
      if (i + 1 < m) s += b.off[i] * x[f + i + 1];
      y[f + i] = s;
    }
    y[f + m - 1] += b.couple * x[ch.row];
    y[ch.row] += b.couple * x[f + m - 1];
  }
}

void Structured::multiply_add(const std::vector<Chain>& chains, double a, const Structured& ma, const double* x,
                              double b, const Structured& mb, const double* y, double* out) {
  const int nc = static_cast<int>(ma.core.rows());
  Eigen::Map<Eigen::VectorXd> oc(out, nc);
  oc.noalias() = a * (ma.core * Eigen::Map<const Eigen::VectorXd>(x, nc));
  oc.noalias() += b * (mb.core * Eigen::Map<const Eigen::VectorXd>(y, nc));
  for (const Chain& ch : chains) {
    if (ch.masses == 0) continue;
    const Band& ba = ma.bands[ch.band];
    const Band& bb = mb.bands[ch.band];
    const int m = ch.masses, f = ch.first;
    const double* xs = x + f;
    const double* ys = y + f;
    double* o = out + f;
    // row i: diag x_i + off_{i-1} x_{i-1} + off_i x_{i+1} (no carried dependency)
    o[0] = a * ba.diag[0] * xs[0] + b * bb.diag[0] * ys[0];
    if (m > 1) o[0] += a * ba.off[0] * xs[1] + b * bb.off[0] * ys[1];
    for (int i = 1; i + 1 < m; ++i)
      o[i] = a * (ba.diag[i] * xs[i] + ba.off[i - 1] * xs[i - 1] + ba.off[i] * xs[i + 1]) +
             b * (bb.diag[i] * ys[i] + bb.off[i - 1] * ys[i - 1] + bb.off[i] * ys[i + 1]);
    if (m > 1)
      o[m - 1] = a * (ba.diag[m - 1] * xs[m - 1] + ba.off[m - 2] * xs[m - 2]) +
                 b * (bb.diag[m - 1] * ys[m - 1] + bb.off[m - 2] * ys[m - 2]);
    o[m - 1] += a * ba.couple * x[ch.row] + b * bb.couple * y[ch.row];
    out[ch.row] += a * ba.couple * xs[m - 1] + b * bb.couple * ys[m - 1];
  }
}

Eigen::MatrixXd Structured::dense(const std::vector<Chain>& chains, int n) const {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  const int nc = static_cast<int>(core.rows());
  a.topLeftCorner(nc, nc) = core;
  for (const Chain& ch : chains) {
    if (ch.masses == 0) continue;
    const Band& b = bands[ch.band];
    for (int i = 0; i < ch.masses; ++i) {
      a(ch.first + i, ch.first + i) = b.diag[i];
      if (i + 1 < ch.masses) a(ch.first + i, ch.first + i + 1) = a(ch.first + i + 1, ch.first + i) = b.off[i];
    }
    a(ch.first + ch.masses - 1, ch.row) += b.couple;
    a(ch.row, ch.first + ch.masses - 1) += b.couple;
  }
  return a;
}

// Thomas elimination of each band from the bottom mass up (no pivoting: the bands of
// M + gamma D + gamma^2 K are diagonally dominant), A_ss^-1 e_top by the same factors, and the
// Schur complement core - couple^2 (A_ss^-1)_top,top on the node row
bool StructuredLU::factor(const std::vector<Chain>& c) {
  chains = &c;
  pivots.resize(a.bands.size());
  top_column.resize(a.bands.size());
  Eigen::MatrixXd schur = a.core;
  for (const Chain& ch : c) {
    if (ch.masses == 0) continue;
    const Band& b = a.bands[ch.band];
    const int m = ch.masses;
    std::vector<double>& p = pivots[ch.band];
    std::vector<double>& z = top_column[ch.band];
    p.resize(m);
    z.assign(m, 0.0);
    // p holds the reciprocal pivots
    double pivot = b.diag[0];
    for (int i = 0; i < m; ++i) {
      if (i > 0) pivot = b.diag[i] - b.off[i - 1] * b.off[i - 1] * p[i - 1];
      if (!(std::abs(pivot) > 0.0) || !std::isfinite(pivot)) return false;
      p[i] = 1.0 / pivot;
    }
    // A_ss z = e_top: forward (only the last entry is non-zero), then back substitution
    z[m - 1] = p[m - 1];
    for (int i = m - 2; i >= 0; --i) z[i] = -b.off[i] * z[i + 1] * p[i];
    schur(ch.row, ch.row) -= b.couple * b.couple * z[m - 1];
  }
  lu.compute(schur);
  const Eigen::MatrixXd& f = lu.matrixLU();
  return f.allFinite() && f.diagonal().cwiseAbs().minCoeff() > 0.0;
}

void StructuredLU::solve(double* x) const {
  const int nc = static_cast<int>(a.core.rows());
  // y_s = A_ss^-1 r_s per band; r_c -= couple y_top
  for (const Chain& ch : *chains) {
    if (ch.masses == 0) continue;
    const Band& b = a.bands[ch.band];
    const std::vector<double>& p = pivots[ch.band];
    const int m = ch.masses, f = ch.first;
    double* y = x + f;
    for (int i = 1; i < m; ++i) y[i] -= b.off[i - 1] * p[i - 1] * y[i - 1];
    y[m - 1] *= p[m - 1];
    for (int i = m - 2; i >= 0; --i) y[i] = (y[i] - b.off[i] * y[i + 1]) * p[i];
    x[ch.row] -= b.couple * y[m - 1];
  }
  Eigen::Map<Eigen::VectorXd> xc(x, nc);
  work = xc;
  xc = lu.solve(work);
  // x_s = y_s - z couple x_row
  for (const Chain& ch : *chains) {
    if (ch.masses == 0) continue;
    const std::vector<double>& z = top_column[ch.band];
    const double t = a.bands[ch.band].couple * x[ch.row];
    for (int i = 0; i < ch.masses; ++i) x[ch.first + i] -= z[i] * t;
  }
}

namespace {

// ---- the SUNMatrix: beta I + alpha J ----
SUNMatrix_ID newton_matrix_id(SUNMatrix) { return SUNMATRIX_CUSTOM; }
void newton_matrix_destroy(SUNMatrix a) {
  if (!a) return;
  delete static_cast<NewtonMatrix*>(a->content);
  a->content = nullptr;
  SUNMatFreeEmpty(a);
}
SUNMatrix newton_matrix_clone(SUNMatrix a) {
  SUNMatrix b = SUNMatNewEmpty(a->sunctx);
  if (!b || SUNMatCopyOps(a, b) != 0) return nullptr;
  b->content = new NewtonMatrix(*static_cast<NewtonMatrix*>(a->content));
  return b;
}
int newton_matrix_zero(SUNMatrix a) {
  NewtonMatrix& c = newton_content(a);
  c.alpha = 0.0;
  c.beta = 0.0;
  return 0;
}
int newton_matrix_copy(SUNMatrix from, SUNMatrix to) {
  const NewtonMatrix& a = newton_content(from);
  NewtonMatrix& b = newton_content(to);
  b.k.copy_from(a.k);
  b.d.copy_from(a.d);
  b.m.copy_from(a.m);
  b.alpha = a.alpha;
  b.beta = a.beta;
  return 0;
}
// A <- c A + I
int newton_matrix_scale_add_identity(sunrealtype c, SUNMatrix a) {
  NewtonMatrix& m = newton_content(a);
  m.alpha *= c;
  m.beta = m.beta * c + 1.0;
  return 0;
}

// ---- the linear solver ----
struct NewtonSolver {
  StructuredLU lu;
  double alpha = 0.0, beta = 0.0;
  std::vector<double> rhs, tmp;
};
SUNLinearSolver_Type newton_solver_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID newton_solver_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int newton_solver_setup(SUNLinearSolver ls, SUNMatrix a) {
  auto* s = static_cast<NewtonSolver*>(ls->content);
  const NewtonMatrix& m = newton_content(a);
  if (m.beta == 0.0) return -1;
  s->alpha = m.alpha;
  s->beta = m.beta;
  // beta^2 M - alpha beta D + alpha^2 K
  s->lu.a.copy_from(m.m);
  s->lu.a.core *= m.beta * m.beta;
  for (Band& b : s->lu.a.bands) {
    for (double& v : b.diag) v *= m.beta * m.beta;
    for (double& v : b.off) v *= m.beta * m.beta;
    b.couple *= m.beta * m.beta;
  }
  s->lu.a.add(-m.alpha * m.beta, m.d);
  s->lu.a.add(m.alpha * m.alpha, m.k);
  return s->lu.factor(*m.chains) ? 0 : 1;
}
int newton_solver_solve(SUNLinearSolver ls, SUNMatrix a, N_Vector x, N_Vector b, sunrealtype) {
  auto* s = static_cast<NewtonSolver*>(ls->content);
  const NewtonMatrix& m = newton_content(a);
  const int n = m.n;
  const double* bv = N_VGetArrayPointer(b);
  double* xv = N_VGetArrayPointer(x);
  // x_v: (beta^2 M - alpha beta D + alpha^2 K) x_v = beta M b_v + alpha K b_q
  Structured::multiply_add(*m.chains, s->beta, m.m, bv + n, s->alpha, m.k, bv, s->rhs.data());
  s->lu.solve(s->rhs.data());
  // x_q = (b_q - alpha x_v) / beta
  for (int i = 0; i < n; ++i) {
    xv[i] = (bv[i] - s->alpha * s->rhs[i]) / s->beta;
    xv[n + i] = s->rhs[i];
  }
  return 0;
}
int newton_solver_free(SUNLinearSolver ls) {
  if (!ls) return 0;
  delete static_cast<NewtonSolver*>(ls->content);
  ls->content = nullptr;
  SUNLinSolFreeEmpty(ls);
  return 0;
}

}  // namespace

NewtonMatrix& newton_content(SUNMatrix a) { return *static_cast<NewtonMatrix*>(a->content); }

SUNMatrix make_newton_matrix(SUNContext ctx, const System& s) {
  SUNMatrix a = SUNMatNewEmpty(ctx);
  if (!a) return nullptr;
  auto* c = new NewtonMatrix;
  c->chains = &s.chains;
  c->n = s.N;
  c->k.resize(s.core(), s.chains);
  c->d.resize(s.core(), s.chains);
  c->m.resize(s.core(), s.chains);
  a->content = c;
  a->ops->getid = newton_matrix_id;
  a->ops->clone = newton_matrix_clone;
  a->ops->destroy = newton_matrix_destroy;
  a->ops->zero = newton_matrix_zero;
  a->ops->copy = newton_matrix_copy;
  a->ops->scaleaddi = newton_matrix_scale_add_identity;
  return a;
}

SUNLinearSolver make_newton_solver(SUNContext ctx, const System& s) {
  SUNLinearSolver ls = SUNLinSolNewEmpty(ctx);
  if (!ls) return nullptr;
  auto* c = new NewtonSolver;
  c->lu.a.resize(s.core(), s.chains);
  c->rhs.resize(s.N);
  c->tmp.resize(s.N);
  ls->content = c;
  ls->ops->gettype = newton_solver_type;
  ls->ops->getid = newton_solver_id;
  ls->ops->setup = newton_solver_setup;
  ls->ops->solve = newton_solver_solve;
  ls->ops->free = newton_solver_free;
  return ls;
}

}  // namespace camopt::dynamics::detail
