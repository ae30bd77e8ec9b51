#include "camopt/kinematics/solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

#include "camopt/kinematics/detail/branch_guard.hpp"

namespace camopt::kin {

using detail::connection_residual;
using detail::node_pose;
using detail::TrustOutcome;
using detail::surface_point;
using detail::V2;

namespace {

constexpr double pi = std::numbers::pi;
constexpr int max_newton_iterations = 40;
constexpr int max_broyden_iterations = 8;
constexpr double relative_tolerance = 1e-13;  // residual tolerance relative to the mechanism size
// step control (Workspace::trust_radius): a solved variable may move at most this far from
// its prediction. Distinct assembly branches are farther apart than this except next to a
// singular configuration (where the condition estimate grows), so a point within it is on
// the predicted branch; fine steps never come near it (their predictor error is < 1e-4 of it).
constexpr double trust_length_fraction = 0.02;  // [mm variables] of Mechanism::length_scale
constexpr double trust_angle_rad = 0.05;        // [rad variables] about 2.9 deg
constexpr double min_step_rad = 1e-6;           // smallest driver step of the halving [rad, or x length_scale mm]
constexpr double min_control_fraction = 1e-6;   // smallest control step, of the control move
// the taylor order every point is solved to, whatever is requested: the predictor and the
// step control depend on it (Request)
constexpr int continuation_order = 3;

template <int N>
double value_of(const Jet<N>& x) {
  return x.value();
}
template <int M>
double value_of(const detail::Dual<M>& x) {
  return x.value();
}

std::string fmt(double v) { return format_value(v, 6); }

std::string driver_text(const Mechanism& m, double driver) {
  return m.driver_is_angle() ? "driver " + fmt(driver * 180.0 / pi) + " deg" : "driver " + fmt(driver) + " mm";
}

// the one-equation form of a block (see Workspace::Block::OffsetContact): one contact, no
// lash opening, a profile curve on a known body, a circle on the one unknown body, which
// rotates or translates; its two unknowns are that body's displacement and the curve parameter
Workspace::Block::OffsetContact offset_contact(const Mechanism& m, const SolveStep& step) {
  Workspace::Block::OffsetContact oc;
  if (step.method != StepMethod::implicit || step.connections.size() != 1 || step.one_sided || step.output_node < 0 ||
      step.unknowns.size() != 2)
    return oc;
  const Connection& c = m.connections[step.connections[0]];
  if (c.kind != ConnectionKind::contact) return oc;
  const int u = step.output_node;
  const Node& node = m.nodes[u];
  if (node.kind == NodeKind::floating || (c.node_a != u && c.node_b != u) || c.node_a == c.node_b) return oc;
  const bool circle_on_a = c.node_a == u;
  const Surface& circle = circle_on_a ? c.surface_a : c.surface_b;
  const Surface& curve = circle_on_a ? c.surface_b : c.surface_a;
  if (circle.kind != SurfaceKind::point || curve.kind != SurfaceKind::curve || curve.variable < 0) return oc;
  oc.connection = step.connections[0];
  oc.unknown_node = u;
  oc.known_node = circle_on_a ? c.node_b : c.node_a;
  oc.curve_variable = curve.variable;
  oc.node_variable = node.first_variable;
  oc.curve_on_a = !circle_on_a;
  oc.centre_offset = circle.offset - c.lash;
  oc.centre = circle.origin;
  if (node.kind == NodeKind::rotational) {
    const Eigen::Vector2d arm = circle.origin - node.pivot;
    oc.arm = arm.norm();
    oc.arm_angle = std::atan2(arm.y(), arm.x());
    oc.cos_arm = std::cos(oc.arm_angle);
    oc.sin_arm = std::sin(oc.arm_angle);
    // a circle centred on the pivot does not move its body: leave the block to the general solver
    if (!(oc.arm > 1e-9 * m.length_scale)) return oc;
  }
  oc.active = true;
  return oc;
}

Workspace::Block make_block(const Mechanism& m, const SolveStep& step, bool tangency_only) {
  Workspace::Block b;
  b.connections = step.connections;
  for (int ci : step.connections) {
    const Connection& c = m.connections[ci];
    const int count = tangency_only ? c.equation_count - 1 : c.equation_count;
    for (int k = 0; k < count; ++k) b.equations.push_back({ci, k});
  }
  for (int v : step.unknowns)
    if (!tangency_only || m.variables[v].node < 0) b.unknowns.push_back(v);
  const int n = static_cast<int>(b.unknowns.size());
  b.solving.assign(m.nodes.size(), 0);
  for (int v : b.unknowns)
    if (m.variables[v].node >= 0) b.solving[m.variables[v].node] = 1;
  b.inverse.setZero(n, n);
  b.jacobian.setZero(n, n);
  b.last_jacobian.setZero(n, n);
  b.prev_jacobian.setZero(n, n);
  b.x.setZero(n);
  b.f.setZero(n);
  b.dx.setZero(n);
  b.f_new.setZero(n);
  b.u.setZero(n);
  b.row.setZero(n);
  b.r1.setZero(n);
  if (!tangency_only) b.offset = offset_contact(m, step);
  return b;
}

// residuals of a block at scalar type T; vars must hold every variable
template <class T, class Poses>
void block_residual(const Mechanism& m, const Workspace::Block& b, const T* vars, const Poses& poses, T* scratch,
                    T* out) {
  int i = 0;
  for (int ci : b.connections) {
    const Connection& c = m.connections[ci];
    connection_residual(m, c, vars, poses, scratch);
    for (const auto& [eci, k] : b.equations)
      if (eci == ci) out[i++] = scratch[k];
  }
}
template <class T>
void block_residual(const Mechanism& m, const Workspace::Block& b, const T* vars, const Eigen::Vector2d* pivots,
                    detail::PoseCache<T>& cache, long point, T* scratch, T* out) {
  block_residual(m, b, vars, detail::CachedPoses<T>{m, vars, pivots, cache, point, b.solving}, scratch, out);
}

class Kernel {
 public:
  // trust: check the point against the prediction (nullptr: accept any converged point);
  // smallest_step: the step from the last accepted point cannot be halved further
  Kernel(const Mechanism& m, Workspace& ws, const Request& rq, TrustOutcome* trust = nullptr,
         bool smallest_step = false)
      : m_(m), ws_(ws), rq_(rq), trust_(trust), smallest_step_(smallest_step) {}

  // the plan step `step` is not solved: `node`'s variables are set from `vars` (see
  // solve_prescribed), the step's contact parameters keep their values
  void prescribe(int step, int node, const Jet3* vars) {
    prescribed_step_ = step;
    prescribed_node_ = node;
    prescribed_vars_ = vars;
  }

  Status run(double driver);

 private:
  double evaluate(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f);
  double jacobian(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f);
  template <int M>
  void jacobian_columns(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f, int first);
  void finish_block(const Workspace::Block& b) {
    for (int v : b.unknowns)
      if (m_.variables[v].node >= 0) ws_.invalidate_pose(m_.variables[v].node);
  }
  Status solve_values(Workspace::Block& b, double driver);
  template <int M>
  Status solve_offset_contact(Workspace::Block& b, double driver, bool& solved);
  static void remember_jacobian(Workspace::Block& b, double driver) {
    const int n = static_cast<int>(b.unknowns.size());
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        b.prev_jacobian(i, j) = b.last_jacobian(i, j);
        b.last_jacobian(i, j) = b.jacobian(i, j);
      }
    b.prev_driver = b.last_driver;
    b.last_driver = driver;
    b.jacobians = std::min(b.jacobians + 1, 2);
  }
  bool broyden(Workspace::Block& b, double tol);
  Status newton(Workspace::Block& b, double tol, double driver);
  Status differentiate(Workspace::Block& b, double driver);
  void scan_contact_parameters(const Workspace::Block& b);
  Status closed_form(const SolveStep& step, int step_index, double driver);
  template <class T>
  Status distance_closed_form(const SolveStep& step, const T* vars, T& q, double driver, const Eigen::Vector2d& pin_u,
                              int k, const Eigen::Vector2d& pin_k, double L);
  template <class T>
  Status line_closed_form(const SolveStep& step, const T* vars, T& s_out, T& u_out, double& gap_at_rest,
                          double driver);
  void set_constant(int var, double v) {
    ws_.values[var] = v;
    ws_.vars[var] = Jet3(v);
  }
  void note_margin(double margin) { ws_.toggle_margin = std::min(ws_.toggle_margin, margin); }
  // the branch guard and the step control's bookkeeping of an accepted point
  bool guard(double driver);
  void accept(double driver);
  void contact_outputs(int step_index);
  // the pose of a node solved before this step: on jets through the point's jet-3 pose
  // cache (the contact outputs then truncate it instead of computing it again)
  template <class T>
  detail::Pose<T> known_pose(int n, const T* vars) const {
    if constexpr (std::is_same_v<T, Jet3>) {
      if (vars == ws_.vars.data())
        return detail::CachedPoses<Jet3>{m_, vars, ws_.pivots.data(), ws_.poses3, ws_.point_id, ws_.no_node_solving}
            .get(n);
    }
    return node_pose(m_, n, vars, ws_.pivots.data());
  }
  double tolerance() const { return relative_tolerance * m_.length_scale; }

