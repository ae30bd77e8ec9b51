#include "camopt/synthesis/floating_inversion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "camopt/kinematics/detail/geometry.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/detail/hermite.hpp"
#include "camopt/synthesis/detail/radial_probe.hpp"

namespace camopt::synthesis {

namespace {

constexpr double pi = std::numbers::pi;
using Jet3 = Jet<3>;

std::string fmt(double v) { return format_value(v, 6); }
std::string deg_of(double rad) { return fmt(rad * 180 / pi); }

// probe travel per scan step [mm] and the slope, relative to the mean slope of the lift
// over the scan, below which L(q) counts as flat (idle travel): at a quadratic ramp foot
// the lift there is ~ 1e-8 of the full lift. 0.04 mm: the bundled Valvetronic input cam
// is within 1.4e-7 mm of the 0.01 mm scan's, its round trip 3.15e-8 mm against 3.13e-8 mm
// (the round trip holds up to 0.07 mm; at 0.08 mm it stops at the cam's rest junction)
constexpr double kScanStep = 0.04;
constexpr double kFlatSlope = 1e-5;
// [mm] probe travel between solves of the whole mechanism where the scan takes the lever's
// pose from them (septic hermite in q)
constexpr double kLeverStep = 0.5;
constexpr double kMaxTravel = 100.0;  // [mm] the scan gives up beyond this probe travel
// [mm per mm of peak lift] how close the target's turning lift must come to the lever's
// (the target is sampled: its extreme sample misses the true turn by ~ L'' h^2 / 8)
constexpr double kTurnTolerance = 1e-4;
// [relative to the mean slope] dL/dq at the last sample inverted before the base circle
// below which the lift does not fix the lever's travel there: the walk's end is then a
// designed landing (landing_samples). The bundled Valvetronic at 0 deg of control ends at
// 7.5e-5 (the lever's lift has a 2.2e-8 mm hump within 1.6e-3 mm of its rest); from 5 deg
// on its lift rises from the rest at 2.6e-2 .. 0.83 and the target fixes the travel
// down to the rest
constexpr double kLandingSlope = 1e-3;
constexpr int kMaxLandingSamples = 64;
// [mm per mm of peak lift] a monotone piece of L(q) over which the lift moves by less is
// not told apart from its neighbours (its turns are dropped)
constexpr double kTinyPiece = 1e-8;

// the landing of the lever's travel on the base circle from the jets q(tau) of the last
// inverted sample, tau the distance walked towards the rest [rad]: the septic hermite from
// them to rest (q and three derivatives 0) over m samples of h, for the smallest m whose
// acceleration q'' runs most evenly to 0 (total variation within 1 % of the least over
// m <= max_m, q falling monotonically to 0, as a ramp designer's constant-deceleration
// landing would). 0 when no such landing exists
int landing_samples(const Jet3& q_tau, double h, int max_m) {
  constexpr int kChecks = 64;  // points along the landing where q'' and the monotony are checked
  std::array<double, kChecks + 1> q2;
  double least = 1e300;
  int least_m = 0;
  for (int m = 2; m <= max_m; ++m) {
    const double span = m * h;
    const double start[4] = {q_tau.derivative(0), q_tau.derivative(1) * span,
                             q_tau.derivative(2) * span * span, q_tau.derivative(3) * span * span * span};
    const double rest[4] = {0.0, 0.0, 0.0, 0.0};
    const detail::Septic piece(start, rest);
    bool monotone = true;
    for (int t = 0; t <= kChecks && monotone; ++t) {
      double d[4];
      piece.eval(static_cast<double>(t) / kChecks, d);
      monotone = d[0] >= -1e-9 * start[0] && d[1] <= 1e-9 * std::abs(start[1]);
      q2[static_cast<std::size_t>(t)] = d[2];
    }
    if (!monotone) {
      if (least_m > 0) break;  // past the monotone landings
      continue;
    }
    double variation = 0.0;
    for (int t = 1; t <= kChecks; ++t) variation += std::abs(q2[static_cast<std::size_t>(t)] - q2[static_cast<std::size_t>(t - 1)]);
    variation /= span * span;
    if (variation < least) least = variation, least_m = m;
    // q'' runs from its start to 0: no landing varies less than that
    if (variation <= 1.01 * std::abs(q_tau.derivative(2))) return m;
  }
  return least_m;
}

// q(theta) from L(q0 + d) = L0 + a1 d + a2 d^2 + a3 d^3 and the target's taylor
// coefficients b in theta (b0 = L0): series reversion to third order
Jet3 revert(const Jet3& lift_of_q, double q0, const Jet3& target) {
  const double a1 = lift_of_q.c[1], a2 = lift_of_q.c[2], a3 = lift_of_q.c[3];
  Jet3 q(q0);
  q.c[1] = target.c[1] / a1;
  q.c[2] = (target.c[2] - a2 * q.c[1] * q.c[1]) / a1;
  q.c[3] = (target.c[3] - 2 * a2 * q.c[1] * q.c[2] - a3 * q.c[1] * q.c[1] * q.c[1]) / a1;
  return q;
}

// f(q(theta)) from the jet of f in q (taylor coefficients at q(theta).value())
Jet3 compose_in(const Jet3& f_of_q, const Jet3& q) {
  double d[4];
  for (int k = 0; k < 4; ++k) d[k] = f_of_q.derivative(k);
  return compose(d, q);
}

}  // namespace

Status invert_floating_follower(const DesignSpec& spec, const MechanismCut& cut, const std::string& target_node,
                                const std::vector<double>& controls, const std::vector<double>& theta,
                                const std::vector<Jet3>& motion, FloatingInversion& out) {
  const auto& conn = spec.connections[static_cast<std::size_t>(cut.connection)];
  const SurfaceSpec& follower_surface = cut.profile_on_a ? conn.surface_b : conn.surface_a;
  if (follower_surface.shape != SurfaceShape::circle)
    throw InputError(conn.where, "synthesize: the follower '" + cut.follower_node + "' of contact '" + conn.name +
                                     "' is a floating lever; through a floating lever the follower must be a roller "
                                     "or pad (circle), not a " + to_string(follower_surface.shape));
  const NodeSpec* cam_node = nullptr;
  for (const auto& n : spec.nodes)
    if (n.name == cut.cam_node) cam_node = &n;
  CAMOPT_ASSERT(cam_node);
  if (cam_node->kind != NodeKind::rotational)
    throw InputError(conn.where, "synthesize: a floating follower '" + cut.follower_node +
                                     "' needs a rotational cam, not the " + to_string(cam_node->kind) + " '" +
                                     cut.cam_node + "'");
  // the probe (detail/radial_probe.hpp) pushes the roller along the cam's radial direction
  const double c0x = follower_surface.origin_mm[0], c0y = follower_surface.origin_mm[1];
  const double px = cam_node->pivot_mm[0], py = cam_node->pivot_mm[1];
  const double base = std::hypot(c0x - px, c0y - py);  // [mm] roller centre from the cam pivot on the base circle
  if (!(base > 1e-9))
    throw InputError(conn.where, "synthesize: the roller of '" + cut.follower_node + "' is centred on the cam pivot");
  auto probe_parts = [&](double cx, double cy) { return detail::radial_probe(follower_surface, px, py, cx, cy); };
  auto make_probe = [&](double cx, double cy) {
    DesignSpec probe_spec = cut.downstream;
    auto [probe, face] = probe_parts(cx, cy);
    probe_spec.nodes.push_back(probe);
    probe_spec.connections.push_back(face);
    probe_spec.driver.node = probe.name;
    probe_spec.output_node = target_node;
    return kin::compile(probe_spec);
  };
  // the compiled probe mechanism moved to push through (cx, cy): compile takes nothing else
  // from the probe than its node's line and its face (and their distances from the origin
  // for the length scale), so moving those gives what a fresh compile would, without
  // building the lever's profiles again. false (m untouched) when the length scale would
  // change: compile afresh then.
  auto move_probe = [&](kin::Mechanism& mech, double cx, double cy) {
    const auto [probe, face] = probe_parts(cx, cy);
    kin::Node& node = mech.nodes[static_cast<std::size_t>(mech.node_index(probe.name))];
    kin::Connection& contact = mech.connections.back();
    CAMOPT_ASSERT(contact.name == face.name && mech.spec.connections.back().name == face.name &&
                  mech.spec.nodes.back().name == probe.name);
    const Eigen::Vector2d origin(probe.origin_mm[0], probe.origin_mm[1]);
    const Eigen::Vector2d face_origin(face.surface_a.origin_mm[0], face.surface_a.origin_mm[1]);
    const double scale = mech.length_scale;
    if (!(std::max({node.pivot.norm(), contact.surface_a.origin.norm(), origin.norm(), face_origin.norm()}) < scale))
      return false;
    node.pivot = origin;
    node.direction = Eigen::Vector2d(probe.direction[0], probe.direction[1]).normalized();  // as compile does
    contact.surface_a.origin = face_origin;
    contact.surface_a.normal = Eigen::Vector2d(face.surface_a.normal[0], face.surface_a.normal[1]).normalized();
    mech.spec.nodes.back() = probe;
    mech.spec.connections.back() = face;
    return true;
  };
  // the lever at rest: its cam roller on the base circle (as far from the cam pivot as in
  // the drawing). Away from the drawing's control position the other contacts move the
  // rest pose (a Valvetronic eccentric turns the lever about the camshaft), so it is found
  // by newton on |c(q) - pivot| = base with a probe along the drawing's radial direction
  double rest_x = c0x, rest_y = c0y;
  kin::Mechanism m0 = make_probe(c0x, c0y);
  {
    kin::Workspace ws0(m0);
    ws0.set_controls(controls);
    const int f0 = m0.node_index(cut.follower_node);
    double q = 0.0;
    for (int it = 0;; ++it) {
      const Status st = kin::solve(m0, ws0, q, {1, false});
      if (!st.ok()) return {st.code, "placing the lever '" + cut.follower_node + "' at rest: " + st.message, "cam base circle"};
      const auto c = kin::detail::node_pose(m0, f0, ws0.vars.data(), ws0.pivots.data()).apply(c0x, c0y);
      const Jet3 rho = sqrt((c.x - px) * (c.x - px) + (c.y - py) * (c.y - py));
      rest_x = c.x.value(), rest_y = c.y.value();
      const double miss = rho.value() - base;
      if (std::abs(miss) < 1e-12 * base) break;
      if (it == 50 || !(std::abs(rho.c[1]) > 1e-9))
        return {StatusCode::no_convergence,
                "placing the lever '" + cut.follower_node + "' at rest with its roller on the base circle (" +
                    fmt(base) + " mm from the cam pivot): " + fmt(miss) + " mm off",
                "cam base circle"};
      q -= miss / rho.c[1];
    }
  }
  // the probe through the rest pose (the drawing's own when the lever rests as drawn, to
  // the rest newton's tolerance)
  const bool rests_as_drawn = std::hypot(rest_x - c0x, rest_y - c0y) < 1e-12 * base;
  if (!rests_as_drawn && !move_probe(m0, rest_x, rest_y)) m0 = make_probe(rest_x, rest_y);
  const kin::Mechanism m = std::move(m0);
  kin::Workspace ws(m);
  ws.set_controls(controls);
  const int lift_var = m.nodes[static_cast<std::size_t>(m.node_index(target_node))].first_variable;
  const int follower = m.node_index(cut.follower_node);
  auto centre_in = [&](const kin::Workspace& w) {
    return kin::detail::node_pose(m, follower, w.vars.data(), w.pivots.data()).apply(c0x, c0y);
  };

  const int n = static_cast<int>(theta.size());
  double motion_hi = -1e300;
  for (const auto& L : motion) motion_hi = std::max(motion_hi, L.value());

  // 1. scan L(q) from the rest up past the largest target lift, keeping the lift and the
  // roller centre with three derivatives in q at every scan point: between them they are
  // septic hermite pieces in q (kScanStep apart), so the inversion below needs no solves
  //
  // The lever itself is smooth in q where its other contacts are analytic (the bundled
  // Valvetronic's rollers on a disc and a circle), the lift is not (the working curve is a
  // table): there, and where the kernel can take the lever as given (kin::solve_prescribed),
  // the whole mechanism is solved only every kLeverStep, and at the
  // scan points between them the lever's pose is septic hermite in q from those solves and
  // only the contacts after it are solved
  std::vector<double> grid_lift;
  std::vector<std::array<double, 12>> grid_jets;  // [L, centre x, centre y][derivative 0..3]
  const bool lever_given = kin::can_prescribe(m, follower) && detail::held_analytically(m, follower);
  const kin::Node& lever = m.nodes[static_cast<std::size_t>(follower)];
  std::vector<std::array<double, 12>> lever_grid;  // [x, y, phi][derivative 0..3] every kLeverStep
  detail::SepticPieces lever_pieces(3);             // between them
  std::optional<kin::Workspace> scan_ws;  // the scan between the lever's solves
  auto solve_whole = [&](double q) -> Status {
    const Status st = kin::solve(m, ws, q, {3, false});
    if (!st.ok())
      return {st.code,
              "the lever '" + cut.follower_node + "' pushed " + fmt(q) + " mm along its cam roller's radial path "
              "cannot be solved with its other contacts (" + st.message + ") before the valve reaches the target's " +
                  fmt(motion_hi) + " mm",
              "probe travel " + fmt(q) + " mm"};
    return Status::success();
  };
  // the lever's pose as just solved in ws, a point of lever_grid
  auto record_lever = [&] {
    std::array<double, 12>& g = lever_grid.emplace_back();
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 4; ++d) g[4 * k + d] = ws.vars[static_cast<std::size_t>(lever.first_variable + k)].derivative(d);
    if (lever_grid.size() >= 2)
      lever_pieces.add_interval(lever_grid[lever_grid.size() - 2].data(), lever_grid.back().data(), kLeverStep);
  };
  // the scan point at q: solved in ws, or with the lever given in scan_ws (`at`: which)
  const kin::Workspace* at = &ws;
  auto scan_at = [&](double q) -> Status {
    if (!lever_given) return solve_whole(q);
    if (q == 0.0) {
      if (const Status st = solve_whole(q); !st.ok()) return st;
      record_lever();
      scan_ws = ws;
      at = &*scan_ws;
      return Status::success();
    }
    while (static_cast<double>(lever_grid.size() - 1) * kLeverStep < q) {
      if (const Status st = solve_whole(static_cast<double>(lever_grid.size()) * kLeverStep); !st.ok()) return st;
      record_lever();
    }
    Jet3 pose[3];
    for (int k = 0; k < 3; ++k) {
      double d[4];
      lever_pieces.eval_at(q / kLeverStep, k, d);
      pose[k] = jet_from_derivatives<3>(d);
    }
    if (kin::solve_prescribed(m, *scan_ws, q, {3, false}, follower, pose).ok()) return Status::success();
    // the step from the last scan point was rejected: the whole mechanism there
    const Status st = kin::solve(m, *scan_ws, q, {3, false});
    if (!st.ok())
      return {st.code, "the valve train after the lever '" + cut.follower_node + "' pushed " + fmt(q) +
                           " mm along its cam roller's radial path: " + st.message,
              "probe travel " + fmt(q) + " mm"};
    return Status::success();
  };
  for (int j = 0;; ++j) {
    const double q = j * kScanStep;
    if (const Status st = scan_at(q); !st.ok()) return st;
    grid_lift.push_back(at->vars[static_cast<std::size_t>(lift_var)].value());
    const auto c = centre_in(*at);
    std::array<double, 12>& g = grid_jets.emplace_back();
    for (int d = 0; d < 4; ++d) {
      g[d] = at->vars[static_cast<std::size_t>(lift_var)].derivative(d);
      g[4 + d] = c.x.derivative(d);
      g[8 + d] = c.y.derivative(d);
    }
    if (grid_lift.back() > motion_hi && j > 0) break;
    if (q > kMaxTravel)
      return {StatusCode::cannot_assemble,
              "the valve lift through the lever '" + cut.follower_node + "' stays below the target's " +
                  fmt(motion_hi) + " mm over " + fmt(kMaxTravel) + " mm of cam-roller travel",
              "probe travel " + fmt(q) + " mm"};
  }
  const int top = static_cast<int>(grid_lift.size()) - 1;
  detail::SepticPieces scan_pieces(3);  // the scan's septic hermite pieces
  for (int j = 0; j < top; ++j)
    scan_pieces.add_interval(grid_jets[static_cast<std::size_t>(j)].data(), grid_jets[static_cast<std::size_t>(j + 1)].data(),
                             kScanStep);
  // the lift and the roller centre at travel q as jets in q: hermite between scan points,
  // a solve beyond the scan (continued from the last one)
  auto probe_at = [&](double q, Jet3& lift, kin::detail::V2<Jet3>& centre) -> Status {
    if (q >= 0.0 && q <= top * kScanStep) {
      Jet3* out3[3] = {&lift, &centre.x, &centre.y};
      for (int f = 0; f < 3; ++f) {
        double d[4];
        scan_pieces.eval_at(q / kScanStep, f, d);
        *out3[f] = jet_from_derivatives<3>(d);
      }
      return Status::success();
    }
    const Status st = kin::solve(m, ws, q, {3, false});
    if (!st.ok()) return st;
    lift = ws.vars[static_cast<std::size_t>(lift_var)];
    centre = centre_in(ws);
    return Status::success();
  };
  // 2. monotone pieces of L(q) between its turning points. A turn lies where dL/dq changes
  // sign between scan points; it is located on the hermite piece (bisection on dL/dq), as a
  // turn taken at the nearest scan point leaves the piece next to it non-monotone (the
  // bundled Valvetronic at 0.25 deg of control turns 0.017 mm before a scan point: its
  // input cam came out with a 0.038 mm step)
  std::vector<double> turn_q{0.0}, turn_lift{grid_lift[0]};  // piece ends [mm], ascending, and the lift there
  for (int j = 0; j < top; ++j) {
    const double s0 = grid_jets[static_cast<std::size_t>(j)][1], s1 = grid_jets[static_cast<std::size_t>(j + 1)][1];
    if (s0 == 0.0 && j > 0 && (grid_lift[j] - grid_lift[j - 1]) * (grid_lift[j + 1] - grid_lift[j]) < 0) {
      turn_q.push_back(j * kScanStep), turn_lift.push_back(grid_lift[j]);  // a turn on the scan point itself
      continue;
    }
    if (!((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0))) continue;
    double lo = 0.0, hi = 1.0, d[4];
    for (int it = 0; it < 60 && hi - lo > 1e-13; ++it) {
      const double mid = 0.5 * (lo + hi);
      scan_pieces.eval(static_cast<std::size_t>(j), 0, mid, d);
      ((d[1] > 0) == (s0 > 0) ? lo : hi) = mid;
    }
    scan_pieces.eval(static_cast<std::size_t>(j), 0, 0.5 * (lo + hi), d);
    turn_q.push_back((j + 0.5 * (lo + hi)) * kScanStep), turn_lift.push_back(d[0]);
  }
  turn_q.push_back(top * kScanStep), turn_lift.push_back(grid_lift[top]);
  // a piece over which the lift moves by less than kTinyPiece of the target's peak is below
  // what the target can tell: its turns are dropped (a first piece merges into the next, as
  // the bundled Valvetronic's 2.2e-8 mm hump next to its rest at 0 deg of control)
  for (std::size_t k = 0; k + 1 < turn_q.size();) {
    if (turn_q.size() <= 2 || std::abs(turn_lift[k + 1] - turn_lift[k]) >= kTinyPiece * std::max(1.0, motion_hi)) {
      ++k;
      continue;
    }
    // the turns to drop: the first piece's upper end, the last one's lower end, else both ends
    const std::size_t first = k == 0 ? 1 : k, count = (k == 0 || k + 2 == turn_q.size()) ? 1 : 2;
    if (first + count > turn_q.size() - 1) break;  // would remove the scan's end
    turn_q.erase(turn_q.begin() + static_cast<std::ptrdiff_t>(first), turn_q.begin() + static_cast<std::ptrdiff_t>(first + count));
    turn_lift.erase(turn_lift.begin() + static_cast<std::ptrdiff_t>(first),
                    turn_lift.begin() + static_cast<std::ptrdiff_t>(first + count));
    k = 0;
  }
  const int pieces = static_cast<int>(turn_q.size()) - 1;
  if (turn_lift[static_cast<std::size_t>(pieces)] <= turn_lift[static_cast<std::size_t>(pieces - 1)])
    return {StatusCode::cannot_assemble, "the valve lift falls as the lever '" + cut.follower_node +
                                             "' is pushed towards the target's peak", "probe travel " + fmt(top * kScanStep) + " mm"};
  const double mean_slope = std::abs(grid_lift[top] - grid_lift[0]) / (top * kScanStep);
  const double flat = kFlatSlope * mean_slope;  // |dL/dq| below which q is not inverted
  const double rest_lift = grid_lift[0];
  const double reverse = 1e-9 * std::max(1.0, mean_slope);  // [mm] target turning, beyond round-off

