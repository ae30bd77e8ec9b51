// steps 1 and 2 of the inversion through a floating follower (floating_inversion.hpp,
// detail/floating_scan.hpp): the lever parameterised by the travel q of a radial probe on
// its cam roller, its lift L(q) scanned from the rest, and L(q) split into monotone pieces.
#include "camopt/synthesis/detail/floating_scan.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "camopt/synthesis/detail/radial_probe.hpp"

namespace camopt::synthesis::detail {

namespace {

using Jet3 = Jet<3>;

std::string fmt(double v) { return format_value(v, 6); }

// [mm] probe travel between solves of the whole mechanism where the scan takes the lever's
// pose from them (septic hermite in q)
constexpr double kLeverStep = 0.5;
constexpr double kMaxTravel = 100.0;  // [mm] the scan gives up beyond this probe travel
// [mm per mm of peak lift] a monotone piece of L(q) over which the lift moves by less is
// not told apart from its neighbours (its turns are dropped)
constexpr double kTinyPiece = 1e-8;

// the downstream half with the probe pushing the roller through (cx, cy)
kin::Mechanism make_probe(const MechanismCut& cut, const FloatingRoller& roller, const std::string& target_node,
                          double cx, double cy) {
  DesignSpec probe_spec = cut.downstream;
  auto [probe, face] = radial_probe(*roller.surface, roller.px, roller.py, cx, cy);
  probe_spec.nodes.push_back(probe);
  probe_spec.connections.push_back(face);
  probe_spec.driver.node = probe.name;
  probe_spec.output_node = target_node;
  return kin::compile(probe_spec);
}

// the compiled probe mechanism moved to push through (cx, cy): compile takes nothing else
// from the probe than its node's line and its face (and their distances from the origin
// for the length scale), so moving those gives what a fresh compile would, without
// building the lever's profiles again. false (mech untouched) when the length scale would
// change: compile afresh then.
bool move_probe(const FloatingRoller& roller, kin::Mechanism& mech, double cx, double cy) {
  const auto [probe, face] = radial_probe(*roller.surface, roller.px, roller.py, cx, cy);
  kin::Node& node = mech.nodes[static_cast<std::size_t>(mech.node_index(probe.name))];
  kin::Connection& contact = mech.connections.back();
  CAMOPT_ASSERT(contact.name == face.name && mech.nodes.back().name == probe.name);
  const Eigen::Vector2d origin(probe.origin_mm[0], probe.origin_mm[1]);
  const Eigen::Vector2d face_origin(face.surface_a.origin_mm[0], face.surface_a.origin_mm[1]);
  const double scale = mech.length_scale;
  if (!(std::max({node.pivot.norm(), contact.surface_a.origin.norm(), origin.norm(), face_origin.norm()}) < scale))
    return false;
  node.pivot = origin;
  node.direction = Eigen::Vector2d(probe.direction[0], probe.direction[1]).normalized();  // as compile does
  contact.surface_a.origin = face_origin;
  contact.surface_a.normal = Eigen::Vector2d(face.surface_a.normal[0], face.surface_a.normal[1]).normalized();
  return true;
}

// the lever at rest: its cam roller on the base circle (as far from the cam pivot as in the
// drawing). Away from the drawing's control position the other contacts move the rest pose
// (a Valvetronic eccentric turns the lever about the camshaft), so it is found by newton on
// |c(q) - pivot| = base with a probe along the drawing's radial direction (m0)
Status rest_pose(const kin::Mechanism& m0, const MechanismCut& cut, const FloatingRoller& roller,
                 const std::vector<double>& controls, double& rest_x, double& rest_y) {
  const double c0x = roller.surface->origin_mm[0], c0y = roller.surface->origin_mm[1];
  const double px = roller.px, py = roller.py, base = roller.base;
  kin::Workspace ws0(m0);
  ws0.set_controls(controls);
  const int f0 = m0.node_index(cut.follower_node);
  double q = 0.0;
  for (int it = 0;; ++it) {
    const Status st = kin::solve(m0, ws0, q, {1, false});
    if (!st.ok()) return {st.code, "placing the lever '" + cut.follower_node + "' at rest: " + st.message, "cam base circle"};
    const auto c = kin::node_pose(m0, f0, ws0.vars.data(), ws0.pivots().data()).apply(c0x, c0y);
    const Jet3 rho = sqrt((c.x - px) * (c.x - px) + (c.y - py) * (c.y - py));
    rest_x = c.x.value(), rest_y = c.y.value();
    const double miss = rho.value() - base;
    if (std::abs(miss) < 1e-12 * base) return Status::success();
    if (it == 50 || !(std::abs(rho.c[1]) > 1e-9))
      return {StatusCode::no_convergence,
              "placing the lever '" + cut.follower_node + "' at rest with its roller on the base circle (" +
                  fmt(base) + " mm from the cam pivot): " + fmt(miss) + " mm off",
              "cam base circle"};
    q -= miss / rho.c[1];
  }
}

}  // namespace

FloatingRoller floating_roller(const DesignSpec& spec, const MechanismCut& cut) {
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
  FloatingRoller out;
  out.surface = &follower_surface;
  const double c0x = follower_surface.origin_mm[0], c0y = follower_surface.origin_mm[1];
  out.px = cam_node->pivot_mm[0], out.py = cam_node->pivot_mm[1];
  out.base = std::hypot(c0x - out.px, c0y - out.py);
  if (!(out.base > 1e-9))
    throw InputError(conn.where, "synthesize: the roller of '" + cut.follower_node + "' is centred on the cam pivot");
  return out;
}

Status probe_through_rest(const MechanismCut& cut, const FloatingRoller& roller, const std::string& target_node,
                          const std::vector<double>& controls, kin::Mechanism& out) {
  const double c0x = roller.surface->origin_mm[0], c0y = roller.surface->origin_mm[1];
  double rest_x = c0x, rest_y = c0y;
  out = make_probe(cut, roller, target_node, c0x, c0y);
  if (Status st = rest_pose(out, cut, roller, controls, rest_x, rest_y); !st.ok()) return st;
  // the probe through the rest pose (the drawing's own when the lever rests as drawn, to
  // the rest newton's tolerance)
  const bool rests_as_drawn = std::hypot(rest_x - c0x, rest_y - c0y) < 1e-12 * roller.base;
  if (!rests_as_drawn && !move_probe(roller, out, rest_x, rest_y)) out = make_probe(cut, roller, target_node, rest_x, rest_y);
  return Status::success();
}

LeverScan::LeverScan(kin::Mechanism probe, const std::vector<double>& controls, const MechanismCut& cut,
                     const FloatingRoller& roller, const std::string& target_node)
    : m_(std::move(probe)), ws_(m_), cut_(cut) {
  ws_.set_controls(controls);
  lift_var_ = m_.nodes[static_cast<std::size_t>(m_.node_index(target_node))].first_variable;
  follower_ = m_.node_index(cut.follower_node);
  c0x_ = roller.surface->origin_mm[0], c0y_ = roller.surface->origin_mm[1];
}

kin::V2<Jet3> LeverScan::centre_in(const kin::Workspace& w) const {
  return kin::node_pose(m_, follower_, w.vars.data(), w.pivots().data()).apply(c0x_, c0y_);
}

// the scan points of a LeverScan. The lever itself is smooth in q where its other contacts
// are analytic (the bundled Valvetronic's rollers on a disc and a circle), the lift is not
// (the working curve is a table): there, and where the kernel can take the lever as given
// (kin::solve_prescribed), the whole mechanism is solved only every kLeverStep, and at the
// scan points between them the lever's pose is septic hermite in q from those solves and
// only the contacts after it are solved
class LeverScanner {
 public:
  LeverScanner(LeverScan& scan, double motion_hi)
      : scan_(scan),
        motion_hi_(motion_hi),
        lever_given_(kin::can_prescribe(scan.m_, scan.follower_) && held_analytically(scan.m_, scan.follower_)),
        lever_(scan.m_.nodes[static_cast<std::size_t>(scan.follower_)]) {}

