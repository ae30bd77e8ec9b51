// blocks solved simultaneously (a coupled cluster, or a contact with its surface
// parameters): the values by broyden from the last exact jacobian, newton with backtracking
// as the fallback and a global scan of the contact points as the last resort; then the
// taylor coefficients by implicit differentiation, J x_k = -r_k, on one factorisation of J
#include <algorithm>
#include <array>
#include <cmath>

#include "kernel.hpp"

namespace camopt::kin::detail {

namespace {

// out = a * v for the leading n x n block (no expression templates: n is 1 to 3 here)
void multiply(int n, const WorkspaceState::Matrix& a, const double* v, double* out) {
  for (int i = 0; i < n; ++i) {
    double s = 0.0;
    for (int j = 0; j < n; ++j) s += a(i, j) * v[j];
    out[i] = s;
  }
}

}  // namespace

double Kernel::evaluate(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f) {
  const int n = static_cast<int>(b.unknowns.size());
  for (int i = 0; i < n; ++i) st_.values[b.unknowns[i]] = x[i];
  block_residual(m_, b, st_.values.data(), st_.pivots.data(), st_.poses0, st_.point_id, st_.residual_buffer.data(),
                 f.data());
  double norm = 0.0;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(f[i])) return INFINITY;
    norm = std::max(norm, std::abs(f[i]));
  }
  return norm;
}

// exact jacobian by forward mode on Dual<M>: direction 0 carries the known variables'
// true first-order rates with every unknown rate zero, giving r_1 (b.r1); direction 1 + j
// seeds unknown first + j, giving column first + j of J. One sweep gives the residual
// itself (into f), r_1 and up to M - 1 columns.
template <int M>
void Kernel::jacobian_columns(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f, int first) {
  using D = Dual<M>;
  const int n = static_cast<int>(b.unknowns.size());
  const int cols = std::min(M - 1, n - first);
  auto& vars = st_.vars_dual<M>();
  for (std::size_t v = 0; v < st_.values.size(); ++v) {
    vars[v] = D(st_.values[v]);
    vars[v].d[0] = ws_.vars[v].c[1];
  }
  for (int i = 0; i < n; ++i) {
    vars[b.unknowns[i]] = D(x[i]);
    st_.values[b.unknowns[i]] = x[i];
  }
  for (int j = 0; j < cols; ++j) vars[b.unknowns[first + j]].d[1 + j] = 1.0;
  D out[WorkspaceState::max_block], scratch[4];
  block_residual(m_, b, vars.data(), DirectPoses<D>{m_, vars.data(), st_.pivots.data()}, scratch, out);
  for (int i = 0; i < n; ++i) {
    f[i] = out[i].v;
    b.r1[i] = out[i].d[0];
    for (int j = 0; j < cols; ++j) b.jacobian(i, first + j) = out[i].d[1 + j];
  }
}

// the exact jacobian and r_1 at x, and the residual there (into f); returns its norm
double Kernel::jacobian(WorkspaceState::Block& b, const WorkspaceState::Vector& x, WorkspaceState::Vector& f) {
  const int n = static_cast<int>(b.unknowns.size());
  CAMOPT_ASSERT(n <= WorkspaceState::max_block);
  switch (n) {
    case 1:
      jacobian_columns<2>(b, x, f, 0);
      break;
    case 2:
      jacobian_columns<3>(b, x, f, 0);
      break;
    case 3:
      jacobian_columns<4>(b, x, f, 0);
      break;
    default:
      for (int first = 0; first < n; first += WorkspaceState::max_dual - 1)
        jacobian_columns<WorkspaceState::max_dual>(b, x, f, first);
  }
  double norm = 0.0;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(f[i])) return INFINITY;
    norm = std::max(norm, std::abs(f[i]));
  }
  return norm;
}