  const Mechanism& m_;
  Workspace& ws_;
  const Request& rq_;
  TrustOutcome* trust_;
  bool smallest_step_;
  int prescribed_step_ = -1, prescribed_node_ = -1;
  const Jet3* prescribed_vars_ = nullptr;
};

// out = a * v for the leading n x n block (no expression templates: n is 1 to 3 here)
void multiply(int n, const Workspace::Matrix& a, const double* v, double* out) {
  for (int i = 0; i < n; ++i) {
    double s = 0.0;
    for (int j = 0; j < n; ++j) s += a(i, j) * v[j];
    out[i] = s;
  }
}

double Kernel::evaluate(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f) {
  const int n = static_cast<int>(b.unknowns.size());
  for (int i = 0; i < n; ++i) ws_.values[b.unknowns[i]] = x[i];
  block_residual(m_, b, ws_.values.data(), ws_.pivots.data(), ws_.poses0, ws_.point_id, ws_.residual_buffer.data(),
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
void Kernel::jacobian_columns(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f, int first) {
  using D = detail::Dual<M>;
  const int n = static_cast<int>(b.unknowns.size());
  const int cols = std::min(M - 1, n - first);
  auto& vars = ws_.vars_dual<M>();
  for (std::size_t v = 0; v < ws_.values.size(); ++v) {
    vars[v] = D(ws_.values[v]);
    vars[v].d[0] = ws_.vars[v].c[1];
  }
  for (int i = 0; i < n; ++i) {
    vars[b.unknowns[i]] = D(x[i]);
    ws_.values[b.unknowns[i]] = x[i];
  }
  for (int j = 0; j < cols; ++j) vars[b.unknowns[first + j]].d[1 + j] = 1.0;
  D out[Workspace::max_block], scratch[4];
  block_residual(m_, b, vars.data(), detail::DirectPoses<D>{m_, vars.data(), ws_.pivots.data()}, scratch, out);
  for (int i = 0; i < n; ++i) {
    f[i] = out[i].v;
    b.r1[i] = out[i].d[0];
    for (int j = 0; j < cols; ++j) b.jacobian(i, first + j) = out[i].d[1 + j];
  }
}

// the exact jacobian and r_1 at x, and the residual there (into f); returns its norm
double Kernel::jacobian(Workspace::Block& b, const Workspace::Vector& x, Workspace::Vector& f) {
  const int n = static_cast<int>(b.unknowns.size());
  CAMOPT_ASSERT(n <= Workspace::max_block);
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
      for (int first = 0; first < n; first += Workspace::max_dual - 1)
        jacobian_columns<Workspace::max_dual>(b, x, f, first);
  }
  double norm = 0.0;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(f[i])) return INFINITY;
    norm = std::max(norm, std::abs(f[i]));
  }
  return norm;
}

