#include "camopt/synthesis/lever_path.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/core/trig_cache.hpp"
#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/detail/radial_probe.hpp"

namespace camopt::synthesis {

namespace {

using Jet3 = Jet<3>;

// [mm] probe travel between scan points. The lever's pose is analytic in the travel where
// its other contacts are circles (the bundled Valvetronic's eccentric disc and gate), so
// septic hermite between scan points errs by ~ (step / arm)^8 of the arm. At 0.25, 0.5 and
// 1 mm the bundled lever agrees with solves of its whole contact cluster to 3e-12, 6e-12
// and 3e-12 mm, its third derivative in the cam angle to 2e-9, 1.2e-9 and 1.4e-10 of its
// scale: the solves' own noise (lever_path_test.cpp)
constexpr double kLeverPathStep = 0.5;
constexpr int kMaxScanPoints = 4000;
// residual tolerance of the contact's newton, relative to the mechanism's size (as the
// kinematics solver's)
constexpr double kRelativeTolerance = 1e-13;

std::string fmt(double v) { return format_value(v, 6); }
std::string driver_deg(double theta) { return "driver " + fmt(theta * 180 / pi) + " deg"; }

// grid entry f (0..2: lever variables, 3, 4: roller centre x, y) at travel q: value and
// three derivatives in q (septic hermite between scan points), or the value and slope only
void grid_at(const LeverPath& p, int f, double q, double out[4], bool slope_only = false) {
  p.pieces.eval_at((q - p.q_first) / p.step, f, out, slope_only);
}

// the probe's node and face names are not used by the design (else compile would reject
// the probe spec as a duplicate)
bool probe_names_free(const DesignSpec& spec) {
  return std::none_of(spec.nodes.begin(), spec.nodes.end(), [](const NodeSpec& n) { return n.name == detail::kProbeNode; }) &&
         std::none_of(spec.connections.begin(), spec.connections.end(),
                      [](const ConnectionSpec& c) { return c.name == detail::kProbeFace; });
}

}  // namespace

Status build_lever_path(const DesignSpec& upstream, const kin::Mechanism& up, int lever,
                        const std::vector<double>& controls, LeverPath& out) {
  out = {};
  const int driver = up.driver_node;
  if (driver < 0 || up.nodes[static_cast<std::size_t>(driver)].kind != NodeKind::rotational ||
      up.nodes[static_cast<std::size_t>(lever)].kind != NodeKind::floating)
    return Status::success();
  // the driver's one connection: a cam contact with its profile on the driver and a roller
  // (convex circle) on the lever
  int contact = -1;
  for (std::size_t ci = 0; ci < up.connections.size(); ++ci) {
    const kin::Connection& c = up.connections[ci];
    if (c.node_a != driver && c.node_b != driver) continue;
    if (contact >= 0) return Status::success();
    contact = static_cast<int>(ci);
  }
  if (contact < 0) return Status::success();
  const kin::Connection& c = up.connections[static_cast<std::size_t>(contact)];
  const bool cam_on_a = c.node_a == driver;
  const kin::Surface& cam = cam_on_a ? c.surface_a : c.surface_b;
  const kin::Surface& roller = cam_on_a ? c.surface_b : c.surface_a;
  if (c.kind != ConnectionKind::contact || c.one_sided || (cam_on_a ? c.node_b : c.node_a) != lever ||
      cam.kind != kin::SurfaceKind::curve || cam.variable < 0 || roller.kind != kin::SurfaceKind::point ||
      !(roller.offset > 0.0))
    return Status::success();
  const auto contact_spec = std::find_if(upstream.connections.begin(), upstream.connections.end(),
                                         [&](const ConnectionSpec& s) { return s.name == c.name; });
  const auto driver_spec = std::find_if(upstream.nodes.begin(), upstream.nodes.end(), [&](const NodeSpec& n) {
    return n.name == up.nodes[static_cast<std::size_t>(driver)].name;
  });
  CAMOPT_ASSERT(contact_spec != upstream.connections.end() && driver_spec != upstream.nodes.end());
  const SurfaceSpec roller_spec = cam_on_a ? contact_spec->surface_b : contact_spec->surface_a;
  const double px = driver_spec->pivot_mm[0], py = driver_spec->pivot_mm[1];
  const double cx = roller_spec.origin_mm[0], cy = roller_spec.origin_mm[1];
  if (!(std::hypot(cx - px, cy - py) > 1e-9 * up.length_scale)) return Status::success();
  // the lever without the driver: the probe pushes its roller
  DesignSpec probe_spec = upstream;
  const std::string lever_name = up.nodes[static_cast<std::size_t>(lever)].name;
  std::erase_if(probe_spec.connections, [&](const ConnectionSpec& s) { return s.name == c.name; });
  std::erase_if(probe_spec.nodes, [&](const NodeSpec& n) { return n.name == driver_spec->name; });
  auto [probe, face] = detail::radial_probe(roller_spec, px, py, cx, cy);
  probe_spec.nodes.push_back(probe);
  probe_spec.connections.push_back(face);
  // only the profiles the lever's other contacts use (compile builds every listed profile)
  std::erase_if(probe_spec.profiles, [&](const ProfileSpec& pr) {
    return std::none_of(probe_spec.connections.begin(), probe_spec.connections.end(), [&](const ConnectionSpec& k) {
      return (k.surface_a.shape == SurfaceShape::profile && k.surface_a.profile == pr.name) ||
             (k.surface_b.shape == SurfaceShape::profile && k.surface_b.profile == pr.name);
    });
  });
  probe_spec.driver = DriverSpec{};
  probe_spec.driver.node = probe.name;
  probe_spec.output_node = lever_name;
  // the probe spec has the structure of the upstream half (the driver's angle and the cam
  // contact's two equations in the cam parameter and the lever become the probe's travel
  // and the face contact's two equations in the face parameter and the lever), whose
  // assembly analysis compile() passed: it compiles too, unless a name is taken
  if (!probe_names_free(upstream)) return Status::success();
  const kin::Mechanism m = kin::compile(probe_spec);
  const int lv = m.node_index(lever_name);
  if (!detail::held_analytically(m, lv)) return Status::success();  // not smooth enough for the path's steps
  const kin::Node& probe_lever = m.nodes[static_cast<std::size_t>(lv)];
  const kin::Node& up_lever = up.nodes[static_cast<std::size_t>(lever)];
  const double len = std::hypot(cx - px, cy - py);
  out.roller = {roller.origin.x(), roller.origin.y()};
  out.probe_at = {cx, cy};
  out.direction = {(cx - px) / len, (cy - py) / len};
  out.centre_offset = roller.offset - c.lash;
  out.step = kLeverPathStep;
  // the scan covers the roller centre's reach on the cam: from the cam's smallest radius to
  // its largest, plus the roller's radius, and a scan step beyond each
  const kin::CamProfile& profile = up.profiles[static_cast<std::size_t>(cam.profile)];
  const double reach_lo = profile.base_radius_mm() + out.centre_offset - kLeverPathStep;
  const double reach_hi = profile.max_radius_mm() + out.centre_offset + kLeverPathStep;
  // the lever's variables in the upstream mechanism from its pose in the probe's: the same
  // rigid motion about a reference point of its own (compile places each at the centroid of
  // the body's features): x_up = t + R (ref_up - ref_probe) - ref_up
  const double ex = up_lever.reference.x() - probe_lever.reference.x();
  const double ey = up_lever.reference.y() - probe_lever.reference.y();
  kin::Workspace ws(m);
  ws.set_controls(controls);
  auto scan_point = [&](double q, std::array<double, 20>& g, double& reach) -> Status {
    const Status st = kin::solve(m, ws, q, {3, false});
    if (!st.ok()) return st;
    const auto pose = kin::node_pose(m, lv, ws.vars.data(), ws.pivots().data());
    const Jet3 x = pose.tx + pose.c * ex - pose.s * ey - up_lever.reference.x();
    const Jet3 y = pose.ty + pose.s * ex + pose.c * ey - up_lever.reference.y();
    const Jet3& phi = ws.vars[static_cast<std::size_t>(probe_lever.first_variable + 2)];
    const auto centre = pose.apply(cx, cy);
    const Jet3* f[5] = {&x, &y, &phi, &centre.x, &centre.y};
    for (int k = 0; k < 5; ++k)
      for (int d = 0; d < 4; ++d) g[static_cast<std::size_t>(4 * k + d)] = f[k]->derivative(d);
    reach = std::hypot(centre.x.value() - px, centre.y.value() - py);
    return Status::success();
  };
  std::vector<std::array<double, 20>> ahead, behind;  // q >= 0 ascending, q < 0 descending
  double reach = 0.0;
  kin::Workspace at_zero = ws;  // solved at q = 0: the scan below 0 continues from it
  for (int side = 0; side < 2; ++side) {
    for (int j = side == 0 ? 0 : -1;; j += side == 0 ? 1 : -1) {
      std::array<double, 20> g{};
      const double q = j * kLeverPathStep;
      if (const Status st = scan_point(q, g, reach); !st.ok())
        return {st.code, "the lever '" + lever_name + "' pushed " + fmt(q) + " mm along its roller's radial path: " +
                             st.message, "probe travel " + fmt(q) + " mm"};
      if (j == 0) at_zero = ws;
      (side == 0 ? ahead : behind).push_back(g);
      if (side == 0 ? reach > reach_hi && j > 0 : reach < reach_lo) break;
      if (static_cast<int>(ahead.size() + behind.size()) > kMaxScanPoints)
        return {StatusCode::cannot_assemble,
                "the lever '" + lever_name + "' pushed along its roller's radial path does not cover the cam's reach (" +
                    fmt(reach_lo) + " .. " + fmt(reach_hi) + " mm from its pivot)",
                "probe travel " + fmt(q) + " mm"};
    }
    if (side == 0) ws = at_zero;
  }
  std::vector<std::array<double, 20>> grid(behind.rbegin(), behind.rend());  // ascending q
  grid.insert(grid.end(), ahead.begin(), ahead.end());
  for (std::size_t j = 0; j + 1 < grid.size(); ++j)
    out.pieces.add_interval(grid[j].data(), grid[j + 1].data(), kLeverPathStep);
  out.q_first = -static_cast<double>(behind.size()) * kLeverPathStep;
  out.contact = contact;
  out.lever_node = lever;
  return Status::success();
}

void lever_path_state(const LeverPath& path, const kin::Mechanism& up, const kin::Workspace& ws, double theta,
                      LeverState& state) {
  const kin::Connection& c = up.connections[static_cast<std::size_t>(path.contact)];
  const kin::Surface& cam = c.node_a == up.driver_node ? c.surface_a : c.surface_b;
  const auto centre =
      kin::node_pose(up, path.lever_node, ws.values().data(), ws.pivots().data()).apply(path.roller[0], path.roller[1]);
  state.theta = theta;
  state.q = Jet3(path.direction[0] * (centre.x - path.probe_at[0]) + path.direction[1] * (centre.y - path.probe_at[1]));
  state.u = Jet3(ws.values()[static_cast<std::size_t>(cam.variable)]);
}

Status lever_at(const LeverPath& path, const kin::Mechanism& up, const kin::Workspace& ws, double theta,
                LeverState& state, Jet3 out[3]) {
  const kin::Connection& c = up.connections[static_cast<std::size_t>(path.contact)];
  const kin::Surface& cam = c.node_a == up.driver_node ? c.surface_a : c.surface_b;
  const kin::Node& driver = up.nodes[static_cast<std::size_t>(up.driver_node)];
  const Eigen::Vector2d pivot = ws.pivots()[static_cast<std::size_t>(up.driver_node)];
  // the cam's pose at theta: p = pivot + R(theta) (p_drawing - drawing pivot)
  double sn, cs;
  sin_cos(theta, sn, cs);
  const double rx = driver.pivot.x(), ry = driver.pivot.y();
  const double tol = kRelativeTolerance * up.length_scale;
  const double q_last = path.q_first + path.step * static_cast<double>(path.pieces.intervals());
  // the start: the last angle's taylor series carried to theta (its value alone if that
  // leaves the scan)
  const double h = theta - state.theta;
  double q = state.q.c[0] + h * (state.q.c[1] + h * (state.q.c[2] + h * state.q.c[3]));
  double u = state.u.c[0] + h * (state.u.c[1] + h * (state.u.c[2] + h * state.u.c[3]));
  if (!(q >= path.q_first && q <= q_last)) q = state.q.c[0], u = state.u.c[0];
  // newton on roller centre C(q) = cam point G(u): J = [C_q, -G_u]; J (dq, du) = -(fx, fy)
  double cq[2][4], gux = 0, guy = 0, det = 0;
  auto step = [&](double fx, double fy, double& dq, double& du) {
    dq = (fx * guy - gux * fy) / det;
    du = (cq[1][1] * fx - cq[0][1] * fy) / det;
  };
  bool converged = false;
  for (int it = 0; it < 30 && !converged; ++it) {
    if (!(q >= path.q_first && q <= q_last))
      return {StatusCode::no_convergence,
              "the lever's roller left its scanned path (" + fmt(q) + " mm of probe travel, scanned " +
                  fmt(path.q_first) + " .. " + fmt(q_last) + " mm)",
              driver_deg(theta)};
    const auto g = kin::offset_local<1>(up, cam, path.centre_offset, u);
    const double dx = g.x.c[0] - rx, dy = g.y.c[0] - ry;
    const double gx = pivot.x() + cs * dx - sn * dy, gy = pivot.y() + sn * dx + cs * dy;
    gux = cs * g.x.c[1] - sn * g.y.c[1], guy = sn * g.x.c[1] + cs * g.y.c[1];
    grid_at(path, 3, q, cq[0], true);  // newton needs the value and slope
    grid_at(path, 4, q, cq[1], true);
    const double fx = cq[0][0] - gx, fy = cq[1][0] - gy;
    det = cq[0][1] * -guy + gux * cq[1][1];
    if (!(std::abs(det) > 0.0)) break;
    // within the tolerance one more step takes the travel to round-off (quadratic
    // convergence): the lever then does not carry the tolerance's noise, which the swing
    // profile's untouched far side would magnify (to ~1e-7 mm)
    converged = std::hypot(fx, fy) <= tol;
    double dq, du;
    step(fx, fy, dq, du);
    q += dq, u += du;
  }
  if (!converged)
    return {StatusCode::no_convergence, "the cam contact on the lever's roller did not converge",
            driver_deg(theta)};
  grid_at(path, 3, q, cq[0]);
  grid_at(path, 4, q, cq[1]);
  det = cq[0][1] * -guy + gux * cq[1][1];
  // taylor coefficients in theta, order by order: (C(q(t)) - G(u(t), t))_k = 0 is linear in
  // (q_k, u_k) with the newton jacobian, the lower orders known
  const auto g3 = kin::offset_local<3>(up, cam, path.centre_offset, u);
  double gdx[4], gdy[4];
  for (int d = 0; d < 4; ++d) gdx[d] = g3.x.derivative(d), gdy[d] = g3.y.derivative(d);
  Jet3 s3, c3;
  sin_cos(Jet3::variable(theta), s3, c3);
  Jet3 qj(q), uj(u);
  for (int k = 1; k <= 3; ++k) {
    const Jet3 ax = compose(gdx, uj) - rx, ay = compose(gdy, uj) - ry;
    const Jet3 fx = compose(cq[0], qj) - (pivot.x() + c3 * ax - s3 * ay);
    const Jet3 fy = compose(cq[1], qj) - (pivot.y() + s3 * ax + c3 * ay);
    step(fx.c[k], fy.c[k], qj.c[k], uj.c[k]);
  }
  for (int f = 0; f < 3; ++f) {
    double d[4];
    grid_at(path, f, q, d);
    out[f] = compose(d, qj);
  }
  state.theta = theta;
  state.q = qj;
  state.u = uj;
  return Status::success();
}

}  // namespace camopt::synthesis