bool Kernel::broyden(WorkspaceState::Block& b, double tol) {
  // "good" broyden update of the inverse jacobian (Broyden 1965; Kelley, Iterative
  // Methods for Linear and Nonlinear Equations, ch. 7), started from the last exact one.
  // When the last observed contraction says a step will converge, the step's residual is
  // taken from the jacobian sweep (which the derivatives need at the solution anyway):
  // the converged point then costs no separate residual evaluation.
  const int n = static_cast<int>(b.unknowns.size());
  double norm = evaluate(b, b.x, b.f);
  if (norm <= tol) return true;
  for (int it = 0; it < max_broyden_iterations; ++it) {
    ++ws_.stats.broyden_iterations;
    multiply(n, b.inverse, b.f.data(), b.dx.data());
    for (int i = 0; i < n; ++i) {
      b.dx[i] = -b.dx[i];
      b.x[i] += b.dx[i];
    }
    const bool speculate = it == 0 || norm * b.contraction <= tol;
    const double new_norm = speculate ? jacobian(b, b.x, b.f_new) : evaluate(b, b.x, b.f_new);
    b.jacobian_at_x = speculate;
    if (!std::isfinite(new_norm) || new_norm > 4.0 * norm) {
      for (int i = 0; i < n; ++i) b.x[i] -= b.dx[i];
      evaluate(b, b.x, b.f);
      b.jacobian_at_x = false;
      return false;
    }
    b.contraction = new_norm / norm;
    if (new_norm <= tol) {
      for (int i = 0; i < n; ++i) b.f[i] = b.f_new[i];
      return true;
    }
    for (int i = 0; i < n; ++i) b.f[i] = b.f_new[i] - b.f[i];  // df
    multiply(n, b.inverse, b.f.data(), b.u.data());
    double denom = 0.0;
    for (int i = 0; i < n; ++i) denom += b.dx[i] * b.u[i];
    if (std::abs(denom) > 1e-300) {
      // inverse += (dx - B^-1 df) (dx^T B^-1) / (dx^T B^-1 df)
      for (int j = 0; j < n; ++j) {
        double s = 0.0;
        for (int i = 0; i < n; ++i) s += b.dx[i] * b.inverse(i, j);
        b.row[j] = s;
      }
      for (int i = 0; i < n; ++i) {
        const double ui = (b.dx[i] - b.u[i]) / denom;
        for (int j = 0; j < n; ++j) b.inverse(i, j) += ui * b.row[j];
      }
    }
    for (int i = 0; i < n; ++i) b.f[i] = b.f_new[i];
    norm = new_norm;
  }
  b.jacobian_at_x = false;
  return false;
}

Status Kernel::newton(WorkspaceState::Block& b, double tol, double driver) {
  ++ws_.stats.newton_fallbacks;
  const int n = static_cast<int>(b.unknowns.size());
  double norm = evaluate(b, b.x, b.f);
  for (int it = 0; it < max_newton_iterations; ++it) {
    if (norm <= tol) return Status::success();
    ++ws_.stats.newton_iterations;
    jacobian(b, b.x, b.f);
    b.lu.factor(n, b.jacobian);
    b.lu.solve(b.f.data(), b.dx.data());
    bool finite = true;
    for (int i = 0; i < n; ++i) {
      b.dx[i] = -b.dx[i];
      finite &= std::isfinite(b.dx[i]);
    }
    if (!finite) break;
    // backtracking on the residual norm
    double step = 1.0, new_norm = 0.0;
    for (int ls = 0; ls < 30; ++ls) {
      for (int i = 0; i < n; ++i) b.u[i] = b.x[i] + step * b.dx[i];
      new_norm = evaluate(b, b.u, b.f_new);
      if (std::isfinite(new_norm) && new_norm < norm) break;
      step *= 0.5;
    }
    if (!(new_norm < norm)) {
      if (norm <= 1e3 * tol) return Status::success();  // at round-off: cannot improve further
      break;
    }
    b.x = b.u;
    b.f = b.f_new;
    norm = new_norm;
  }
  norm = evaluate(b, b.x, b.f);
  if (norm <= tol) return Status::success();
  const Connection& c = m_.connections[b.connections.front()];
  const std::string names = connection_names(m_, b.connections);
  return {StatusCode::no_convergence,
          "connection(s) " + names + " did not converge: residual " + fmt(norm) + " mm > tolerance " + fmt(tol) +
              " mm (" + (c.kind == ConnectionKind::contact ? "the follower cannot reach the cam surface, or the "
                                                              "contact jumped to another lobe"
                                                            : "the loop cannot close") + ")",
          driver_text(m_, driver) + ", residual " + fmt(norm) + " mm"};
}