bool Kernel::broyden(Workspace::Block& b, double tol) {
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

Status Kernel::newton(Workspace::Block& b, double tol, double driver) {
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
  std::string names;
  for (int ci : b.connections) names += (names.empty() ? "'" : ", '") + m_.connections[ci].name + "'";
  return {StatusCode::no_convergence,
          "connection(s) " + names + " did not converge: residual " + fmt(norm) + " mm > tolerance " + fmt(tol) +
              " mm (" + (c.kind == ConnectionKind::contact ? "the follower cannot reach the cam surface, or the "
                                                              "contact jumped to another lobe"
                                                            : "the loop cannot close") + ")",
          driver_text(m_, driver) + ", residual " + fmt(norm) + " mm"};
}

// contact parameters from a global scan: used on the first point and after a failure
void Kernel::scan_contact_parameters(const Workspace::Block& b) {
  constexpr int samples = 720;
  for (int ci : b.connections) {
    const Connection& c = m_.connections[ci];
    if (c.kind != ConnectionKind::contact) continue;
    const Surface& sa = c.surface_a;
    const Surface& sb = c.surface_b;
    if (sa.variable < 0 && sb.variable < 0) continue;
    const double* v = ws_.values.data();
    const auto pa = node_pose(m_, c.node_a, v, ws_.pivots.data());
    const auto pb = node_pose(m_, c.node_b, v, ws_.pivots.data());
    auto range = [&](const Surface& s) -> std::pair<double, double> {
      if (s.kind == SurfaceKind::curve) return {0.0, 2 * pi};
      return {-2.0 * m_.length_scale, 2.0 * m_.length_scale};
    };
    if (sa.variable >= 0 && sb.variable >= 0) {
      // two curves: closest pair with antiparallel tangents
      const auto [a0, a1] = range(sa);
      const auto [b0, b1] = range(sb);
      double best = 1e300, best_a = 0, best_b = 0;
      constexpr int n2 = 180;
      for (int i = 0; i < n2; ++i)
        for (int j = 0; j < n2; ++j) {
          ws_.values[sa.variable] = a0 + (a1 - a0) * i / n2;
          ws_.values[sb.variable] = b0 + (b1 - b0) * j / n2;
          const auto A = surface_point(m_, sa, pa, ws_.values.data());
          const auto B = surface_point(m_, sb, pb, ws_.values.data());
          const V2<double> d{B.p.x - A.p.x, B.p.y - A.p.y};
          const double align = 1.0 + detail::dot(A.d1, B.d1) / std::sqrt(detail::dot(A.d1, A.d1) * detail::dot(B.d1, B.d1));
          const double score = std::sqrt(detail::dot(d, d)) + m_.length_scale * align;
          if (score < best) best = score, best_a = ws_.values[sa.variable], best_b = ws_.values[sb.variable];
        }
      ws_.values[sa.variable] = best_a;
      ws_.values[sb.variable] = best_b;
      continue;
    }
    const bool a_param = sa.variable >= 0;
    const Surface& sp = a_param ? sa : sb;   // the parametrised surface
    const Surface& so = a_param ? sb : sa;   // the circle (point + offset)
    const auto& pose_p = a_param ? pa : pb;
    const auto& pose_o = a_param ? pb : pa;
    const auto centre = pose_o.apply(so.origin.x(), so.origin.y());
    const auto [range_lo, range_hi] = range(sp);
    const double u0 = range_lo, u1 = range_hi;  // copies: clang 14 cannot capture structured bindings
    auto score_at = [&](int i) {
      ws_.values[sp.variable] = u0 + (u1 - u0) * i / samples;
      const auto P = surface_point(m_, sp, pose_p, ws_.values.data());
      const V2<double> d{centre.x - P.p.x, centre.y - P.p.y};
      const double len = std::sqrt(detail::dot(P.d1, P.d1));
      const double along = std::abs(detail::dot(d, P.d1)) / len;
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
    ws_.values[sp.variable] = best_u;
  }
}

Status Kernel::solve_values(Workspace::Block& b, double driver) {
  const int n = static_cast<int>(b.unknowns.size());
  for (int i = 0; i < n; ++i) b.x[i] = ws_.values[b.unknowns[i]];
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
    for (int i = 0; i < n; ++i) ws_.values[b.unknowns[i]] = b.x[i];
    scan_contact_parameters(b);
    for (int i = 0; i < n; ++i) b.x[i] = ws_.values[b.unknowns[i]];
    st = newton(b, tol, driver);
    if (!st.ok()) return st;
  }
  return Status::success();
}

// taylor coefficients of the block's unknowns: J x_k = -r_k, k = 1..order, where r_k is
// the order-k residual coefficient with the unknowns' order >= k terms still zero
Status Kernel::differentiate(Workspace::Block& b, double driver) {
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
  b.margin = detail::scaled_margin(m_, ws_, n, b.unknowns.data(), b.jacobian, b.inverse, b.r1.data());
  b.sign = b.lu.determinant_sign();
  note_margin(b.margin);
  if (!(cond < 1e13)) {
    std::string names;
    for (int ci : b.connections) names += (names.empty() ? "'" : ", '") + m_.connections[ci].name + "'";
    return {StatusCode::singular,
            "connection(s) " + names + " are singular (condition number " + fmt(cond) +
                "): a pressure angle reached 90 deg or a linkage is at toggle",
            driver_text(m_, driver)};
  }
  double rhs[Workspace::max_block], xk[Workspace::max_block];
  for (int i = 0; i < n; ++i) {
    ws_.vars[b.unknowns[i]] = Jet3(b.x[i]);
    rhs[i] = -b.r1[i];
  }
  b.lu.solve(rhs, xk);
  for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[1] = xk[i];
  ++ws_.stats.taylor_orders;
  {
    // order 2 needs only second-order jets: the known variables truncated to Jet<2>
    for (std::size_t v = 0; v < ws_.values.size(); ++v) ws_.vars2[v] = truncate<2>(ws_.vars[v]);
    Jet<2> out2[Workspace::max_block];
    block_residual(m_, b, ws_.vars2.data(), ws_.pivots.data(), ws_.poses2, ws_.point_id, ws_.residual_buffer2.data(),
                   out2);
    for (int i = 0; i < n; ++i) rhs[i] = -out2[i].c[2];
    b.lu.solve(rhs, xk);
    for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[2] = xk[i];
    ++ws_.stats.taylor_orders;
  }
  {
    Jet3 out[Workspace::max_block];
    block_residual(m_, b, ws_.vars.data(), ws_.pivots.data(), ws_.poses3, ws_.point_id, ws_.residual_buffer3.data(),
                   out);
    for (int i = 0; i < n; ++i) rhs[i] = -out[i].c[3];
    b.lu.solve(rhs, xk);
    for (int i = 0; i < n; ++i) ws_.vars[b.unknowns[i]].c[3] = xk[i];
    ++ws_.stats.taylor_orders;
  }
  return Status::success();
}

// ---- one-equation form of a curve-circle contact (Workspace::Block::OffsetContact) ----

// the one equation [mm]: the centre at its distance from the unknown body's pivot
// (rotational) or on the unknown body's line of travel (translational)
double offset_residual(const Workspace::Block::OffsetContact& oc, const Node& node, const Eigen::Vector2d& pivot,
                       const V2<double>& centre) {
  if (node.kind == NodeKind::rotational) {
    const double dx = centre.x - pivot.x(), dy = centre.y - pivot.y();  // [mm]: no overflow
    return std::sqrt(dx * dx + dy * dy) - oc.arm;
  }
  return node.direction.x() * (centre.y - oc.centre.y()) - node.direction.y() * (centre.x - oc.centre.x());
}

// the pose's values (its Taylor coefficients dropped)
template <int N>
detail::Pose<double> pose_values(const detail::Pose<Jet<N>>& p) {
  detail::Pose<double> out;
  out.tx = p.tx.value();
  out.ty = p.ty.value();
  out.c = p.c.value();
  out.s = p.s.value();
  out.rx = p.rx;
  out.ry = p.ry;
  return out;
}

// solves the block through its one equation g(u) = 0 by newton from the predicted u. One
// evaluation gives the centre as a taylor series of order M in u; while a newton step du is
// below `shift_limit` the series is shifted to the new u instead of evaluating the curve
// again (the truncation, ~ q^(M+1) du^(M+1-k) in the k-th coefficient, is below round-off).
// The taylor coefficients in the driver follow order by order, each linear in its u_k:
// C(t) = T(t) + R(t) (Q(u(t)) - r) (Faa di Bruno for Q), g_k = 0 for u_k. The body's
// displacement follows in closed form from the centre. solved = false (values untouched)
// leaves the block to the general solver.
// kept out of line: inlined into run() it changes the inlining of its own callees
template <int M>
[[gnu::noinline]] Status Kernel::solve_offset_contact(Workspace::Block& b, double driver, bool& solved) {
  // [rad or 2 pi chord fraction]: the first neglected term q_(M+1) du^(M+1) of the value
  // stays below round-off (order 1: ~1e-16 q_2)
  constexpr double shift_limit = M == 1 ? 1e-8 : 1e-7;
  const auto& oc = b.offset;
  const Connection& c = m_.connections[oc.connection];
  const Surface& curve = oc.curve_on_a ? c.surface_a : c.surface_b;
  const Node& node = m_.nodes[oc.unknown_node];
  const Eigen::Vector2d pivot = ws_.pivots[oc.unknown_node];
  constexpr int order = continuation_order;
  solved = false;
  const auto& pose3 = detail::CachedPoses<Jet3>{m_, ws_.vars.data(), ws_.pivots.data(), ws_.poses3, ws_.point_id,
                                                b.solving}
                          .get(oc.known_node);
  const auto pose0 = pose_values(pose3);
  const bool rotational = node.kind == NodeKind::rotational;
  // d g / d centre (a unit vector for the rotational arm, the travel's normal otherwise)
  auto gradient = [&](const V2<double>& centre) {
    if (!rotational) return V2<double>{-node.direction.y(), node.direction.x()};
    const double dx = centre.x - pivot.x(), dy = centre.y - pivot.y(), dist = std::sqrt(dx * dx + dy * dy);
    return V2<double>{dx / dist, dy / dist};
  };
  double u = ws_.values[oc.curve_variable];
  V2<Jet<M>> q;  // the centre in the curve body's frame, series in u
  V2<double> centre, centre_u;
  double g = 0.0, gu = 0.0;
  bool converged = false;
  constexpr int max_evaluations = 6, max_shifts = 3;
  double evaluated_at = u;
  for (int ev = 0; ev < max_evaluations && !converged; ++ev) {
    evaluated_at = u;
    q = detail::offset_local<M>(m_, curve, oc.centre_offset, u);
    bool reevaluate = false;
    for (int shifts = 0; shifts <= max_shifts && !reevaluate; ++shifts) {
      centre = pose0.apply(q.x.c[0], q.y.c[0]);
      centre_u = pose0.rotate(q.x.c[1], q.y.c[1]);
      g = offset_residual(oc, node, pivot, centre);
      gu = detail::dot(gradient(centre), centre_u);
      if (!std::isfinite(g) || !std::isfinite(gu) || gu == 0.0) return Status::success();
      if (std::abs(g) <= tolerance()) {
        converged = true;
        break;
      }
      if (shifts == max_shifts) break;
      ++ws_.stats.newton_iterations;
      const double du = -g / gu;
      u += du;
      reevaluate = std::abs(du) > shift_limit;
      if (!reevaluate) {
        taylor_shift(q.x, du);
        taylor_shift(q.y, du);
      }
    }
  }
  if (!converged) return Status::success();
  // the contact outputs evaluate the curve at the shifted u
  if (u != evaluated_at) m_.profiles[curve.profile].shift_memo(evaluated_at, u - evaluated_at);
  // the curve's unit tangent: along dC/du (the offset curve is parallel to the curve; a
  // reversed sign leaves the condition number below unchanged)
  const double centre_u_norm = std::sqrt(centre_u.x * centre_u.x + centre_u.y * centre_u.y);
  const V2<double> tangent{centre_u.x / centre_u_norm, centre_u.y / centre_u_norm};
  // the block's 2 x 2 jacobian of (tangency, closure) in (displacement, u), for its
  // condition: d/dq = (X_q . t, X_q . n), d/du = (-C_u . t, 0) with n = (t_y, -t_x)
  {
    const V2<double> xq = rotational ? V2<double>{-(centre.y - pivot.y()), centre.x - pivot.x()}
                                     : V2<double>{node.direction.x(), node.direction.y()};
    const V2<double> n{tangent.y, -tangent.x};
    const double a = detail::dot(xq, tangent), bb = -detail::dot(centre_u, tangent);
    const double cc = detail::dot(xq, n);
    const double det = -bb * cc;
    // |J|_1 |J^-1|_1, J^-1 = [[0, -b], [-c, a]] / det
    const double cond = std::max(std::abs(a) + std::abs(cc), std::abs(bb)) *
                        std::max(std::abs(cc), std::abs(bb) + std::abs(a)) / std::abs(det);
    ws_.max_condition = std::max(ws_.max_condition, cond);
    // the cosine of the pressure angle: the normal against the centre's direction of motion
    b.margin = std::abs(cc) / std::sqrt(detail::dot(xq, xq));
    b.sign = det > 0 ? 2 : det < 0 ? -2 : 0;
    note_margin(b.margin);
    if (!(cond < 1e13))
      return {StatusCode::singular,
              "connection(s) '" + c.name + "' are singular (condition number " + fmt(cond) +
                  "): a pressure angle reached 90 deg or a linkage is at toggle",
              driver_text(m_, driver)};
  }
  // taylor coefficients in the driver, order by order: u_k, the centre C_k and the
  // body-frame lever L = Q - r (Q_k from Q(u(t)), Faa di Bruno up to order 3)
  Jet3 uj(u), cx(centre.x), cy(centre.y);
  V2<double> lever[4] = {{q.x.c[0] - pose3.rx, q.y.c[0] - pose3.ry}, {0, 0}, {0, 0}, {0, 0}};
  const V2<double> q1{q.x.c[1], q.y.c[1]};
  const V2<double> d0{centre.x - pivot.x(), centre.y - pivot.y()};  // rotational: centre - pivot
  const V2<double> travel_normal{-node.direction.y(), node.direction.x()};
  for (int k = 1; k <= order; ++k) {
    // Q_k without its u_k term
    const double u1 = uj.c[1], u2 = uj.c[2];
    V2<double> known{0.0, 0.0};
    if constexpr (M >= 2) {
      if (k == 2) known = {q.x.c[2] * u1 * u1, q.y.c[2] * u1 * u1};
    }
    if constexpr (M >= 3) {
      if (k == 3) {
        const double a2 = 2.0 * u1 * u2, a3 = u1 * u1 * u1;
        known = {q.x.c[2] * a2 + q.x.c[3] * a3, q.y.c[2] * a2 + q.y.c[3] * a3};
      }
    }
    // C_k without its u_k term: T_k + sum_{i=1..k} R_i L_{k-i} + R_0 known
    V2<double> ck{pose3.tx.c[k], pose3.ty.c[k]};
    for (int i = 1; i <= k; ++i) {
      const double ci = pose3.c.c[i], si = pose3.s.c[i];
      const V2<double>& l = lever[k - i];
      ck.x += ci * l.x - si * l.y;
      ck.y += si * l.x + ci * l.y;
    }
    ck.x += pose0.c * known.x - pose0.s * known.y;
    ck.y += pose0.s * known.x + pose0.c * known.y;
    // g_k = 0, linear in u_k through C_u u_k
    double uk;
    if (rotational) {
      // |C - P|^2 = arm^2: 2 D_0 . D_k + sum_{0<i<k} D_i . D_{k-i} = 0
      double rest = 2.0 * detail::dot(d0, ck);
      const V2<double> d1{cx.c[1], cy.c[1]}, d2{cx.c[2], cy.c[2]};
      if (k == 2) rest += detail::dot(d1, d1);
      if (k == 3) rest += 2.0 * detail::dot(d1, d2);
      uk = -rest / (2.0 * detail::dot(d0, centre_u));
    } else {
      uk = -detail::dot(travel_normal, ck) / detail::dot(travel_normal, centre_u);
    }
    uj.c[k] = uk;
    ++ws_.stats.taylor_orders;
    lever[k] = {known.x + q1.x * uk, known.y + q1.y * uk};
    cx.c[k] = ck.x + centre_u.x * uk;
    cy.c[k] = ck.y + centre_u.y * uk;
  }
  // the body's displacement from its circle centre
  Jet3 qn;
  if (rotational) {
    qn = atan2(cy - pivot.y(), cx - pivot.x()) - oc.arm_angle;
    // the branch nearest the prediction (the general solver tracks it continuously)
    const double turns = std::round((ws_.values[oc.node_variable] - qn.value()) / (2 * pi));
    qn.c[0] += turns * 2 * pi;
    // sin and cos of the body's angle from the arm's direction d0 / |d0| turned back by the
    // arm angle: the body's pose then needs no libm call
    const double dist = std::sqrt(d0.x * d0.x + d0.y * d0.y);
    const double ca = d0.x / dist, sa = d0.y / dist;
    memo_sin_cos_insert(qn.value(), sa * oc.cos_arm - ca * oc.sin_arm, ca * oc.cos_arm + sa * oc.sin_arm);
  } else {
    qn = node.direction.x() * (cx - oc.centre.x()) + node.direction.y() * (cy - oc.centre.y());
  }
  ws_.values[oc.curve_variable] = u;
  ws_.values[oc.node_variable] = qn.value();
  ws_.vars[oc.curve_variable] = uj;
  ws_.vars[oc.node_variable] = qn;
  solved = true;
  return Status::success();
}

// |pin_u(q) - pin_k| = L for the one unknown q of node u (rotational: law of cosines in the
// triangle pivot - known pin - unknown pin; translational: a quadratic in the travel)
template <class T>
Status Kernel::distance_closed_form(const SolveStep& step, const T* vars, T& q, double driver,
                                    const Eigen::Vector2d& pin_u, int k, const Eigen::Vector2d& pin_k, double L) {
  using std::acos;
  // the message prefix is built only on failure (no allocation on the hot path)
  const auto what = [&] {
    const Connection& c = m_.connections[step.connections[0]];
    return (c.kind == ConnectionKind::contact ? "contact '" : "link '") + c.name + "'";
  };
  using std::atan2;
  using std::sqrt;
  const int u = step.output_node;
  const Node& node = m_.nodes[u];
  const auto pk = known_pose(k, vars).apply(pin_k.x(), pin_k.y());
  if (node.kind == NodeKind::rotational) {
    const Eigen::Vector2d o = ws_.pivots[u];
    const Eigen::Vector2d a0 = pin_u - node.pivot;
    const double rho = a0.norm();
    const V2<T> d{pk.x - o.x(), pk.y - o.y()};
    const T dist2 = detail::dot(d, d);
    const T dist = sqrt(dist2);
    const T cos_beta = (dist2 + rho * rho - L * L) / (2.0 * dist * rho);
    const double cb = value_of(cos_beta);
    if (!(std::abs(cb) <= 1.0))
      return {StatusCode::cannot_assemble,
              what() + " cannot close: pivot of '" + node.name + "' is " + fmt(value_of(dist)) +
                  " mm from the known point, outside the reach [" + fmt(std::abs(rho - L)) + ", " + fmt(rho + L) +
                  "] mm of arm " + fmt(rho) + " mm and distance " + fmt(L) + " mm",
              driver_text(m_, driver)};
    ws_.max_condition = std::max(ws_.max_condition, 1.0 / std::max(1e-300, std::sqrt(1.0 - cb * cb)));
    // the transmission angle mu at the unknown pin: sin mu / dist = sin beta / L (law of sines)
    note_margin(std::min(1.0, value_of(dist) * std::sqrt(1.0 - cb * cb) / L));
    if (std::abs(cb) == 1.0)
      return {StatusCode::singular, what() + " is exactly at toggle (transmission angle 0 or 180 deg)",
              driver_text(m_, driver)};
    const T beta = acos(cos_beta);
    q = atan2(d.y, d.x) + double(step.branch) * beta - atan2_by_atan(a0.y(), a0.x());
  } else {
    // slider: |pin_u + s dir - pk| = L  ->  s^2 + 2 w s + (|e|^2 - L^2) = 0
    const V2<T> e{pin_u.x() - pk.x, pin_u.y() - pk.y};
    const T w = node.direction.x() * e.x + node.direction.y() * e.y;
    const T disc = w * w - (detail::dot(e, e) - L * L);
    if (!(value_of(disc) >= 0.0))
      return {StatusCode::cannot_assemble,
              what() + " cannot close: the line of '" + node.name + "' passes farther than " + fmt(L) +
                  " mm from the known point",
              driver_text(m_, driver)};
    if (value_of(disc) == 0.0)
      return {StatusCode::singular, what() + " is at toggle (perpendicular to the slide)", driver_text(m_, driver)};
    ws_.max_condition = std::max(ws_.max_condition, L / std::sqrt(value_of(disc)));
    note_margin(std::sqrt(value_of(disc)) / L);  // the cosine of the link's angle to the slide
    q = -w + double(step.branch) * sqrt(disc);
  }
  return Status::success();
}

// a circle against a flat face, one of them on the translating unknown: the closure
// (c - q_line) . n - r + lash = 0 is linear in the travel s; the face parameter is the
// foot of the circle centre on the face. gap_at_rest (s = rest) is returned for lash.
template <class T>
Status Kernel::line_closed_form(const SolveStep& step, const T* vars, T& s_out, T& u_out, double& gap_at_rest,
                                double driver) {
  const Connection& c = m_.connections[step.connections[0]];
  const int un = step.output_node;
  const Node& node = m_.nodes[un];
  const bool line_on_a = c.surface_a.kind == SurfaceKind::line;
  const Surface& line = line_on_a ? c.surface_a : c.surface_b;
  const Surface& circle = line_on_a ? c.surface_b : c.surface_a;
  const int line_node = line_on_a ? c.node_a : c.node_b;
  const int circle_node = line_on_a ? c.node_b : c.node_a;
  const double tx0 = -line.normal.y(), ty0 = line.normal.x();
  const Eigen::Vector2d dir = node.direction;
  V2<T> centre, point, n, t;
  T k;  // d(closure)/ds
  if (line_node == un) {
    const auto pose = known_pose(circle_node, vars);
    centre = pose.apply(circle.origin.x(), circle.origin.y());
    point = {T(line.origin.x()), T(line.origin.y())};  // the face at s = 0
    n = {T(line.normal.x()), T(line.normal.y())};
    t = {T(tx0), T(ty0)};
    k = T(-(dir.x() * line.normal.x() + dir.y() * line.normal.y()));
  } else {
    const auto pose = known_pose(line_node, vars);
    point = pose.apply(line.origin.x(), line.origin.y());
    n = pose.rotate(line.normal.x(), line.normal.y());
    t = pose.rotate(tx0, ty0);
    centre = {T(circle.origin.x()), T(circle.origin.y())};  // the circle at s = 0
    k = dir.x() * n.x + dir.y() * n.y;
  }
  const V2<T> d{centre.x - point.x, centre.y - point.y};
  const T closure0 = detail::dot(d, n) - circle.offset + c.lash;  // at s = 0
  const double kv = value_of(k);
  if (!(std::abs(kv) > 1e-12))
    return {StatusCode::singular,
            "contact '" + c.name + "': the face normal is perpendicular to the travel of '" + node.name +
                "' (pressure angle 90 deg)",
            driver_text(m_, driver)};
  ws_.max_condition = std::max(ws_.max_condition, 1.0 / std::abs(kv));
  note_margin(std::abs(kv));  // the cosine of the pressure angle
  s_out = -closure0 / k;
  gap_at_rest = value_of(closure0) + kv * node.rest;
  // foot of the centre on the face, in the face's own parameter
  const double sign = line_node == un ? -1.0 : 1.0;  // the moving side shifts d by s dir
  const V2<T> ds{d.x + sign * s_out * dir.x(), d.y + sign * s_out * dir.y()};
  u_out = detail::dot(ds, t);
  return Status::success();
}

Status Kernel::closed_form(const SolveStep& step, int step_index, double driver) {
  const Connection& c = m_.connections[step.connections[0]];
  const int var = m_.nodes[step.output_node].first_variable;
  const bool out_b = step.output_node == c.node_b;
  const int ia = m_.nodes[c.node_a].first_variable, ib = m_.nodes[c.node_b].first_variable;
  Jet3 q;
  ws_.open[step_index] = false;
  auto hold_at_rest = [&](double gap) {
    ws_.open[step_index] = true;
    ws_.contacts[step.connections[0]].gap = gap;
    set_constant(var, m_.nodes[step.output_node].rest);
    ws_.invalidate_pose(step.output_node);
  };
  switch (step.method) {
    case StepMethod::link_closed_form:
    case StepMethod::contact_distance_closed_form: {
      const int u = step.output_node, k = u == c.node_a ? c.node_b : c.node_a;
      Eigen::Vector2d pin_u, pin_k;
      double L = c.length;
      if (step.method == StepMethod::contact_distance_closed_form) {
        const Surface& su = u == c.node_a ? c.surface_a : c.surface_b;
        const Surface& sk = u == c.node_a ? c.surface_b : c.surface_a;
        pin_u = su.origin;
        pin_k = sk.origin;
        // centre distance at contact: r_a + r_b (outside) or R - r (inside a concave circle)
        const bool inside = su.offset < 0 || sk.offset < 0;
        const double touching = std::abs(su.offset + sk.offset);
        L = inside ? touching + c.lash : touching - c.lash;
        if (c.one_sided) {
          // the follower at rest: is the physical gap open?
          ws_.values[var] = m_.nodes[u].rest;
          const auto pu = node_pose(m_, u, ws_.values.data(), ws_.pivots.data()).apply(pin_u.x(), pin_u.y());
          const auto pk = node_pose(m_, k, ws_.values.data(), ws_.pivots.data()).apply(pin_k.x(), pin_k.y());
          const double dist = std::hypot(pu.x - pk.x, pu.y - pk.y);
          const double gap = (inside ? touching - dist : dist - touching) + c.lash;
          if (gap > 0.0) {
            hold_at_rest(gap);
            return Status::success();
          }
          ws_.contacts[step.connections[0]].gap = 0.0;
        }
      } else {
        pin_u = u == c.node_a ? c.pin_a : c.pin_b;
        pin_k = u == c.node_a ? c.pin_b : c.pin_a;
      }
      const double previous = ws_.values[var];
      ++ws_.stats.jet_closed_forms;
      Status st = distance_closed_form(step, ws_.vars.data(), q, driver, pin_u, k, pin_k, L);
      if (!st.ok()) return st;
      if (m_.nodes[step.output_node].kind == NodeKind::rotational) {
        // keep the angle continuous with the previous value
        const double turns = std::round((previous - q.value()) / (2 * pi));
        q.c[0] += turns * 2 * pi;
      }
      break;
    }
    case StepMethod::contact_line_closed_form: {
      const Surface& line = c.surface_a.kind == SurfaceKind::line ? c.surface_a : c.surface_b;
      Jet3 u;
      double gap_at_rest = 0.0;
      ++ws_.stats.jet_closed_forms;
      Status st = line_closed_form(step, ws_.vars.data(), q, u, gap_at_rest, driver);
      if (!st.ok()) return st;
      if (c.one_sided && gap_at_rest > 0.0) {
        // open: the follower rests; the face parameter is the foot of the centre at rest
        const double rest = m_.nodes[step.output_node].rest;
        const double shift = rest - q.value();
        const Node& node = m_.nodes[step.output_node];
        const bool line_moves = (c.surface_a.kind == SurfaceKind::line) == (step.output_node == c.node_a);
        const double tx = -line.normal.y(), ty = line.normal.x();
        // the face moving by +shift moves the foot by -shift (dir . t); the circle by +shift
        const double du = (line_moves ? -1.0 : 1.0) * shift * (node.direction.x() * tx + node.direction.y() * ty);
        hold_at_rest(gap_at_rest);
        u = Jet3(u.value() + du);
        ws_.vars[line.variable] = u;
        ws_.values[line.variable] = u.value();
        return Status::success();
      }
      if (c.one_sided) ws_.contacts[step.connections[0]].gap = 0.0;
      ws_.vars[line.variable] = u;
      ws_.values[line.variable] = u.value();
      break;
    }
    case StepMethod::gear_closed_form:
      q = out_b ? c.ratio * ws_.vars[ia] : ws_.vars[ib] / c.ratio;
      break;
    case StepMethod::rack_closed_form:
      q = out_b ? c.pitch_radius * ws_.vars[ia] : ws_.vars[ib] / c.pitch_radius;
      break;
    case StepMethod::variable_gear_closed_form:
      q = detail::gear_integral(c, ws_.vars[ia]);
      break;
    case StepMethod::implicit:
      CAMOPT_ASSERT(false);
  }
  ws_.vars[var] = q;
  ws_.values[var] = q.value();
  ws_.invalidate_pose(step.output_node);
  return Status::success();
}

Status Kernel::run(double driver) {
  const int nv = static_cast<int>(m_.variables.size());
  const bool fresh = ws_.history == 0;
  ++ws_.point_id;  // every cached pose is stale
  const bool check = trust_ != nullptr && ws_.history >= 1;
  // predictor for the warm start: the taylor series (continuation_order) from the last point
  if (ws_.history >= 1) {
    const double h = driver - ws_.prev_driver, step = ws_.prev_driver - ws_.prev2_driver;
    const bool two = ws_.history >= 2 && step != 0.0;
    // quartic term from the change of the cubic coefficient: d c_3 / dt = 4 c_4
    const double quartic = two ? h * h * h * h / (4.0 * step) : 0.0;
    const double cubic = h * h * h;
    const Jet3* jets = ws_.prev_jets.data();
    const Jet3* jets2 = ws_.prev2_jets.data();
    const double* prev = ws_.prev_values.data();
    const double* radius = ws_.trust_radius.data();
    double* x = ws_.values.data();
    double* predicted = ws_.predicted.data();
    double* error = ws_.predicted_error.data();
    bool beyond = false;
    for (int v = 0; v < nv; ++v) {
      const Jet3& j = jets[v];
      const double q = (j.c[3] - jets2[v].c[3]) * quartic;
      const double xv = prev[v] + h * (j.c[1] + h * (j.c[2] + h * j.c[3])) + q;
      // the highest terms taken, cubic and quartic, estimate the predictor's error
      error[v] = std::abs(cubic * j.c[3] + q);
      beyond |= error[v] > radius[v];
      x[v] = xv;
      predicted[v] = xv;
    }
    // a step beyond the predictor's reach is halved before any solve
    if (check && beyond) {
      for (int v = 0; v < nv && !trust_->rejected; ++v)
        if (error[v] > radius[v]) trust_->reject(TrustOutcome::Kind::predicted, v, error[v], radius[v]);
      return Status::success();
    }
  }
  // known variables: driver and control-set nodes
  ws_.values[m_.driver_variable()] = driver;
  ws_.vars[m_.driver_variable()] = Jet3::variable(driver, 1.0);
  for (const auto& n : m_.nodes)
    if (n.control >= 0) {
      const double cv = ws_.controls()[n.control];
      set_constant(n.first_variable, m_.controls[n.control].is_angle ? cv * pi / 180.0 : cv);
    }
  ws_.max_condition = 0.0;
  ws_.toggle_margin = 1.0;
  for (std::size_t si = 0; si < m_.plan.size(); ++si) {
    const SolveStep& step = m_.plan[si];
    ws_.full_blocks[si].solved = false;
    if (static_cast<int>(si) == prescribed_step_) {
      // the node as given; the contact parameters stay where they were last solved
      const Node& node = m_.nodes[static_cast<std::size_t>(prescribed_node_)];
      for (int v : step.unknowns) ws_.vars[v] = Jet3(ws_.values[v] = ws_.predicted[v] = ws_.prev_values[v]);
      for (int k = 0; k < node.dof; ++k) {
        const int v = node.first_variable + k;
        ws_.vars[v] = prescribed_vars_[k];
        ws_.values[v] = ws_.vars[v].value();
      }
      ws_.invalidate_pose(prescribed_node_);
      continue;
    }
    if (step.method != StepMethod::implicit) {
      Status st = closed_form(step, static_cast<int>(si), driver);
      if (!st.ok()) return st;
      continue;
    }
    auto& b = ws_.full_blocks[si];
    if (fresh) scan_contact_parameters(b);
    ws_.open[si] = false;
    if (step.one_sided) {
      // lash: with the follower at rest, is the closure residual (= the physical gap) open?
      const int var = m_.nodes[step.output_node].first_variable;
      auto& t = ws_.tangency_blocks[si];
      const double saved = ws_.values[var];
      ws_.values[var] = m_.nodes[step.output_node].rest;
      double gap = 0.0;
      Status st = Status::success();
      if (!t.unknowns.empty()) {
        st = solve_values(t, driver);
      }
      if (st.ok()) {
        const Connection& c = m_.connections[step.connections[0]];
        double r[3];
        connection_residual(m_, c, ws_.values.data(),
                            detail::DirectPoses<double>{m_, ws_.values.data(), ws_.pivots.data()}, r);
        gap = r[c.equation_count - 1];
      }
      if (st.ok() && gap > 0.0) {
        ws_.open[si] = true;
        set_constant(var, m_.nodes[step.output_node].rest);
        if (!t.unknowns.empty()) {
          Status dst = differentiate(t, driver);
          if (!dst.ok()) return dst;
        }
        ws_.contacts[step.connections[0]].gap = gap;
        ws_.invalidate_pose(step.output_node);
        continue;
      }
      ws_.values[var] = saved;
      ws_.invalidate_pose(step.output_node);
      ws_.contacts[step.connections[0]].gap = 0.0;
    }
    if (b.offset.active && !fresh && ws_.offset_contacts) {
      bool solved = false;
      // the derivatives need the centre's series to order 4 in u (see there)
      Status st = solve_offset_contact<4>(b, driver, solved);
      if (!st.ok()) return st;
      if (solved) {
        b.solved = true;
        finish_block(b);
        continue;
      }
      // the general solver takes over from the prediction: no stale warm start
      b.have_inverse = false;
      b.jacobians = 0;
    }
    Status st = solve_values(b, driver);
    if (!st.ok()) return st;
    Status dst = differentiate(b, driver);
    if (!dst.ok()) return dst;
    b.solved = true;
    finish_block(b);
  }
  for (int v = 0; v < nv; ++v) {
    if (!std::isfinite(ws_.values[v]))
      return {StatusCode::no_convergence, "variable '" + m_.variables[v].name + "' is not finite",
              driver_text(m_, driver)};
  }
  // a converged point off the predicted branch is rejected: the step is halved
  if (check && !guard(driver)) return Status::success();
  accept(driver);
  return Status::success();
}

// the trust radius, then the branch guard (detail/branch_guard.hpp); false: rejected
bool Kernel::guard(double driver) {
  const int nv = static_cast<int>(m_.variables.size());
  // a converged point outside the trust region may be another assembly branch
  const double* x = ws_.values.data();
  const double* predicted = ws_.predicted.data();
  const double* radius = ws_.trust_radius.data();
  bool outside = false;
  for (int v = 0; v < nv; ++v) outside |= std::abs(x[v] - predicted[v]) > radius[v];
  if (outside) {
    for (int v = 0; v < nv && !trust_->rejected; ++v)
      if (std::abs(x[v] - predicted[v]) > radius[v])
        trust_->reject(TrustOutcome::Kind::moved, v, std::abs(x[v] - predicted[v]), radius[v]);
    return false;
  }
  detail::guard_branch(m_, ws_, driver != ws_.prev_driver && !ws_.controls_moved, smallest_step_, *trust_);
  return !trust_->rejected;
}

// an accepted point: the requested outputs, then the history for the next predictor
void Kernel::accept(double driver) {
  const int nv = static_cast<int>(m_.variables.size());
  if (rq_.contacts) {
    // contact quantities need values and first-order rates only (curvature is taken
    // from values of d1 and d2): first-order jets suffice
    for (int v = 0; v < nv; ++v) ws_.vars1[v] = truncate<1>(ws_.vars[v]);
    for (std::size_t si = 0; si < m_.plan.size(); ++si) contact_outputs(static_cast<int>(si));
  }
  ws_.prev2_values.swap(ws_.prev_values);
  ws_.prev_values = ws_.values;
  ws_.prev2_jets.swap(ws_.prev_jets);
  ws_.prev_jets = ws_.vars;
  ws_.prev2_driver = ws_.prev_driver;
  ws_.prev_driver = driver;
  ws_.history = std::min(ws_.history + 1, 2);
  ws_.prev_open = ws_.open;
  ws_.controls_moved = false;
  detail::accept_branch(ws_);
  if (ws_.toggle_margin < ws_.path_margin) {
    ws_.path_margin = ws_.toggle_margin;
    ws_.path_margin_at = driver;
  }
  ++ws_.stats.points;
  // the orders not requested are not returned
  if (rq_.derivative_order < continuation_order)
    for (Jet3& j : ws_.vars)
      for (int k = rq_.derivative_order + 1; k <= continuation_order; ++k) j.c[k] = 0.0;
}

// velocity [per driver] of the material point at drawing position `local` of a body with this pose
V2<double> material_velocity(const detail::Pose<Jet<1>>& pose, const Eigen::Vector2d& local) {
  const auto p = pose.apply(local.x(), local.y());
  return {p.x.c[1], p.y.c[1]};
}

// drawing coordinates of a global point on a body with this pose (inverse at the values)
Eigen::Vector2d to_local(const detail::Pose<Jet<1>>& pose, double gx, double gy) {
  const double c = pose.c.value(), s = pose.s.value();
  const double dx = gx - pose.tx.value(), dy = gy - pose.ty.value();
  return {pose.rx + c * dx + s * dy, pose.ry - s * dx + c * dy};
}

void Kernel::contact_outputs(int step_index) {
  const SolveStep& step = m_.plan[step_index];
  for (int ci : step.connections) {
    const Connection& c = m_.connections[ci];
    if (c.kind != ConnectionKind::contact) continue;
    ContactState& out = ws_.contacts[ci];
    ++ws_.stats.contact_outputs;
    out.open = ws_.open[step_index];
    if (!out.open) out.gap = 0.0;
    using J1 = Jet<1>;
    const J1* vars = ws_.vars1.data();
    // a body's pose serves every contact it carries (every variable is final here)
    const detail::CachedPoses<J1> poses{
        m_, vars, ws_.pivots.data(), ws_.poses1, ws_.point_id, ws_.no_node_solving, &ws_.poses3};
    const auto& pa = poses.get(c.node_a);
    const auto& pb = poses.get(c.node_b);
    // the surfaces at the values: points, tangents d/du and d2/du2 (global) [mm]
    const auto A = surface_point(m_, c.surface_a, pose_values(pa), ws_.values.data(), true, true);
    const auto B = surface_point(m_, c.surface_b, pose_values(pb), ws_.values.data(), true, true);
    auto curvature = [](const detail::SurfacePoint<double>& s) {
      const double q = detail::dot(s.d1, s.d1);
      return detail::cross(s.d1, s.d2) / (q * std::sqrt(q));
    };
    const Surface& sa = c.surface_a;
    const Surface& sb = c.surface_b;
    // unit normal n from a into b, the contact point p and its velocity vc [mm per driver
    // unit]. On a curve or line surface p = X(t) (S(u(t))): vc = the material velocity of
    // X at p + S_u u'. Between two circles p = C_a + |r_a| e, e = d / |d|, d = C_b - C_a:
    // vc = C_a' + |r_a| (d' - e (e . d')) / |d|
    V2<double> n, p, vc;
    auto on_surface = [&](const detail::SurfacePoint<double>& sp, const Surface& s, const detail::Pose<J1>& pose) {
      p = sp.p;
      const V2<double> vm = material_velocity(pose, to_local(pose, p.x, p.y));
      const double du = vars[s.variable].c[1];
      vc = {vm.x + sp.d1.x * du, vm.y + sp.d1.y * du};
    };
    if (sa.kind != SurfaceKind::point) {
      const double len = std::sqrt(detail::dot(A.d1, A.d1));
      n = {A.d1.y / len, -A.d1.x / len};
      on_surface(A, sa, pa);
    } else if (sb.kind != SurfaceKind::point) {
      const double len = std::sqrt(detail::dot(B.d1, B.d1));
      n = {-B.d1.y / len, B.d1.x / len};  // b's outward normal points into a
      on_surface(B, sb, pb);
    } else {
      const V2<double> d{B.p.x - A.p.x, B.p.y - A.p.y};
      const double len = std::sqrt(detail::dot(d, d));
      const V2<double> e{d.x / len, d.y / len};
      const double sign = (sa.offset < 0 || sb.offset < 0) ? (sa.offset < 0 ? -1.0 : 1.0) : 1.0;
      n = {sign * e.x, sign * e.y};
      p = {A.p.x + e.x * std::abs(sa.offset), A.p.y + e.y * std::abs(sa.offset)};
      const V2<double> va_centre = material_velocity(pa, sa.origin), vb_centre = material_velocity(pb, sb.origin);
      const V2<double> dd{vb_centre.x - va_centre.x, vb_centre.y - va_centre.y};
      const double along = detail::dot(e, dd), k = std::abs(sa.offset) / len;
      vc = {va_centre.x + k * (dd.x - e.x * along), va_centre.y + k * (dd.y - e.y * along)};
    }
    out.x = p.x;
    out.y = p.y;
    out.normal_x = n.x;
    out.normal_y = n.y;
    const Eigen::Vector2d la = to_local(pa, out.x, out.y);
    const Eigen::Vector2d lb = to_local(pb, out.x, out.y);
    out.local_a_x = la.x();
    out.local_a_y = la.y();
    out.local_b_x = lb.x();
    out.local_b_y = lb.y();
    out.polar_angle_a = sa.variable >= 0 ? ws_.values[sa.variable] : 0.0;
    out.curvature_a = sa.kind == SurfaceKind::curve ? curvature(A) : sa.kind == SurfaceKind::point ? 1.0 / sa.offset : 0.0;
    out.curvature_b = sb.kind == SurfaceKind::curve ? curvature(B) : sb.kind == SurfaceKind::point ? 1.0 / sb.offset : 0.0;
    // material velocities at the contact point [mm per driver unit]
    const V2<double> va = material_velocity(pa, la);
    const V2<double> vb = material_velocity(pb, lb);
    const V2<double> t{-out.normal_y, out.normal_x};
    double ua = (va.x - vc.x) * t.x + (va.y - vc.y) * t.y;
    double ub = (vb.x - vc.x) * t.x + (vb.y - vc.y) * t.y;
    out.roller_speed = 0.0;
    const bool roller_a = sa.kind == SurfaceKind::point && sa.roller;
    const bool roller_b = sb.kind == SurfaceKind::point && sb.roller;
    if (roller_a || roller_b) {
      // perfect rolling: the roller's surface moves with the other body's surface
      const Surface& sr = roller_a ? sa : sb;
      const int carrier = roller_a ? c.node_a : c.node_b;
      const V2<double> v_other = roller_a ? vb : va;
      const auto& cpose = roller_a ? pa : pb;
      const V2<double> v_centre = material_velocity(cpose, sr.origin);
      const auto centre = cpose.apply(sr.origin.x(), sr.origin.y());
      const double ex = (out.x - centre.x.value()) / sr.offset, ey = (out.y - centre.y.value()) / sr.offset;
      // omega_abs * r * (z x e) = (v_other - v_centre) tangential
      const double omega_abs = ((v_other.x - v_centre.x) * (-ey) + (v_other.y - v_centre.y) * ex) / sr.offset;
      // carrier angular velocity: d(phi)/d(driver)
      double omega_carrier = 0.0;
      const Node& cn = m_.nodes[carrier];
      if (!cn.ground && cn.kind == NodeKind::rotational) omega_carrier = ws_.vars[cn.first_variable].c[1];
      if (!cn.ground && cn.kind == NodeKind::floating) omega_carrier = ws_.vars[cn.first_variable + 2].c[1];
      out.roller_speed = omega_abs - omega_carrier;
      if (roller_a) ua = ub; else ub = ua;
    }
    out.sliding = ua - ub;
    out.entrainment = 0.5 * (ua + ub);
    // pressure angle: the normal against the direction of motion of the follower's trace
    // point - a roller's or pad's centre (the normal passes through it), else the contact
    // point on the follower's surface (Norton, Cam Design and Manufacturing Handbook, ch. 7)
    const bool follower_is_a = step.output_node == c.node_a;
    const int follower = follower_is_a || step.output_node == c.node_b ? step.output_node : c.node_b;
    const Surface& fs = follower == c.node_a ? sa : sb;
    const Node& fn = m_.nodes[follower];
    double trace_x = out.x, trace_y = out.y;
    if (fs.kind == SurfaceKind::point) {
      const auto centre = (follower == c.node_a ? pa : pb).apply(fs.origin.x(), fs.origin.y());
      trace_x = centre.x.value();
      trace_y = centre.y.value();
    }
    V2<double> dir{0, 0};
    if (fn.kind == NodeKind::translational) {
      dir = {fn.direction.x(), fn.direction.y()};
    } else if (fn.kind == NodeKind::rotational) {
      const Eigen::Vector2d o = ws_.pivots[follower];
      dir = {-(trace_y - o.y()), trace_x - o.x()};
    } else {
      // a floating follower has no fixed path: use the trace point's velocity; while the
      // body is at rest the angle is undefined and reported as 0
      const auto& fpose = follower == c.node_a ? pa : pb;
      dir = material_velocity(fpose, to_local(fpose, trace_x, trace_y));
      if (std::hypot(dir.x, dir.y) < 1e-9 * m_.length_scale) dir = {0.0, 0.0};
    }
    const double dn = std::sqrt(dir.x * dir.x + dir.y * dir.y);  // [mm] scale: no overflow
    // atan2 keeps full precision near 0 and 90 deg (acos of a dot product does not)
    const double along = std::abs(dir.x * out.normal_x + dir.y * out.normal_y);
    const double across = std::abs(dir.x * out.normal_y - dir.y * out.normal_x);
    out.pressure_angle = dn > 0 ? atan2_by_atan(across, along) : 0.0;
  }
}

}  // namespace