  // the scan point at q: solved in the scan's workspace, or with the lever given in
  // scan_ws_; the solved workspace in `solved()`
  Status scan_at(double q) {
    if (!lever_given_) return solve_whole(q);
    if (q == 0.0) {
      if (const Status st = solve_whole(q); !st.ok()) return st;
      record_lever();
      scan_ws_ = scan_.ws_;
      at_ = &*scan_ws_;
      return Status::success();
    }
    while (static_cast<double>(lever_grid_.size() - 1) * kLeverStep < q) {
      if (const Status st = solve_whole(static_cast<double>(lever_grid_.size()) * kLeverStep); !st.ok()) return st;
      record_lever();
    }
    Jet3 pose[3];
    for (int k = 0; k < 3; ++k) {
      double d[4];
      lever_pieces_.eval_at(q / kLeverStep, k, d);
      pose[k] = jet_from_derivatives<3>(d);
    }
    if (kin::solve_prescribed(scan_.m_, *scan_ws_, q, {3, false}, scan_.follower_, pose).ok()) return Status::success();
    // the step from the last scan point was rejected: the whole mechanism there
    const Status st = kin::solve(scan_.m_, *scan_ws_, q, {3, false});
    if (!st.ok())
      return {st.code, "the valve train after the lever '" + scan_.follower_name() + "' pushed " + fmt(q) +
                           " mm along its cam roller's radial path: " + st.message,
              "probe travel " + fmt(q) + " mm"};
    return Status::success();
  }
  const kin::Workspace& solved() const { return *at_; }