// contact parameters from a global scan: used on the first point and after a failure
void Kernel::scan_contact_parameters(const WorkspaceState::Block& b) {
  for (int ci : b.connections) {
    const Connection& c = m_.connections[ci];
    if (c.kind != ConnectionKind::contact) continue;
    const Surface& sa = c.surface_a;
    const Surface& sb = c.surface_b;
    if (sa.variable < 0 && sb.variable < 0) continue;
    const double* v = st_.values.data();
    const auto pa = node_pose(m_, c.node_a, v, st_.pivots.data());
    const auto pb = node_pose(m_, c.node_b, v, st_.pivots.data());
    if (sa.variable >= 0 && sb.variable >= 0)
      scan_two_curves(c, pa, pb);
    else
      scan_curve_circle(c, pa, pb);
  }
}

namespace {
// the range a surface parameter is scanned over: a closed curve's polar angle [rad], or a
// flat face's length [mm] either side of its point
std::pair<double, double> scan_range(const Mechanism& m, const Surface& s) {
  if (s.kind == SurfaceKind::curve) return {0.0, 2 * pi};
  return {-2.0 * m.length_scale, 2.0 * m.length_scale};
}
}  // namespace

// two curves: the closest pair with antiparallel tangents on a 180 x 180 grid
void Kernel::scan_two_curves(const Connection& c, const Pose<double>& pa, const Pose<double>& pb) {
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  const auto [a0, a1] = scan_range(m_, sa);
  const auto [b0, b1] = scan_range(m_, sb);
  double best = 1e300, best_a = 0, best_b = 0;
  constexpr int n2 = 180;
  for (int i = 0; i < n2; ++i)
    for (int j = 0; j < n2; ++j) {
      st_.values[sa.variable] = a0 + (a1 - a0) * i / n2;
      st_.values[sb.variable] = b0 + (b1 - b0) * j / n2;
      const auto A = surface_point(m_, sa, pa, st_.values.data());
      const auto B = surface_point(m_, sb, pb, st_.values.data());
      const V2<double> d{B.p.x - A.p.x, B.p.y - A.p.y};
      const double align = 1.0 + dot(A.d1, B.d1) / std::sqrt(dot(A.d1, A.d1) * dot(B.d1, B.d1));
      const double score = std::sqrt(dot(d, d)) + m_.length_scale * align;
      if (score < best) best = score, best_a = st_.values[sa.variable], best_b = st_.values[sb.variable];
    }
  st_.values[sa.variable] = best_a;
  st_.values[sb.variable] = best_b;
}