Workspace::Workspace(const Mechanism& mech) {
  const std::size_t nv = mech.variables.size();
  vars.assign(nv, Jet3(0.0));
  values.assign(nv, 0.0);
  prev_values.assign(nv, 0.0);
  prev2_values.assign(nv, 0.0);
  prev_jets.assign(nv, Jet3(0.0));
  prev2_jets.assign(nv, Jet3(0.0));
  vars1.assign(nv, Jet<1>(0.0));
  vars2.assign(nv, Jet<2>(0.0));
  std::apply([nv](auto&... v) { (v.assign(nv, {}), ...); }, dual_vars);
  contacts.assign(mech.connections.size(), ContactState{});
  open.assign(mech.plan.size(), false);
  prev_open.assign(mech.plan.size(), false);
  residual_buffer.assign(4, 0.0);
  residual_buffer2.assign(4, Jet<2>(0.0));
  residual_buffer3.assign(4, Jet3(0.0));
  for (const auto& step : mech.plan) {
    CAMOPT_ASSERT(step.unknowns.size() <= 16);
    full_blocks.push_back(make_block(mech, step, false));
    tangency_blocks.push_back(make_block(mech, step, true));
  }
  controls_.resize(mech.controls.size());
  for (std::size_t i = 0; i < mech.controls.size(); ++i) controls_[i] = mech.controls[i].default_value;
  pivots.resize(mech.nodes.size());
  poses0.resize(mech.nodes.size());
  poses2.resize(mech.nodes.size());
  poses3.resize(mech.nodes.size());
  poses1.resize(mech.nodes.size());
  no_node_solving.assign(mech.nodes.size(), 0);
  predicted.assign(nv, 0.0);
  predicted_error.assign(nv, 0.0);
  trust_radius.assign(nv, INFINITY);
  for (int s = 0; s < 2 * static_cast<int>(mech.connections.size()); ++s) {
    // surface parameters: a curve's is an angle, a flat face's a length
    const Connection& c = mech.connections[s / 2];
    const Surface& f = s % 2 ? c.surface_b : c.surface_a;
    if (c.kind == ConnectionKind::contact && f.variable >= 0)
      trust_radius[f.variable] =
          f.kind == SurfaceKind::curve ? trust_angle_rad : trust_length_fraction * mech.length_scale;
  }
  variable_scale.assign(nv, 1.0);
  for (std::size_t v = 0; v < nv; ++v)
    if (mech.variables[v].is_angle) variable_scale[v] = 1.0 / mech.length_scale;
  for (int s = 0; s < 2 * static_cast<int>(mech.connections.size()); ++s) {
    const Connection& c = mech.connections[s / 2];
    const Surface& f = s % 2 ? c.surface_b : c.surface_a;
    if (c.kind == ConnectionKind::contact && f.variable >= 0 && f.kind != SurfaceKind::curve)
      variable_scale[f.variable] = 1.0;  // a flat face's parameter is a length
  }
  for (std::size_t v = 0; v < nv; ++v) {
    const int node = mech.variables[v].node;
    if (node < 0) continue;
    const bool known = node == mech.driver_node || mech.nodes[node].control >= 0;
    trust_radius[v] = known                       ? INFINITY
                      : mech.variables[v].is_angle ? trust_angle_rad
                                                   : trust_length_fraction * mech.length_scale;
  }
  set_controls(controls_);
}