 private:
  Status solve_whole(double q) {
    const Status st = kin::solve(scan_.m_, scan_.ws_, q, {3, false});
    if (!st.ok())
      return {st.code,
              "the lever '" + scan_.follower_name() + "' pushed " + fmt(q) + " mm along its cam roller's radial path "
              "cannot be solved with its other contacts (" + st.message + ") before the valve reaches the target's " +
                  fmt(motion_hi_) + " mm",
              "probe travel " + fmt(q) + " mm"};
    return Status::success();
  }
  // the lever's pose as just solved in the scan's workspace, a point of lever_grid_
  void record_lever() {
    std::array<double, 12>& g = lever_grid_.emplace_back();
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 4; ++d)
        g[4 * k + d] = scan_.ws_.vars[static_cast<std::size_t>(lever_.first_variable + k)].derivative(d);
    if (lever_grid_.size() >= 2)
      lever_pieces_.add_interval(lever_grid_[lever_grid_.size() - 2].data(), lever_grid_.back().data(), kLeverStep);
  }

  LeverScan& scan_;
  double motion_hi_;
  bool lever_given_;
  const kin::Node& lever_;
  std::vector<std::array<double, 12>> lever_grid_;  // [x, y, phi][derivative 0..3] every kLeverStep
  SepticPieces lever_pieces_{3};                     // between them
  std::optional<kin::Workspace> scan_ws_;            // the scan between the lever's solves
  const kin::Workspace* at_ = &scan_.ws_;
};

Status LeverScan::run(double motion_hi) {
  LeverScanner scanner(*this, motion_hi);
  for (int j = 0;; ++j) {
    const double q = j * kScanStep;
    if (const Status st = scanner.scan_at(q); !st.ok()) return st;
    const kin::Workspace& at = scanner.solved();
    lift.push_back(at.vars[static_cast<std::size_t>(lift_var_)].value());
    const auto c = centre_in(at);
    std::array<double, 12>& g = jets.emplace_back();
    for (int d = 0; d < 4; ++d) {
      g[d] = at.vars[static_cast<std::size_t>(lift_var_)].derivative(d);
      g[4 + d] = c.x.derivative(d);
      g[8 + d] = c.y.derivative(d);
    }
    if (lift.back() > motion_hi && j > 0) break;
    if (q > kMaxTravel)
      return {StatusCode::cannot_assemble,
              "the valve lift through the lever '" + follower_name() + "' stays below the target's " +
                  fmt(motion_hi) + " mm over " + fmt(kMaxTravel) + " mm of cam-roller travel",
              "probe travel " + fmt(q) + " mm"};
  }
  top = static_cast<int>(lift.size()) - 1;
  for (int j = 0; j < top; ++j)
    pieces.add_interval(jets[static_cast<std::size_t>(j)].data(), jets[static_cast<std::size_t>(j + 1)].data(), kScanStep);
  return Status::success();
}

