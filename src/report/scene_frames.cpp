// the scene's frames: at every control position the driver sweep solved point by point by
// kin::solve (the continuation kin::sweep runs, so every frame is the CSV row of its angle),
// and per frame every body's pose, every contact's point and normal, the output node's lift
// and the contacts' surface parameters (for the extent of the drawn faces and guides)
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/kinematics/solver.hpp"
#include "scene_detail.hpp"

namespace camopt::report::detail {

namespace {

// a rigid map drawing -> current, as a scene pose: current = R(angle) drawing + t
struct ScenePose {
  double tx = 0, ty = 0, angle = 0;
};

// a node's pose from the solved values: kin::Pose maps p -> t + R (p - ref)
ScenePose node_scene_pose(const kin::Mechanism& mech, const kin::Workspace& ws, int n) {
  const kin::Node& node = mech.nodes[static_cast<std::size_t>(n)];
  const kin::Pose<double> p = kin::node_pose(mech, n, ws.values().data(), ws.pivots().data());
  double angle = 0.0;
  if (!node.ground && node.kind == NodeKind::rotational) angle = ws.values()[static_cast<std::size_t>(node.first_variable)];
  if (!node.ground && node.kind == NodeKind::floating) angle = ws.values()[static_cast<std::size_t>(node.first_variable) + 2];
  return {p.tx - (p.c * p.rx - p.s * p.ry), p.ty - (p.s * p.rx + p.c * p.ry), angle};
}

// a link bar's pose: pin a where node a carries it, the bar along the current pins
ScenePose link_scene_pose(const kin::Mechanism& mech, const kin::Workspace& ws, const ExtraBody& e) {
  const kin::Connection& c = mech.connections[static_cast<std::size_t>(e.connection)];
  const auto pa = kin::node_pose(mech, c.node_a, ws.values().data(), ws.pivots().data()).apply(c.pin_a.x(), c.pin_a.y());
  const auto pb = kin::node_pose(mech, c.node_b, ws.values().data(), ws.pivots().data()).apply(c.pin_b.x(), c.pin_b.y());
  const Eigen::Vector2d d0 = c.pin_b - c.pin_a;
  const double angle = std::atan2(pb.y - pa.y, pb.x - pa.x) - std::atan2(d0.y(), d0.x());
  const double co = std::cos(angle), si = std::sin(angle);
  return {pa.x - (co * c.pin_a.x() - si * c.pin_a.y()), pa.y - (si * c.pin_a.x() + co * c.pin_a.y()), angle};
}

// a pivot carrier's pose: the rotation by gain x control about the pivot's centre (the
// rotation kin::solve places the pivot with)
ScenePose carrier_scene_pose(const kin::Mechanism& mech, const std::vector<double>& controls, const ExtraBody& e) {
  const kin::Node& node = mech.nodes[static_cast<std::size_t>(e.node)];
  const double a = node.pivot_gain * controls[static_cast<std::size_t>(node.pivot_control)];
  const double co = std::cos(a), si = std::sin(a);
  const Eigen::Vector2d o = node.pivot_about;
  return {o.x() - (co * o.x() - si * o.y()), o.y() - (si * o.x() + co * o.y()), a};
}

// the contact's parameter on one side for the swept extent (SceneLayout::swept)
bool swept_parameter(const kin::Mechanism& mech, const kin::Workspace& ws, const kin::Connection& c, int side,
                     double& u) {
  const kin::Surface& s = side == 0 ? c.surface_a : c.surface_b;
  const int node = side == 0 ? c.node_a : c.node_b;
  if (s.kind != kin::SurfaceKind::point) {
    u = ws.values()[static_cast<std::size_t>(s.variable)];
    return true;
  }
  if (!mech.nodes[static_cast<std::size_t>(node)].ground) return false;
  const kin::ContactState& cs = ws.contacts[static_cast<std::size_t>(&c - mech.connections.data())];
  const double lx = side == 0 ? cs.local_a_x : cs.local_b_x, ly = side == 0 ? cs.local_a_y : cs.local_b_y;
  u = std::atan2(ly - s.origin.y(), lx - s.origin.x());
  return true;
}

// the output node's lift as `camopt kinematics` writes it (kin::sweep's value, less the
// rest position): mm, or deg for a rotating output
double csv_lift(const kin::Mechanism& mech, const kin::Workspace& ws) {
  const kin::Node& out = mech.nodes[static_cast<std::size_t>(mech.output_node)];
  const std::size_t v = static_cast<std::size_t>(out.first_variable);
  if (!mech.variables[v].is_angle) return ws.vars[v].c[0] - out.rest;
  return ws.vars[v].c[0] * (1.0 / rad_per_deg) - out.rest * 180.0 / pi;
}

// every buffer of one position, sized before the solve loop
void reserve_position(std::size_t frames, std::size_t bodies, std::size_t contacts, ScenePosition& p) {
  p.cam_deg.reserve(frames);
  p.lift_mm.reserve(frames);
  p.pose.assign(bodies, {});
  for (auto& b : p.pose) b.reserve(3 * frames);
  p.contact.assign(contacts, {});
  for (auto& c : p.contact) c.reserve(4 * frames);
}

// one control position's frames
void solve_position(const kin::Mechanism& mech, const std::vector<double>& controls, const std::vector<double>& driver,
                    SceneLayout& layout, ScenePosition& out) {
  kin::Workspace ws(mech);
  ws.set_controls(controls);
  kin::Request request;
  request.derivative_order = 1;  // the contacts' points and normals need first-order rates
  request.contacts = true;
  const double unit = mech.driver_is_angle() ? rad_per_deg : 1.0;  // driver deg -> rad
  const std::size_t nodes = mech.nodes.size();
  for (double d : driver) {
    if (Status st = kin::solve(mech, ws, d * unit, request); !st.ok()) {
      if (!mech.controls.empty()) st.where += ", control " + mech.controls[0].name + " = " + format_value(controls[0], 12);
      throw NumericalError(st);
    }
    out.cam_deg.push_back(d);
    out.lift_mm.push_back(csv_lift(mech, ws));
    // every body's pose: the nodes, then link bars and pivot carriers
    for (std::size_t b = 0; b < out.pose.size(); ++b) {
      ScenePose p;
      if (b < nodes) {
        p = node_scene_pose(mech, ws, static_cast<int>(b));
      } else {
        const ExtraBody& e = layout.extras[b - nodes];
        p = e.kind == ExtraBody::Kind::link ? link_scene_pose(mech, ws, e) : carrier_scene_pose(mech, controls, e);
      }
      std::vector<double>& pose = out.pose[b];
      if (b >= nodes && !pose.empty())  // a bar's angle continuous from frame to frame
        p.angle += 2 * pi * std::round((pose.back() - p.angle) / (2 * pi));
      pose.insert(pose.end(), {p.tx, p.ty, p.angle});
    }
    // every contact's point and unit normal (from a into b), and its swept parameters
    std::size_t k = 0;
    for (const kin::Connection& c : mech.connections) {
      if (c.kind != ConnectionKind::contact) continue;
      const kin::ContactState& cs = ws.contacts[static_cast<std::size_t>(&c - mech.connections.data())];
      std::vector<double>& contact = out.contact[k++];
      contact.insert(contact.end(), {cs.x, cs.y, cs.normal_x, cs.normal_y});
      for (int side = 0; side < 2; ++side) {
        double u = 0.0;
        if (swept_parameter(mech, ws, c, side, u))
          layout.swept[static_cast<std::size_t>(&c - mech.connections.data())][static_cast<std::size_t>(side)].push_back(u);
      }
    }
  }
}

}  // namespace

void solve_frames(const kin::Mechanism& mech, const std::vector<std::vector<double>>& controls,
                  const std::vector<double>& driver, SceneLayout& layout, Scene& scene) {
  const std::size_t frames = driver.size() * controls.size();
  for (auto& sides : layout.swept)
    for (auto& s : sides) s.reserve(frames);
  scene.positions.resize(controls.size());
  for (std::size_t p = 0; p < controls.size(); ++p) {
    ScenePosition& pos = scene.positions[p];
    pos.control = controls[p].empty() ? 0.0 : controls[p][0];
    reserve_position(driver.size(), scene.bodies.size(), scene.contacts.size(), pos);
    solve_position(mech, controls[p], driver, layout, pos);
  }
}

}  // namespace camopt::report::detail