namespace {
void drop_block_warm_starts(Workspace& ws) {
  for (auto* blocks : {&ws.full_blocks, &ws.tangency_blocks})
    for (auto& b : *blocks) {
      b.have_inverse = b.jacobian_at_x = false;
      b.contraction = 0.0;
      b.jacobians = 0;
    }
}
}  // namespace

void Workspace::reset() {
  history = 0;
  std::fill(values.begin(), values.end(), 0.0);
  drop_block_warm_starts(*this);
  for (auto& b : full_blocks) b.accepted_sign = 0;
}

void Workspace::set_controls(std::span<const double> values_in, bool keep_warm_start) {
  CAMOPT_ASSERT(values_in.size() == controls_.size());
  std::copy(values_in.begin(), values_in.end(), controls_.begin());
  pivots_stale = true;
  controls_moved = true;
  if (!keep_warm_start) reset();
}

namespace {

// pivots moved by controls (recomputed when the controls change)
void place_pivots(const Mechanism& mech, Workspace& ws) {
  if (ws.pivots_stale) {
    ws.pivots_stale = false;
    for (std::size_t i = 0; i < mech.nodes.size(); ++i) {
      const Node& n = mech.nodes[i];
      ws.pivots[i] = n.pivot;
      if (n.pivot_control >= 0) {
        const double a = n.pivot_gain * ws.controls()[n.pivot_control];
        const Eigen::Vector2d r = n.pivot - n.pivot_about;
        ws.pivots[i] = n.pivot_about + Eigen::Vector2d(std::cos(a) * r.x() - std::sin(a) * r.y(),
                                                       std::sin(a) * r.x() + std::cos(a) * r.y());
      }
    }
  }
}

// one point with the trust check; on rejection the blocks' warm starts (jacobians of the
// rejected point) are dropped, the history of accepted points is kept. smallest: the step
// cannot be halved further (Kernel)
Status attempt(const Mechanism& m, Workspace& ws, double driver, const Request& rq, TrustOutcome& trust,
               bool smallest) {
  place_pivots(m, ws);
  trust = TrustOutcome{};
  Status st = Kernel(m, ws, rq, &trust, smallest).run(driver);
  if (trust.rejected) {
    ++ws.stats.rejected_steps;
    drop_block_warm_starts(ws);
  }
  return st;
}

// a point still rejected at the smallest step: names the variable's connection(s)
Status jump_status(const Mechanism& m, const TrustOutcome& t, double driver, const std::string& step_text) {
  std::string names;
  for (const SolveStep& step : m.plan)
    if (std::find(step.unknowns.begin(), step.unknowns.end(), t.variable) != step.unknowns.end())
      for (int ci : step.connections) names += (names.empty() ? "'" : ", '") + m.connections[ci].name + "'";
  const std::string unit = m.variables[t.variable].is_angle && m.variables[t.variable].node >= 0 ? " rad" : "";
  const std::string name = "'" + m.variables[t.variable].name + "' ";
  std::string what;
  switch (t.kind) {
    case TrustOutcome::Kind::predicted:
      what = name + "is predicted to change by " + fmt(t.distance) + unit + ", beyond the trust radius " +
             fmt(t.radius) + unit;
      break;
    case TrustOutcome::Kind::moved:
      what = name + "moved " + fmt(t.distance) + unit + " from its prediction, beyond the trust radius " +
             fmt(t.radius) + unit;
      break;
    case TrustOutcome::Kind::disagrees:
      what = name + "moved " + fmt(t.distance) + unit + " from its taylor prediction, beyond " +
             fmt(detail::taylor_agreement_factor) + " times the prediction's error estimate (" + fmt(t.radius) +
             unit + ")";
      break;
    case TrustOutcome::Kind::flipped:
      what = "the jacobian's determinant changed sign with the toggle margin at " + fmt(t.radius) +
             ", not near a singular configuration (" + name + "moved " + fmt(t.distance) + unit +
             " from its prediction)";
      break;
  }
  return {StatusCode::no_convergence,
          "connection(s) " + names + " jump: " + what + ", even at a step of " + step_text +
              " (another assembly branch, or the contact leaves the surface)",
          driver_text(m, driver) + ", residual " + fmt(t.distance)};
}

// the whole step was rejected: halved from the last accepted point (at `start`), the
// intermediate points solved with derivatives for the predictor, down to min_step_rad
Status subdivide(const Mechanism& m, Workspace& ws, double target, const Request& rq, const TrustOutcome& first,
                 double start) {
  const Request inner{3, false};
  const double min_step = m.driver_is_angle() ? min_step_rad : min_step_rad * m.length_scale;
  auto step_text = [&](double h) {
    return m.driver_is_angle() ? fmt(std::abs(h) * 180.0 / pi) + " deg" : fmt(std::abs(h)) + " mm";
  };
  if (std::abs(target - start) <= min_step) return jump_status(m, first, target, step_text(target - start));
  double h = 0.5 * (target - start);
  for (;;) {
    const double from = ws.prev_driver;
    const bool last = std::abs(target - from) <= std::abs(h);
    const double at = last ? target : from + h;
    TrustOutcome trust;
    Status st = attempt(m, ws, at, last ? rq : inner, trust, std::abs(at - from) <= min_step);
    if (!st.ok() && !last) {
      // the way to the target is blocked: reported at the target, with where it stopped
      const std::string at_text = driver_text(m, at);
      if (st.where.rfind(at_text, 0) == 0) st.where.replace(0, at_text.size(), driver_text(m, target));
      st.message += " (reached at " + at_text + ", continuing from " + driver_text(m, from) + ")";
    }
    if (!st.ok()) return st;
    if (!trust.rejected) {
      if (last) return st;
      h *= 2.0;
      continue;
    }
    if (std::abs(at - from) <= min_step) return jump_status(m, trust, at, step_text(at - from));
    h = 0.5 * (at - from);
  }
}

// the point at `target` by continuation from the last accepted one (the whole step first:
// the fine-step path is one attempt)
Status step_to(const Mechanism& m, Workspace& ws, double target, const Request& rq) {
  place_pivots(m, ws);
  if (ws.history == 0) return Kernel(m, ws, rq).run(target);
  const double start = ws.prev_driver;
  const double min_step = m.driver_is_angle() ? min_step_rad : min_step_rad * m.length_scale;
  TrustOutcome first;
  Status st = attempt(m, ws, target, rq, first, std::abs(target - start) <= min_step);
  if (st.ok() && first.rejected) st = subdivide(m, ws, target, rq, first, start);
  return st;
}

// from the solved drawing (driver 0, default controls, where every node is at its drawing
// position): the controls moved to `target` in steps, then the driver continued to
// `driver`, all under the trust check, so the first point is on the drawing's assembly
// branch rather than wherever Newton from the drawing lands
Status continue_from_drawing(const Mechanism& m, Workspace& ws, const std::vector<double>& target, double driver,
                             const Request& rq) {
  const std::vector<double> defaults = m.default_controls();
  std::vector<double> controls = defaults;
  const Request inner{3, false};
  double done = 0.0, step = 1.0;  // fraction of the control move
  while (done < 1.0) {
    const double next = std::min(1.0, done + step);
    for (std::size_t i = 0; i < target.size(); ++i)
      controls[i] = next == 1.0 ? target[i] : defaults[i] + next * (target[i] - defaults[i]);
    ws.set_controls(controls, true);
    TrustOutcome trust;
    Status st = attempt(m, ws, 0.0, inner, trust, next - done <= min_control_fraction);
    if (!st.ok()) return st;
    if (!trust.rejected) {
      done = next;
      step *= 2.0;
      continue;
    }
    if (next - done <= min_control_fraction)
      return jump_status(m, trust, 0.0, "1e-6 of the control move");
    step *= 0.5;
  }
  ws.path_margin = INFINITY;  // the path at the target controls starts here
  return step_to(m, ws, driver, rq);
}

// a fresh workspace away from the drawing: assembled by continuation from the drawing
// (solved here, or copied from `drawing`), else directly
Status solve_fresh(const Mechanism& mech, Workspace& ws, double driver, const Request& request,
                   const Workspace* drawing) {
  const std::vector<double> target = ws.controls();
  Status st = Status::success();
  if (drawing != nullptr)
    ws = *drawing;
  else
    st = solve_drawing(mech, ws);
  CamProfile::clear_thread_memo();  // the continuation does not depend on the thread's past
  if (st.ok()) st = continue_from_drawing(mech, ws, target, driver, request);
  if (st.ok()) return st;
  // the drawing does not assemble or continue: assemble at the point directly
  ws.set_controls(target);
  ws.path_margin = INFINITY;
  st = step_to(mech, ws, driver, request);
  if (!st.ok()) ws.reset();
  return st;
}
}  // namespace