  out = {};
  out.centre_x.assign(n, Jet3(0.0));
  out.centre_y.assign(n, Jet3(0.0));
  enum class Kind : char { open, rest, inverted, bridged };
  std::vector<Kind> kind(n, Kind::open);
  std::vector<Jet3> q_of(n, Jet3(0.0));
  std::vector<double> slope_of(n, 0.0);  // dL/dq at each inverted sample
  // invert sample i on piece k (newton inside the piece's grid bracket)
  // guess: the travel predicted from the neighbouring sample (NaN: none), else linear in
  // the scan's bracket
  auto invert_on = [&](int i, int k, double guess, double& a1) -> Status {
    const double target = motion[i].value();
    const auto piece = static_cast<std::size_t>(k);
    const double sign = turn_lift[piece + 1] > turn_lift[piece] ? 1.0 : -1.0;
    // the bracket: between the piece's ends and the scan points inside it, the first whose
    // lift reaches the target and the one before (bisection: the lift is monotone there)
    int inside_lo = static_cast<int>(std::floor(turn_q[piece] / kScanStep)) + 1;
    int inside_hi = static_cast<int>(std::ceil(turn_q[piece + 1] / kScanStep)) - 1;
    while (inside_lo * kScanStep <= turn_q[piece]) ++inside_lo;
    while (inside_hi >= inside_lo && inside_hi * kScanStep >= turn_q[piece + 1]) --inside_hi;
    int reach = inside_lo, past = inside_hi + 1;  // the first scan point inside reaching the target
    auto reaches = [&](int j) { return j > inside_hi || (grid_lift[j] - target) * sign >= 0; };
    if (guess >= 0.0) {  // the scan point just past the predicted travel, if it is that point
      const int near = std::clamp(static_cast<int>(std::ceil(guess / kScanStep)), inside_lo, inside_hi + 1);
      if (reaches(near) && (near == inside_lo || !reaches(near - 1))) reach = past = near;
    }
    while (reach < past) {
      const int mid = (reach + past) / 2;
      if ((grid_lift[mid] - target) * sign >= 0)
        past = mid;
      else
        reach = mid + 1;
    }
    double lo = turn_q[piece], lo_lift = turn_lift[piece], hi = turn_q[piece + 1], hi_lift = turn_lift[piece + 1];
    if (reach > inside_lo) lo = (reach - 1) * kScanStep, lo_lift = grid_lift[reach - 1];
    if (reach <= inside_hi) hi = reach * kScanStep, hi_lift = grid_lift[reach];
    const double span = hi_lift - lo_lift;
    double q = span != 0.0 ? lo + std::clamp((target - lo_lift) / span, 0.0, 1.0) * (hi - lo) : 0.5 * (lo + hi);
    if (guess > lo && guess < hi) q = guess;
    Jet3 L;
    kin::detail::V2<Jet3> c;
    for (int it = 0; it < 100; ++it) {
      const Status st = probe_at(q, L, c);
      if (!st.ok()) return {st.code, st.message, "cam " + deg_of(theta[i]) + " deg"};
      const double f = (L.value() - target) * sign;  // increasing in q on this piece
      if (std::abs(f) <= 1e-13 * std::max(1.0, motion_hi) || hi - lo < 1e-15) {
        a1 = L.c[1];
        q_of[i] = revert(L, q, motion[i]);
        out.centre_x[i] = compose_in(c.x, q_of[i]);
        out.centre_y[i] = compose_in(c.y, q_of[i]);
        return Status::success();
      }
      (f < 0 ? lo : hi) = q;
      double next = L.c[1] * sign > 0 ? q - f / (L.c[1] * sign) : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      q = next;
    }
    return {StatusCode::no_convergence,
            "inverting the valve lift " + fmt(target) + " mm for the travel of the lever '" + cut.follower_node +
                "' did not converge",
            "cam " + deg_of(theta[i]) + " deg"};
  };
  // 3. from the peak back along the opening stroke (q falls) and on along the closing
  // stroke (q falls): each sample on the piece the lever has reached; the walk moves to the
  // previous piece where the target turns back at that piece's turning lift, and stops
  // where the target is at the lever's rest (q = 0)
  int peak = 0;
  for (int i = 1; i < n; ++i)
    if (motion[i].value() > motion[peak].value()) peak = i;
  // (the walks invert on the scan's hermite pieces: the scan continued from the rest keeps
  // the drawing's assembly branch; a cold start next to the peak may land on another one)
  const double h = 2 * pi / n;
  int landing_anchor[2] = {-1, -1};  // per walk (opening, closing): its last inverted sample when it reached the rest
  for (int dir : {-1, +1}) {
    int k = pieces - 1;
    int last = -1, last_piece = -1;  // the walk's last inverted sample and its piece
    double extreme = motion[peak].value();  // the target's running extreme on this piece
    bool near_rest = false;  // on the first piece, past the target's last turn: bridged to the rest
    // each walk covers half the revolution (the opening stroke and the base circle before
    // it, the closing stroke and the base circle after it), unless it reaches the rest
    for (int step = dir < 0 ? 0 : 1; dir < 0 ? step <= n / 2 : step < n - n / 2; ++step) {
      const int i = ((peak + dir * step) % n + n) % n;
      if (kind[i] != Kind::open) break;  // met the other walk
      const double target = motion[i].value();
      if (k == 0 && std::abs(target - rest_lift) <= reverse) {  // the lever at rest: the base circle
        if (last_piece == 0) landing_anchor[dir > 0] = last;
        break;
      }
      if (near_rest) {
        kind[i] = Kind::bridged;
        continue;
      }
      const auto piece = static_cast<std::size_t>(k);
      const double rises = turn_lift[piece + 1] > turn_lift[piece] ? 1.0 : -1.0;  // L(q) rises with q: +1
      // walking towards smaller q the target must move by -rises; a turn back beyond
      // round-off means the lever passed the piece's lower turning point
      if ((target - extreme) * rises > reverse || (k == 0 && (target - rest_lift) * rises < -reverse)) {
        if (k == 0) {
          // a turn (or a step past the rest lift) within a scan step of the rest: the
          // target's ripple next to the rest, left to the bridge down to q = 0
          near_rest = true;
          kind[i] = Kind::bridged;
          continue;
        }
        if (std::abs(extreme - turn_lift[piece]) > kTurnTolerance * std::max(1.0, motion_hi))
          return {StatusCode::singular,
                  "the target lift turns back at " + fmt(extreme) + " mm, but the lever '" + cut.follower_node +
                      "' turns back only at " + fmt(turn_lift[piece]) + " mm of lift (its idle travel, at " +
                      fmt(turn_q[piece]) + " mm of cam-roller travel): the lift does not fix the lever's "
                      "travel there",
                  "cam " + deg_of(theta[i]) + " deg"};
        --k;
        // the samples on both sides of the turn: dL/dq ~ 0, their jets by reversion are
        // ill-conditioned, so they are bridged
        kind[((i - dir) % n + n) % n] = Kind::bridged;
        kind[i] = Kind::bridged;
        extreme = target;
        continue;
      }
      extreme = (target - extreme) * rises < 0 ? target : extreme;
      double a1 = 0.0, guess = NAN;
      if (last == ((i - dir) % n + n) % n && last_piece == k) {
        // cubic taylor of the neighbour's travel, one sample on
        const Jet3& q = q_of[last];
        const double s1 = dir * h;
        guess = q.c[0] + s1 * (q.c[1] + s1 * (q.c[2] + s1 * q.c[3]));
      }
      const Status st = invert_on(i, k, guess, a1);
      if (!st.ok()) return st;
      kind[i] = std::abs(a1) < flat ? Kind::bridged : Kind::inverted;
      slope_of[i] = a1;
      last = i, last_piece = k;
    }
  }
  // a walk whose last inverted sample barely moves the lift lands on the rest as designed
  // (landing_samples) instead of where the target's lift first meets the rest lift: there
  // the lever's travel is ~1e-3 mm, and stepping it to 0 in one sample put a slope step
  // (a -124 mm radius) on the synthesized cam
  for (int side = 0; side < 2; ++side) {
    const int anchor = landing_anchor[side], dir = side == 0 ? -1 : 1;
    if (anchor < 0 || kind[anchor] != Kind::inverted || !(std::abs(slope_of[anchor]) < kLandingSlope * mean_slope))
      continue;
    auto walked = [&](int j) { return ((anchor + dir * j) % n + n) % n; };
    // samples past the anchor that the landing may take: the walk's own bridged tail, then
    // the rest up to the other walk
    int available = 1;
    while (available <= kMaxLandingSamples && kind[walked(available)] == Kind::bridged) ++available;
    while (available <= kMaxLandingSamples && kind[walked(available)] == Kind::open) ++available;
    Jet3 q_tau = q_of[anchor];  // its travel in the walked angle tau = dir (theta - theta_anchor)
    q_tau.c[1] *= dir, q_tau.c[3] *= dir;
    const int landing = landing_samples(q_tau, h, available - 1);
    if (landing == 0) continue;
    for (int j = 1; j < available; ++j) kind[walked(j)] = j < landing ? Kind::bridged : Kind::open;
  }
  for (auto& kd : kind)
    if (kd == Kind::open) kd = Kind::rest;  // between the two walks: the base circle
  // where the walks meet without reaching the rest, they must agree: the lever rests past
  // its drawing rest (a target whose base circle lies beyond the lever's idle travel)
  const int meet_a = ((peak - n / 2) % n + n) % n, meet_b = (meet_a + n - 1) % n;  // the walks' last samples
  if (kind[meet_a] != Kind::rest && kind[meet_b] != Kind::rest) {
    const double gap = std::abs(q_of[meet_a].value() - q_of[meet_b].value());
    if (kind[meet_a] == Kind::inverted && kind[meet_b] == Kind::inverted && gap > 1e-3)
      return {StatusCode::singular,
              "the opening and closing strokes leave the lever '" + cut.follower_node + "' " + fmt(gap) +
                  " mm of cam-roller travel apart on the base circle: the target's base circle lies on two pieces of "
                  "the lever's lift (before and after its idle travel)",
              "cam " + deg_of(theta[meet_a]) + " deg"};
    out.rest_travel_mm = q_of[meet_a].value();
  }
  // 4. bridges: runs of samples where the lift barely moves with q (next to a turning
  // point or the rest) take q from septic hermite pieces between their neighbours' jets
  int rest_samples = 0, bridged_samples = 0;
  const kin::detail::V2<Jet3> rest_centre{Jet3(grid_jets[0][4]), Jet3(grid_jets[0][8])};
  for (int i = 0; i < n; ++i)
    if (kind[i] == Kind::rest) {
      ++rest_samples;
      out.centre_x[i] = Jet3(rest_centre.x.value());
      out.centre_y[i] = Jet3(rest_centre.y.value());
      q_of[i] = Jet3(0.0);
    }
  for (int i = 0; i < n; ++i) {
    if (kind[i] != Kind::bridged || kind[(i + n - 1) % n] == Kind::bridged) continue;
    int count = 0;
    while (count < n && kind[(i + count) % n] == Kind::bridged) ++count;
    if (count >= n) return {StatusCode::singular, "the lift does not fix the lever anywhere", "whole revolution"};
    const int before = (i + n - 1) % n, after = (i + count) % n;
    const double span = (count + 1) * h;
    double p0[4], p1[4];
    for (int o = 0; o < 4; ++o) {
      p0[o] = q_of[before].derivative(o) * std::pow(span, o);
      p1[o] = q_of[after].derivative(o) * std::pow(span, o);
    }
    const detail::Septic piece(p0, p1);
    for (int c = 0; c < count; ++c) {
      const int s = (i + c) % n;
      double d[4];
      piece.eval((c + 1.0) / (count + 1.0), d);  // derivatives per unit of the piece's parameter
      d[0] = std::max(0.0, d[0]);
      for (int o = 1; o < 4; ++o) d[o] /= std::pow(span, o);
      const Jet3 q = jet_from_derivatives<3>(d);
      Jet3 lift;
      kin::detail::V2<Jet3> cc;
      const Status st = probe_at(q.value(), lift, cc);
      if (!st.ok()) return {st.code, st.message, "cam " + deg_of(theta[s]) + " deg"};
      const double e = std::abs(lift.value() - motion[s].value());
      if (e > out.fill_error_mm) out.fill_error_mm = e, out.fill_error_at_rad = theta[s];
      out.centre_x[s] = compose_in(cc.x, q);
      out.centre_y[s] = compose_in(cc.y, q);
      ++bridged_samples;
    }
  }
  out.rest_lift = rest_lift;
  out.fill_span = std::to_string(rest_samples) + " samples at the lever's rest, " + std::to_string(bridged_samples) +
                  " bridged where the lift barely moves with the lever (" + std::to_string(pieces) +
                  " monotone piece(s) of the lift against the cam-roller travel)";
  return Status::success();
}

}  // namespace camopt::synthesis
