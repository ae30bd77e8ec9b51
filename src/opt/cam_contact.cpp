#include "camopt/opt/cam_contact.hpp"

#include <cmath>
#include <sstream>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::opt {

namespace {

using G = Grad3;

struct V {
  G x, y;
};
V operator+(const V& a, const V& b) { return {a.x + b.x, a.y + b.y}; }
V operator-(const V& a, const V& b) { return {a.x - b.x, a.y - b.y}; }
V operator*(const V& a, const G& k) { return {a.x * k, a.y * k}; }
V operator*(const V& a, double k) { return {a.x * k, a.y * k}; }
G dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y; }
G cross(const V& a, const V& b) { return a.x * b.y - a.y * b.x; }
V perp(const V& a) { return {-a.y, a.x}; }  // J a: rotated +90 deg
V constant(const Eigen::Vector2d& v) { return {G(v.x()), G(v.y())}; }

G abs(const G& a) { return a.v < 0.0 ? -a : a; }
// atan2(y, x) with its gradient: d = (x dy - y dx) / (x^2 + y^2)
G atan2(const G& y, const G& x) {
  const double r2 = x.v * x.v + y.v * y.v;
  G out(std::atan2(y.v, x.v));
  for (int k = 0; k < 3; ++k) out.d[k] = r2 > 0.0 ? (x.v * y.d[k] - y.v * x.d[k]) / r2 : 0.0;
  return out;
}
// angle between a normal and a direction of motion, in [0, pi/2]
G angle_between(const V& normal, const V& direction) {
  return atan2(abs(cross(direction, normal)), abs(dot(direction, normal)));
}

std::string fmt(double v) { return format_value(v, 6); }

}  // namespace

struct CamContactModel::Impl {
  kin::Mechanism up, down;
  int cam = -1, follower = -1;
  bool rotational_follower = true;
  Eigen::Vector2d trace_origin{0, 0};  // roller / pad centre or face point, follower drawing [mm]
  Eigen::Vector2d face_normal{0, 1};   // flat: unit normal cam -> follower, drawing
};

struct ContactWorkspace::State {
  State(const kin::Mechanism& up, const kin::Mechanism& down, const std::vector<double>& controls)
      : up_ws(up), down_ws(down) {
    up_ws.set_controls(controls);
    down_ws.set_controls(controls);
  }
  kin::Workspace up_ws, down_ws;
};

ContactWorkspace::ContactWorkspace(std::unique_ptr<State> state) : state_(std::move(state)) {}
ContactWorkspace::ContactWorkspace(ContactWorkspace&&) noexcept = default;
ContactWorkspace& ContactWorkspace::operator=(ContactWorkspace&&) noexcept = default;
ContactWorkspace::~ContactWorkspace() = default;

CamContactModel::CamContactModel(const DesignSpec& spec, std::vector<double> controls, const std::string& cam)
    : impl_(std::make_unique<Impl>()), controls_(std::move(controls)) {
  const synthesis::MechanismCut cut = synthesis::cut_mechanism(spec, cam, spec.output_node);
  impl_->up = kin::compile(cut.upstream);
  impl_->down = kin::compile(cut.downstream);
  if (controls_.empty())
    for (const auto& c : spec.controls) controls_.push_back(c.default_value);
  const auto& conn = spec.connections[static_cast<std::size_t>(cut.connection)];
  const SurfaceSpec& follower = cut.profile_on_a ? conn.surface_b : conn.surface_a;
  connection_ = conn.name;
  follower_node_ = cut.follower_node;
  cam_node_ = cut.cam_node;
  material_cam_ = cut.profile_on_a ? conn.material_a : conn.material_b;
  material_follower_ = cut.profile_on_a ? conn.material_b : conn.material_a;
  width_ = conn.width_mm.value_or(0.0);
  impl_->cam = impl_->up.node_index(cut.cam_node);
  if (impl_->up.nodes[static_cast<std::size_t>(impl_->cam)].kind == NodeKind::floating)
    throw InputError(conn.where, "optimize: the cam '" + cut.cam_node + "' of contact '" + conn.name +
                                     "' is a floating lever; the optimiser needs a rotational cam (use camopt synthesize)");
  impl_->follower = impl_->down.node_index(cut.follower_node);
  const kin::Node& fn = impl_->down.nodes[static_cast<std::size_t>(impl_->follower)];
  if (fn.kind == NodeKind::floating)
    throw InputError(conn.where, "optimize: the follower '" + cut.follower_node + "' of contact '" + conn.name +
                                     "' is a floating body; the optimiser needs a rotational or translational follower");
  impl_->rotational_follower = fn.kind == NodeKind::rotational;
  impl_->trace_origin = {follower.origin_mm[0], follower.origin_mm[1]};
  if (follower.shape == SurfaceShape::circle) {
    shape_ = follower.roller ? FollowerShape::roller : FollowerShape::pad;
    radius_ = follower.radius_mm;
  } else {
    shape_ = FollowerShape::flat;
    half_width_ = follower.half_width_mm.value_or(0.0);
    const double len = std::hypot(follower.normal[0], follower.normal[1]);
    // the face's outward normal points towards the cam: the contact normal is its opposite
    impl_->face_normal = {-follower.normal[0] / len, -follower.normal[1] / len};
  }
}