namespace {
// the plan step that solves `node`, if it solves nothing else but contact parameters (else -1)
int prescribable_step(const Mechanism& mech, int node) {
  const Node& n = mech.nodes[static_cast<std::size_t>(node)];
  if (n.first_variable < 0 || n.control >= 0 || node == mech.driver_node) return -1;
  for (std::size_t si = 0; si < mech.plan.size(); ++si) {
    const auto& unknowns = mech.plan[si].unknowns;
    if (std::find(unknowns.begin(), unknowns.end(), n.first_variable) == unknowns.end()) continue;
    for (int v : unknowns)
      if (mech.variables[static_cast<std::size_t>(v)].node >= 0 && mech.variables[static_cast<std::size_t>(v)].node != node)
        return -1;
    return mech.plan[si].one_sided ? -1 : static_cast<int>(si);
  }
  return -1;
}
}  // namespace

bool can_prescribe(const Mechanism& mech, int node) { return prescribable_step(mech, node) >= 0; }

Status solve_prescribed(const Mechanism& mech, Workspace& ws, double driver, const Request& request, int node,
                        std::span<const Jet3> node_vars) {
  const int step = prescribable_step(mech, node);
  CAMOPT_ASSERT(step >= 0 && static_cast<int>(node_vars.size()) == mech.nodes[static_cast<std::size_t>(node)].dof);
  CAMOPT_ASSERT(ws.history >= 1 && !request.contacts);
  place_pivots(mech, ws);
  ws.path_margin = INFINITY;
  TrustOutcome trust;
  Kernel kernel(mech, ws, request, &trust);
  kernel.prescribe(step, node, node_vars.data());
  const Status st = kernel.run(driver);
  if (!st.ok() || !trust.rejected) return st;
  ++ws.stats.rejected_steps;
  drop_block_warm_starts(ws);
  return jump_status(mech, trust, driver, "one step");
}

