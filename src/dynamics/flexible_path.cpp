// the flexible model's kinematic path: tabulated in smooth pieces between lash kinks
// (flexible_system.hpp)
#include <algorithm>
#include <numbers>

#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// a piece is tabulated from kKinkOffset past one kink to kKinkOffset before the next: at the
// kink itself the contact's open flag is decided by a gap at the solver's round-off
constexpr double kKinkOffset = 1e-8;  // [rad]
constexpr double kPieceSlack = 1e-7;  // [rad] an angle this close to a piece belongs to it
}  // namespace

Layout::Layout(int r, int c, int s, int v, int p) : R(r), C(c), S(s), V(v), P(p) {
  gas = inertia + R;        // R: gas load on the row [N or N mm]
  other = gas + R;          // R: remaining springs (torsion, ...)
  spring_k = other + R;     // R x R (column-major): their stiffness d(load)/dq
  vel = spring_k + R * R;   // R: dq/dtheta
  gn = vel + R;             // R x C (column-major): gap gradient (links: length)
  gt = gn + R * C;          // R x C: tangent gradient (friction)
  gap = gt + R * C;         // C: kinematic gap (lash)
  curv = gap + C;           // C: curvature sum 1/R* [1/mm]
  curv2 = curv + C;         // C: 1 / (R_a + R_b) [1/mm]: the gap's growth s^2 / (2 (R_a + R_b)) with sliding s
  slide = curv2 + C;        // C: sliding of a over b per rad [mm/rad]
  gn_drv = slide + C;       // C: d gap / d driver
  gt_drv = gn_drv + C;      // C: tangent gradient on the driver
  load_drv = gt_drv + C;    // 1: driver load (inertia per omega^2 excluded: constant speed)
  mass = load_drv + 1;      // R x R
  xs = mass + R * R;        // S: chain node displacement [mm]
  xs1 = xs + S;             // S: its d/dtheta [mm/rad]
  seat = xs1 + S;           // V: seat node displacement from rest [mm]
  out = seat + V;           // 1: output node displacement from rest
  out1 = out + 1;           // 1: its d/dtheta
  out2 = out1 + 1;          // 1: its d2/dtheta2
  pz_gn = out2 + 1;         // P x C: gap gradient on each plunger coordinate
  pz_gt = pz_gn + P * C;    // P x C: tangent gradient on it
  pz_inertia = pz_gt + P * C;  // P: inertia of the node's kinematic motion along the axis (per omega^2)
  pz_mass = pz_inertia + P;    // P: mass coupling of the plunger coordinate with the node's row
  size = pz_mass + P;
}