CamContactModel::~CamContactModel() = default;

ContactWorkspace CamContactModel::make_workspace() const { return make_workspace(controls_); }

ContactWorkspace CamContactModel::make_workspace(const std::vector<double>& controls) const {
  return ContactWorkspace(std::make_unique<ContactWorkspace::State>(impl_->up, impl_->down, controls));
}

Status CamContactModel::evaluate(double cam_rad, const double lift[3], ContactWorkspace& cws,
                                 ContactQuantities& out) const {
  const Impl& m = *impl_;
  ContactWorkspace::State& ws = *cws.state_;
  // cam node motion psi(theta) and its pivot
  Status st = kin::solve(m.up, ws.up_ws, cam_rad, {2, false});
  if (!st.ok()) {
    st.where = "cam " + fmt(cam_rad * 180.0 / pi) + " deg";
    return st;
  }
  const kin::Node& cn = m.up.nodes[static_cast<std::size_t>(m.cam)];
  const double psi1 = ws.up_ws.vars[static_cast<std::size_t>(cn.first_variable)].derivative(1);
  const double psi2 = ws.up_ws.vars[static_cast<std::size_t>(cn.first_variable)].derivative(2);
  const Eigen::Vector2d cam_pivot = ws.up_ws.pivots()[static_cast<std::size_t>(m.cam)];

  // follower coordinate q(L) and dq/dL .. d3q/dL3
  st = kin::solve(m.down, ws.down_ws, lift[0], {3, false});
  if (!st.ok()) {
    st.message = "inverting the valve lift " + fmt(lift[0]) + " mm through '" + follower_node_ + "': " + st.message;
    st.where = "cam " + fmt(cam_rad * 180.0 / pi) + " deg";
    return st;
  }
  const kin::Node& fn = m.down.nodes[static_cast<std::size_t>(m.follower)];
  const auto& qj = ws.down_ws.vars[static_cast<std::size_t>(fn.first_variable)];
  const double q1 = qj.derivative(1), q2 = qj.derivative(2), q3 = qj.derivative(3);

  // (L, L', L'') are the gradient directions
  G L1(lift[1]), L2(lift[2]);
  L1.d = {0.0, 1.0, 0.0};
  L2.d = {0.0, 0.0, 1.0};
  G dq(0.0), Q1(q1), Q2(q2);  // q - q(L0), dq/dL and d2q/dL2 as functions of L
  dq.d = {q1, 0.0, 0.0};
  Q1.d = {q2, 0.0, 0.0};
  Q2.d = {q3, 0.0, 0.0};
  const G qd1 = Q1 * L1;                 // dq/dtheta
  const G qd2 = Q2 * L1 * L1 + Q1 * L2;  // d2q/dtheta2

  // follower trace point g(q) and its q-derivatives (global) [mm]
  const auto pose = kin::node_pose(m.down, m.follower, ws.down_ws.vars.data(), ws.down_ws.pivots().data());
  const auto gp = pose.apply(m.trace_origin.x(), m.trace_origin.y());
  const Eigen::Vector2d g0{gp.x.value(), gp.y.value()};
  const Eigen::Vector2d pivot = ws.down_ws.pivots()[static_cast<std::size_t>(m.follower)];
  auto J = [](const Eigen::Vector2d& a) { return Eigen::Vector2d{-a.y(), a.x()}; };
  Eigen::Vector2d gq0, gqq0, gqqq0;  // d^k g / dq^k at q(L0)
  if (m.rotational_follower) {
    gq0 = J(g0 - pivot);
    gqq0 = -(g0 - pivot);
    gqqq0 = -gq0;
  } else {
    gq0 = fn.direction;
    gqq0.setZero();
    gqqq0.setZero();
  }
  const V g = constant(g0) + constant(gq0) * dq;
  const V gq = constant(gq0) + constant(gqq0) * dq;
  const V gqq = constant(gqq0) + constant(gqqq0) * dq;
  const V w = g - constant(cam_pivot);
  const V w1 = gq * qd1;
  const V w2 = gqq * (qd1 * qd1) + gq * qd2;
  const G rot_rate = m.rotational_follower ? qd1 : G(0.0);  // follower rotation rate [rad/rad]

  using std::sqrt;
  out = {};
  if (shape_ != FollowerShape::flat) {
    const V P1 = w1 - perp(w) * psi1;
    const V P2 = w2 - perp(w) * psi2 - perp(w1) * (2.0 * psi1) - w * (psi1 * psi1);
    const G speed = sqrt(dot(P1, P1));
    if (!(speed.v > 1e-12))
      return {StatusCode::undercut, "the follower centre stands still relative to the cam (no envelope)",
              "cam " + fmt(cam_rad * 180.0 / pi) + " deg"};
    const double s = cross(w, P1).v >= 0.0 ? 1.0 : -1.0;
    const V nu{P1.y * (s / speed), -P1.x * (s / speed)};  // outward normal of the pitch curve, cam -> follower
    out.pitch_curvature = s * cross(P1, P2) / (speed * speed * speed);
    const double r = radius_;
    out.cam_radius = 1.0 / out.pitch_curvature - r;
    out.inverse_radius_sum = 1.0 / (r * (1.0 - r * out.pitch_curvature));
    out.pressure_angle = angle_between(nu, gq);
    out.force_ratio = 1.0 / (Q1 * dot(nu, gq));
    const G u_cam = -s * speed * (1.0 - r * out.pitch_curvature);  // cam surface relative to the contact
    if (shape_ == FollowerShape::roller) {
      out.roller_speed = s * speed / r + psi1 - rot_rate;
      out.entrainment = u_cam;  // perfect rolling: both surfaces at the same speed
    } else {
      // pad: the material points at the contact x = c - r nu
      const V x = g - nu * r;
      const V v_cam = perp(x - constant(cam_pivot)) * psi1;
      const V v_fol = m.rotational_follower ? perp(x - constant(pivot)) * qd1 : constant(gq0) * qd1;
      out.sliding = dot(v_cam - v_fol, perp(nu));
      out.entrainment = u_cam - 0.5 * out.sliding;
    }
    return Status::success();
  }

  // flat face: the contact normal rotates with a rotational follower
  V nu = constant(m.face_normal);
  if (m.rotational_follower) {
    // rotate the drawing normal by the follower angle q (through the pose's rotation)
    const auto nr = pose.rotate(m.face_normal.x(), m.face_normal.y());
    const Eigen::Vector2d n0{nr.x.value(), nr.y.value()};
    nu = constant(n0) + constant(J(n0)) * dq;
  }
  const V nu_q = m.rotational_follower ? perp(nu) : V{G(0.0), G(0.0)};
  const V nu1 = nu_q * qd1;
  const V nu2 = m.rotational_follower ? nu * (-(qd1 * qd1)) + perp(nu) * qd2 : V{G(0.0), G(0.0)};
  const G h = dot(w, nu);
  const G h1 = dot(w1, nu) + dot(w, nu1);
  const G h2 = dot(w2, nu) + 2.0 * dot(w1, nu1) + dot(w, nu2);
  const G b1 = rot_rate - psi1;                                     // d(beta)/dtheta
  const G b2 = (m.rotational_follower ? qd2 : G(0.0)) - psi2;      // d2(beta)/dtheta2
  if (!(std::abs(b1.v) > 1e-12))
    return {StatusCode::undercut, "the flat face does not turn relative to the cam (no envelope)",
            "cam " + fmt(cam_rad * 180.0 / pi) + " deg"};
  const G hb = h1 / b1;
  const G hbb = (h2 * b1 - h1 * b2) / (b1 * b1 * b1);
  out.cam_radius = h + hbb;
  out.inverse_radius_sum = 1.0 / out.cam_radius;
  const V x = constant(cam_pivot) + nu * h + perp(nu) * hb;  // contact point (global) [mm]
  const V dx = m.rotational_follower ? perp(x - constant(pivot)) : constant(gq0);  // follower point velocity per dq
  out.pressure_angle = angle_between(nu, dx);
  out.force_ratio = 1.0 / (Q1 * dot(nu, dx));
  const V v_cam = perp(x - constant(cam_pivot)) * psi1;
  out.sliding = dot(v_cam - dx * qd1, perp(nu));
  out.face_offset = dot(x - g, perp(nu));
  out.entrainment = -(out.cam_radius * b1) - 0.5 * out.sliding;
  return Status::success();
}

}  // namespace camopt::opt