// a curve or face against a circle: the parameter where the circle centre lies on the
// surface's normal, on the side facing it, best of 720 samples searched coarse to fine
void Kernel::scan_curve_circle(const Connection& c, const Pose<double>& pa, const Pose<double>& pb) {
  constexpr int samples = 720;
  const Surface& sa = c.surface_a;
  const Surface& sb = c.surface_b;
  const bool a_param = sa.variable >= 0;
  const Surface& sp = a_param ? sa : sb;   // the parametrised surface
  const Surface& so = a_param ? sb : sa;   // the circle (point + offset)
  const auto& pose_p = a_param ? pa : pb;
  const auto& pose_o = a_param ? pb : pa;
  const auto centre = pose_o.apply(so.origin.x(), so.origin.y());
  const auto [range_lo, range_hi] = scan_range(m_, sp);
  const double u0 = range_lo, u1 = range_hi;  // copies: a lambda cannot capture structured bindings in C++17 mode
  auto score_at = [&](int i) {
    st_.values[sp.variable] = u0 + (u1 - u0) * i / samples;
    const auto P = surface_point(m_, sp, pose_p, st_.values.data());
    const V2<double> d{centre.x - P.p.x, centre.y - P.p.y};
    const double len = std::sqrt(dot(P.d1, P.d1));
    const double along = std::abs(dot(d, P.d1)) / len;
    const double normal = (d.x * P.d1.y - d.y * P.d1.x) / len;  // d . outward normal
    // the contact candidate: tangency (along = 0) on the side facing the circle centre
    // (convex circle outside: normal > 0; concave circle around the curve: normal < 0)
    const bool facing = so.offset >= 0 ? normal > 0 : normal < 0;
    return along + (facing ? 0.0 : 1e6) + 1e-3 * std::abs(std::abs(normal) - std::abs(so.offset));
  };
  // the best of the `samples` grid, searched coarse to fine: every kCoarse-th sample, then
  // the grid within kCoarse samples of the kCandidates lowest coarse local minima (a closed
  // curve's grid is cyclic). Ties go to the lowest index, as in a scan of the whole grid.
  constexpr int kCoarse = 8, kCandidates = 4, coarse_count = samples / kCoarse;
  static_assert(samples % kCoarse == 0);
  const bool cyclic = sp.kind == SurfaceKind::curve;
  std::array<double, coarse_count> coarse;
  for (int k = 0; k < coarse_count; ++k) coarse[k] = score_at(k * kCoarse);
  std::array<int, coarse_count> minima;
  int minima_count = 0;
  for (int k = 0; k < coarse_count; ++k) {
    const bool below_left = k > 0 ? coarse[k] <= coarse[k - 1] : !cyclic || coarse[k] <= coarse[coarse_count - 1];
    const bool below_right =
        k + 1 < coarse_count ? coarse[k] <= coarse[k + 1] : !cyclic || coarse[k] <= coarse[0];
    if (below_left && below_right) minima[minima_count++] = k;
  }
  const int kept = std::min(kCandidates, minima_count);
  std::partial_sort(minima.begin(), minima.begin() + kept, minima.begin() + minima_count,
                    [&](int x, int y) { return coarse[x] < coarse[y] || (coarse[x] == coarse[y] && x < y); });
  double best = 1e300;
  int best_i = 0;
  auto consider = [&](int i, double score) {
    if (score < best || (score == best && i < best_i)) best = score, best_i = i;
  };
  for (int k = 0; k < coarse_count; ++k) consider(k * kCoarse, coarse[k]);
  for (int m = 0; m < kept; ++m)
    for (int j = -kCoarse + 1; j < kCoarse; ++j) {
      if (j == 0) continue;
      int i = minima[m] * kCoarse + j;
      if (cyclic) i = (i + samples) % samples;
      else if (i < 0 || i >= samples) continue;
      consider(i, score_at(i));
    }
  const double best_u = u0 + (u1 - u0) * best_i / samples;
  st_.values[sp.variable] = best_u;
}