namespace {

// the open flags of the lash contacts after a solve
std::vector<char> lash_flags(const System& s, const RigidWorkspace& ws) {
  std::vector<char> f;
  for (int c : s.lash) f.push_back(ws.kin.contacts[c].open ? 1 : 0);
  return f;
}

// a plunger's columns: moving the pivot by z along the axis moves the whole node (in series:
// the node's contact side), so a contact's gap changes by +-n.axis z (b side +, a side -, as
// the gradients of rigid.cpp), its tangent coordinate by +-t.axis z; the moved mass couples z
// with the node's row (under a pivot m (k x r_cg) . axis, in series m_b direction . axis) and
// its kinematic acceleration loads z (m a_cg . axis)
void fill_plunger(const System& s, const RigidWorkspace& ws, const Plunger& p, double* row) {
  constexpr double kMilli = 1e-3;  // kg mm/s^2 -> N
  const kin::Mechanism& mech = s.mech;
  for (int c = 0; c < s.C; ++c) {
    if (!p.touches[c]) continue;
    const kin::ContactState& cs = ws.kin.contacts[c];
    const Eigen::Vector2d n(cs.normal_x, cs.normal_y), t(-cs.normal_y, cs.normal_x);
    const double side = mech.connections[c].node_b == p.node ? 1.0 : -1.0;
    row[s.L.pz_gn + p.table_index * s.C + c] = side * n.dot(p.axis);
    row[s.L.pz_gt + p.table_index * s.C + c] = side * t.dot(p.axis);
  }
  const double m = p.series ? p.mass : kMilli * s.flex.bodies[p.node].mass;
  const Eigen::Vector2d arm = ws.cg_pos[p.node] - p.pivot;
  row[s.L.pz_inertia + p.table_index] = m * ws.cg_acc[p.node].dot(p.axis);
  row[s.L.pz_mass + p.table_index] = p.series ? m * p.along : m * Eigen::Vector2d(-arm.y(), arm.x()).dot(p.axis);
}

// one table row: what the model needs of the kinematic path at the workspace's angle
void fill_row(const System& s, const RigidWorkspace& ws, double* row) {
  const kin::Mechanism& mech = s.mech;
  const Layout& L = s.L;
  const int dv = mech.driver_variable();
  std::fill(row, row + L.size, 0.0);
  for (int r = 0; r < s.R; ++r) {
    const int v = s.flex.free_variables[r];
    row[L.inertia + r] = ws.loads(v, 0);
    row[L.gas + r] = ws.loads(v, 1);
    // the springs left in the path (their dampers, per rad/s, are the chains' in this model)
    for (int j = 2; j < ws.damping_case(); ++j) row[L.other + r] += ws.loads(v, j);
    row[L.vel + r] = ws.kin.vars[v].c[1];
    for (int c = 0; c < s.C; ++c) {
      const bool contact = s.flex.contacts[c].is_contact;
      row[L.gn + r + s.R * c] = contact ? ws.g_normal(v, c) : ws.g(v, c);
      row[L.gt + r + s.R * c] = contact ? ws.g_tangent(v, c) : 0.0;
    }
    for (int j = 0; j < s.R; ++j) row[L.mass + r + s.R * j] = ws.mass(r, j);
  }
  for (int r = 0; r < s.R; ++r)
    for (int j = 0; j < s.R; ++j) row[L.spring_k + r + s.R * j] = ws.spring_stiffness(r, j);
  for (int c = 0; c < s.C; ++c) {
    const bool contact = s.flex.contacts[c].is_contact;
    row[L.gn_drv + c] = contact ? ws.g_normal(dv, c) : ws.g(dv, c);
    row[L.gt_drv + c] = contact ? ws.g_tangent(dv, c) : 0.0;
    if (!contact) continue;
    const kin::ContactState& cs = ws.kin.contacts[c];
    row[L.gap + c] = cs.gap;
    row[L.curv + c] = cs.curvature_a + cs.curvature_b;
    if (cs.curvature_a != 0.0 && cs.curvature_b != 0.0)
      row[L.curv2 + c] = 1.0 / (1.0 / cs.curvature_a + 1.0 / cs.curvature_b);
    row[L.slide + c] = cs.sliding;
  }
  for (int j = 1; j < ws.damping_case(); ++j) row[L.load_drv] += ws.loads(dv, j);
  for (const Chain& ch : s.chains) {
    const auto& var = ws.kin.vars[mech.nodes[ch.node].first_variable];
    row[L.xs + ch.table_index] = var.value();
    row[L.xs1 + ch.table_index] = var.c[1];
  }
  for (const Seat& st : s.seats) {
    const kin::Node& n = mech.nodes[st.node];
    row[L.seat + st.table_index] = ws.kin.vars[n.first_variable].value() - n.rest;
  }
  for (const Plunger& p : s.plungers) fill_plunger(s, ws, p, row);
  const kin::Node& on = mech.nodes[mech.output_node];
  const auto& ov = ws.kin.vars[on.first_variable];
  row[L.out] = ov.value() - on.rest;
  row[L.out1] = ov.c[1];
  row[L.out2] = 2.0 * ov.c[2];  // taylor coefficient -> second derivative
}

struct Kink {
  double lo = 0.0, hi = 0.0;  // [rad] the flags of the left side at lo, of the right side at hi
  RigidWorkspace before;      // a workspace solved just before lo (to restart a sweep)
};

// bisect (lo, hi) for the first angle where the lash flags leave `left`
Status bisect_kink(const System& s, const RigidWorkspace& at_lo, double lo, double hi, const std::vector<char>& left,
                   Kink& out) {
  RigidWorkspace w = at_lo;
  for (int it = 0; it < 80 && hi - lo > 4e-15 * std::max(1.0, std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    w = at_lo;
    const Status st = solve_rigid(s.mech, s.flex, w, mid);
    if (!st.ok()) return st;
    if (lash_flags(s, w) == left) lo = mid;
    else hi = mid;
  }
  out.lo = lo;
  out.hi = hi;
  out.before = at_lo;
  return Status::success();
}

// the kinks of one revolution from theta_first: a uniform sweep, bisection where the flags change
Status find_kinks(System& s, const std::vector<double>& controls, double theta_first, double h, int grid,
                  std::vector<Kink>& kinks) {
  RigidWorkspace ws(s.mech, s.flex);
  ws.kin.set_controls(controls);
  Status st = solve_rigid(s.mech, s.flex, ws, theta_first);
  if (!st.ok()) return st;
  std::vector<char> flags = lash_flags(s, ws);
  for (int i = 1; i <= grid; ++i) {
    RigidWorkspace prev = ws;
    const double lo = theta_first + (i - 1) * h, hi = theta_first + i * h;
    st = solve_rigid(s.mech, s.flex, ws, hi);
    if (!st.ok()) return st;
    const std::vector<char> now = lash_flags(s, ws);
    double from = lo;
    while (flags != now) {  // several contacts may change within one interval
      Kink k{0.0, 0.0, prev};
      st = bisect_kink(s, prev, from, hi, flags, k);
      if (!st.ok()) return st;
      RigidWorkspace at = prev;
      st = solve_rigid(s.mech, s.flex, at, k.hi);
      if (!st.ok()) return st;
      flags = lash_flags(s, at);
      prev = at;
      from = k.hi;
      kinks.push_back(std::move(k));
    }
  }
  return Status::success();
}

}  // namespace

Status tabulate_path(System& s, const std::vector<double>& controls, double theta_first) {
  const FlexibleOptions& opt = s.opt;
  const int grid = static_cast<int>(std::ceil(360.0 / opt.table_step_deg - 1e-9));
  const double h = kTwoPi / grid;
  std::vector<Kink> kinks;
  if (!s.lash.empty()) {
    const Status st = find_kinks(s, controls, theta_first, h, grid, kinks);
    if (!st.ok()) return st;
  }
  s.pieces.clear();
  s.kinks.clear();
  s.table.clear();
  s.row_angle.clear();
  s.path.assign(s.L.size, 0.0);
  s.gap_slope.assign(s.C, 0.0);
  if (kinks.empty()) {
    // one periodic piece on the uniform grid
    RigidWorkspace ws(s.mech, s.flex);
    ws.kin.set_controls(controls);
    s.table.resize(static_cast<std::size_t>(grid) * s.L.size);
    for (int i = 0; i < grid; ++i) {
      const double th = theta_first + i * h;
      const Status st = solve_rigid(s.mech, s.flex, ws, th);
      if (!st.ok()) return st;
      fill_row(s, ws, &s.table[static_cast<std::size_t>(i) * s.L.size]);
      s.row_angle.push_back(th);
    }
    s.pieces.push_back({theta_first, theta_first + kTwoPi, 0, grid, true});
    s.active_piece = 0;
    return Status::success();
  }
  // pieces [hi_k, lo_k+1], the last one to lo_1 + 2 pi; one monotone sweep through them
  const std::size_t n = kinks.size();
  RigidWorkspace ws = kinks[0].before;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = kinks[k].hi + kKinkOffset, b = (k + 1 < n ? kinks[k + 1].lo : kinks[0].lo + kTwoPi) - kKinkOffset;
    const int count = std::max(2, static_cast<int>(std::ceil((b - a) / h - 1e-9)) + 1);
    PathPiece p{a, b, static_cast<int>(s.row_angle.size()), count, false};
    std::vector<char> flags;
    for (int j = 0; j < count; ++j) {
      const double th = j + 1 == count ? b : a + j * (b - a) / (count - 1);
      const Status st = solve_rigid(s.mech, s.flex, ws, th);
      if (!st.ok()) return st;
      const std::vector<char> f = lash_flags(s, ws);
      if (j == 0) flags = f;
      if (f != flags)
        return {StatusCode::no_convergence,
                "a lash contact opens or closes twice within one table step of the flexible model's path",
                "cam " + format_number(th * 180.0 / std::numbers::pi) + " deg: lower table_step_deg"};
      s.table.resize(s.table.size() + s.L.size);
      fill_row(s, ws, &s.table[s.table.size() - s.L.size]);
      s.row_angle.push_back(th);
    }
    s.pieces.push_back(p);
    s.kinks.push_back(a);
  }
  s.active_piece = 0;
  return Status::success();
}