bool at_drawing(const Mechanism& mech, const std::vector<double>& controls, double driver) {
  return driver == 0.0 && controls == mech.default_controls();
}

Status solve_drawing(const Mechanism& mech, Workspace& ws) {
  CamProfile::clear_thread_memo();  // the drawing does not depend on the thread's past
  ws.set_controls(mech.default_controls());
  place_pivots(mech, ws);
  ws.path_margin = INFINITY;
  Status st = Kernel(mech, ws, Request{3, false}).run(0.0);
  if (!st.ok()) ws.reset();
  return st;
}

Status solve(const Mechanism& mech, Workspace& ws, double driver, const Request& request, const Workspace* drawing) {
  CAMOPT_ASSERT(request.derivative_order >= 0 && request.derivative_order <= 3);
  CAMOPT_ASSERT(!request.contacts || request.derivative_order >= 1);
  ws.path_margin = INFINITY;
  if (ws.history == 0 && !at_drawing(mech, ws.controls(), driver))
    return solve_fresh(mech, ws, driver, request, drawing);
  if (ws.history == 0) CamProfile::clear_thread_memo();  // the drawing does not depend on the thread's past
  Status st = step_to(mech, ws, driver, request);
  if (!st.ok()) ws.reset();
  return st;
}

}  // namespace camopt::kin