Status LeverScan::at(double q, Jet3& lift_jet, kin::V2<Jet3>& centre) {
  if (q >= 0.0 && q <= top * kScanStep) {
    Jet3* out3[3] = {&lift_jet, &centre.x, &centre.y};
    for (int f = 0; f < 3; ++f) {
      double d[4];
      pieces.eval_at(q / kScanStep, f, d);
      *out3[f] = jet_from_derivatives<3>(d);
    }
    return Status::success();
  }
  // beyond the scan: a solve (continued from the last one)
  const Status st = kin::solve(m_, ws_, q, {3, false});
  if (!st.ok()) return st;
  lift_jet = ws_.vars[static_cast<std::size_t>(lift_var_)];
  centre = centre_in(ws_);
  return Status::success();
}

namespace {

// the turns of L(q): where dL/dq changes sign between scan points, located on the hermite
// piece (bisection on dL/dq), as a turn taken at the nearest scan point leaves the piece
// next to it non-monotone (the bundled Valvetronic at 0.25 deg of control turns 0.017 mm
// before a scan point: its input cam would come out with a 0.038 mm step)
void find_turns(const LeverScan& scan, LiftPieces& out) {
  const std::vector<double>& grid_lift = scan.lift;
  const int top = scan.top;
  out.turn_q = {0.0}, out.turn_lift = {grid_lift[0]};
  for (int j = 0; j < top; ++j) {
    const double s0 = scan.jets[static_cast<std::size_t>(j)][1], s1 = scan.jets[static_cast<std::size_t>(j + 1)][1];
    if (s0 == 0.0 && j > 0 && (grid_lift[j] - grid_lift[j - 1]) * (grid_lift[j + 1] - grid_lift[j]) < 0) {
      out.turn_q.push_back(j * kScanStep), out.turn_lift.push_back(grid_lift[j]);  // a turn on the scan point itself
      continue;
    }
    if (!((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0))) continue;
    double lo = 0.0, hi = 1.0, d[4];
    for (int it = 0; it < 60 && hi - lo > 1e-13; ++it) {
      const double mid = 0.5 * (lo + hi);
      scan.pieces.eval(static_cast<std::size_t>(j), 0, mid, d);
      ((d[1] > 0) == (s0 > 0) ? lo : hi) = mid;
    }
    scan.pieces.eval(static_cast<std::size_t>(j), 0, 0.5 * (lo + hi), d);
    out.turn_q.push_back((j + 0.5 * (lo + hi)) * kScanStep), out.turn_lift.push_back(d[0]);
  }
  out.turn_q.push_back(top * kScanStep), out.turn_lift.push_back(grid_lift[top]);
}

// a piece over which the lift moves by less than kTinyPiece of the target's peak is below
// what the target can tell: its turns are dropped (a first piece merges into the next, as
// the bundled Valvetronic's 2.2e-8 mm hump next to its rest at 0 deg of control)
void drop_tiny_pieces(double motion_hi, LiftPieces& p) {
  std::vector<double>& turn_q = p.turn_q;
  std::vector<double>& turn_lift = p.turn_lift;
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
}

}  // namespace

Status monotone_pieces(const LeverScan& scan, double motion_hi, LiftPieces& out) {
  find_turns(scan, out);
  drop_tiny_pieces(motion_hi, out);
  const int pieces = out.count();
  if (out.turn_lift[static_cast<std::size_t>(pieces)] <= out.turn_lift[static_cast<std::size_t>(pieces - 1)])
    return {StatusCode::cannot_assemble, "the valve lift falls as the lever '" + scan.follower_name() +
                                             "' is pushed towards the target's peak", "probe travel " + fmt(scan.top * kScanStep) + " mm"};
  return Status::success();
}

}  // namespace camopt::synthesis::detail