int System::piece_of(double theta) const {
  auto inside = [&](int k) {
    const PathPiece& p = pieces[k];
    const double mid = 0.5 * (p.a + p.b);
    const double th = theta - kTwoPi * std::round((theta - mid) / kTwoPi);
    return th >= p.a - kPieceSlack && th <= p.b + kPieceSlack;
  };
  if (pieces.size() == 1 || inside(active_piece)) return active_piece;
  for (int k = 0; k < static_cast<int>(pieces.size()); ++k)
    if (inside(k)) return k;
  return active_piece;
}

void System::evaluate_angle(double theta) {
  if (theta == evaluated_theta) return;
  evaluated_theta = theta;
  const int k = piece_of(theta);
  const PathPiece& p = pieces[k];
  const double h = p.step();
  const double mid = p.periodic ? p.a : 0.5 * (p.a + p.b);
  const double th = p.periodic ? theta : theta - kTwoPi * std::round((theta - mid) / kTwoPi);
  const double xg = (th - p.a) / h;
  double fl = std::floor(xg);
  if (!p.periodic) fl = std::clamp(fl, 0.0, static_cast<double>(p.count - 2));
  const double u = xg - fl;
  double w[4], dw[4];
  catmull_rom_weights(u, w);
  catmull_rom_slopes(u, dw);
  const std::size_t size = L.size;
  auto row = [&](int j) { return &table[static_cast<std::size_t>(p.first + j) * size]; };
  if (p.periodic) {
    int i = static_cast<int>(std::fmod(fl, p.count));
    if (i < 0) i += p.count;
    const double* r[4];
    for (int q = 0; q < 4; ++q) r[q] = row(((i + q - 1) % p.count + p.count) % p.count);
    for (std::size_t j = 0; j < size; ++j) path[j] = w[0] * r[0][j] + w[1] * r[1][j] + w[2] * r[2][j] + w[3] * r[3][j];
    for (int c = 0; c < C; ++c) {
      const int j = L.gap + c;
      gap_slope[c] = (dw[0] * r[0][j] + dw[1] * r[1][j] + dw[2] * r[2][j] + dw[3] * r[3][j]) / h;
    }
    return;
  }
  // a piece with ends: the points outside it are extrapolated (quadratic, or linear for 2 points)
  const int i = static_cast<int>(fl);
  auto value = [&](int j, std::size_t col) -> double {
    if (j >= 0 && j < p.count) return row(j)[col];
    const int e = j < 0 ? 0 : p.count - 1, dir = j < 0 ? 1 : -1;
    if (p.count >= 3) return 3.0 * row(e)[col] - 3.0 * row(e + dir)[col] + row(e + 2 * dir)[col];
    return 2.0 * row(e)[col] - row(e + dir)[col];
  };
  const bool inner = i >= 1 && i + 2 < p.count;
  if (inner) {
    const double* r[4] = {row(i - 1), row(i), row(i + 1), row(i + 2)};
    for (std::size_t j = 0; j < size; ++j) path[j] = w[0] * r[0][j] + w[1] * r[1][j] + w[2] * r[2][j] + w[3] * r[3][j];
  } else {
    for (std::size_t j = 0; j < size; ++j)
      path[j] = w[0] * value(i - 1, j) + w[1] * value(i, j) + w[2] * value(i + 1, j) + w[3] * value(i + 2, j);
  }
  for (int c = 0; c < C; ++c) {
    const std::size_t j = L.gap + c;
    gap_slope[c] =
        (dw[0] * value(i - 1, j) + dw[1] * value(i, j) + dw[2] * value(i + 1, j) + dw[3] * value(i + 2, j)) / h;
  }
}

double System::piece_end_rate(int piece, int side, int e) const {
  if (e >= core()) return 0.0;
  const PathPiece& p = pieces[piece];
  if (e >= R + E) return 0.0;  // a plunger: at rest on the path
  const int r = e < R ? e : elements[e - R].near;
  const double* row = &table[static_cast<std::size_t>(p.first + (side ? p.count - 1 : 0)) * L.size];
  return row[L.vel + r] * omega;
}

}  // namespace camopt::dynamics::detail