Status Kernel::solve_values(WorkspaceState::Block& b, double driver) {
  const int n = static_cast<int>(b.unknowns.size());
  for (int i = 0; i < n; ++i) b.x[i] = st_.values[b.unknowns[i]];
  const double tol = tolerance();
  b.jacobian_at_x = false;
  if (b.jacobians >= 2 && b.last_driver != b.prev_driver) {
    // J(d) ~ J_last + (J_last - J_prev) (d - d_last) / (d_last - d_prev): the chord step
    // then errs by O(h^2) of the jacobian instead of O(h)
    const double w = (driver - b.last_driver) / (b.last_driver - b.prev_driver);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        b.jacobian(i, j) = b.last_jacobian(i, j) + w * (b.last_jacobian(i, j) - b.prev_jacobian(i, j));
    if (b.lu.factor(n, b.jacobian) && std::isfinite(b.lu.inverse(b.inverse))) b.have_inverse = true;
  }
  if (b.have_inverse && broyden(b, tol)) return Status::success();
  Status st = newton(b, tol, driver);
  if (!st.ok()) {
    // retry from a fresh scan of the contact points
    for (int i = 0; i < n; ++i) st_.values[b.unknowns[i]] = b.x[i];
    scan_contact_parameters(b);
    for (int i = 0; i < n; ++i) b.x[i] = st_.values[b.unknowns[i]];
    st = newton(b, tol, driver);
    if (!st.ok()) return st;
  }
  return Status::success();
}

// taylor coefficients of the block's unknowns: J x_k = -r_k, k = 1..order, where r_k is
// the order-k residual coefficient with the unknowns' order >= k terms still zero
Status Kernel::differentiate(WorkspaceState::Block& b, double driver) {
  const int n = static_cast<int>(b.unknowns.size());
  if (!b.jacobian_at_x) jacobian(b, b.x, b.f_new);  // also r_1 in b.r1
  b.jacobian_at_x = false;
  b.lu.factor(n, b.jacobian);
  // condition in the 1-norm, exact for these tiny blocks; the inverse starts the next
  // point's broyden iteration
  const double cond = b.lu.inverse(b.inverse);
  remember_jacobian(b, driver);
  b.have_inverse = std::isfinite(cond);
  ws_.max_condition = std::max(ws_.max_condition, cond);
  b.margin = scaled_margin(m_, st_, n, b.unknowns.data(), b.jacobian, b.inverse, b.r1.data());
  b.sign = b.lu.determinant_sign();
  note_margin(b.margin);
  if (!(cond < 1e13)) {
    const std::string names = connection_names(m_, b.connections);
    return {StatusCode::singular,
            "connection(s) " + names + " are singular (condition number " + fmt(cond) +
                "): a pressure angle reached 90 deg or a linkage is at toggle",
            driver_text(m_, driver)};
  }
  double rhs[WorkspaceState::max_block], xk[WorkspaceState::max_block];
  for (int i = 0; i < n; ++i) {
    ws_.vars[b.unknowns[i]] = Jet3(b.x[i]);
    rhs[i] = -b.r1[i];
  }
  b.lu.solve(rhs, xk);
  for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[1] = xk[i];
  ++ws_.stats.taylor_orders;
  {
    // order 2 needs only second-order jets: the known variables truncated to Jet<2>
    for (std::size_t v = 0; v < st_.values.size(); ++v) st_.vars2[v] = truncate<2>(ws_.vars[v]);
    Jet<2> out2[WorkspaceState::max_block];
    block_residual(m_, b, st_.vars2.data(), st_.pivots.data(), st_.poses2, st_.point_id, st_.residual_buffer2.data(),
                   out2);
    for (int i = 0; i < n; ++i) rhs[i] = -out2[i].c[2];
    b.lu.solve(rhs, xk);
    for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[2] = xk[i];
    ++ws_.stats.taylor_orders;
  }
  {
    Jet3 out[WorkspaceState::max_block];
    block_residual(m_, b, ws_.vars.data(), st_.pivots.data(), st_.poses3, st_.point_id, st_.residual_buffer3.data(),
                   out);
    for (int i = 0; i < n; ++i) rhs[i] = -out[i].c[3];
    b.lu.solve(rhs, xk);
    for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[3] = xk[i];
    ++ws_.stats.taylor_orders;
  }
  return Status::success();
}

}  // namespace camopt::kin::detail
