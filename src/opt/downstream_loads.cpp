#include "camopt/opt/downstream_loads.hpp"

#include <Eigen/Core>
#include <numeric>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::opt {

namespace {

constexpr double kMilli = 1e-3;  // kg mm/s^2 -> N

// connected components of the downstream bodies without connection `skip` (ground joins nothing)
std::vector<int> components(const kin::Mechanism& m, int skip) {
  std::vector<int> parent(m.nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[static_cast<std::size_t>(a)] != a) a = parent[static_cast<std::size_t>(a)];
    return a;
  };
  for (int c = 0; c < static_cast<int>(m.connections.size()); ++c) {
    const kin::Connection& k = m.connections[static_cast<std::size_t>(c)];
    if (c == skip || k.node_a < 0 || k.node_b < 0) continue;
    if (m.nodes[static_cast<std::size_t>(k.node_a)].ground || m.nodes[static_cast<std::size_t>(k.node_b)].ground) continue;
    parent[static_cast<std::size_t>(find(k.node_a))] = find(k.node_b);
  }
  std::vector<int> out(m.nodes.size());
  for (int n = 0; n < static_cast<int>(out.size()); ++n) out[static_cast<std::size_t>(n)] = find(n);
  return out;
}

// sums of one contact's body set
struct Sums {
  double mass = 0, half_mass_rate = 0, half_mass_rate_rate = 0;  // M, N = M'/2, N'
  Grad3 statics, damping_rate;                                 // S + G, D L'
};

}  // namespace

struct DownstreamLoads::Impl {
  kin::Mechanism down;
  double crank_per_cam = 2.0;
  struct Body {
    int node = -1, angle_variable = -1;
    double mass = 0, inertia = 0;
    Eigen::Vector2d cg{0, 0};
  };
  struct SpringLoad {
    int node = -1;
    dynamics::Spring spring;
  };
  struct Gas {
    int node = -1;
    dynamics::GasForce gas;
  };
  std::vector<Body> bodies;
  std::vector<SpringLoad> springs;
  std::vector<Gas> gas;
  std::vector<std::vector<char>> beyond;  // per contact: per downstream node, loads it
};

struct LoadWorkspace::State {
  explicit State(const kin::Mechanism& m) : kin(m) {}
  kin::Workspace kin;
};

LoadWorkspace::LoadWorkspace(std::unique_ptr<State> state) : state_(std::move(state)) {}
LoadWorkspace::LoadWorkspace(LoadWorkspace&&) noexcept = default;
LoadWorkspace& LoadWorkspace::operator=(LoadWorkspace&&) noexcept = default;
LoadWorkspace::~LoadWorkspace() = default;

DownstreamLoads::~DownstreamLoads() = default;

DownstreamLoads::DownstreamLoads(const DesignSpec& design, const std::string& cam_kind) : impl_(std::make_unique<Impl>()) {
  const synthesis::MechanismCut cut = synthesis::cut_mechanism(design, cam_kind, design.output_node);
  Impl& m = *impl_;
  m.down = kin::compile(cut.downstream);
  const kin::Mechanism full = kin::compile(design);
  const dynamics::Model model = dynamics::compile_dynamics(design, full);  // InputError names the missing data
  m.crank_per_cam = model.crank_per_cam;
  auto down_index = [&](int full_node) { return m.down.node_index(full.nodes[static_cast<std::size_t>(full_node)].name); };

  // the moving bodies of the downstream part with their mass properties
  for (int n = 0; n < static_cast<int>(m.down.nodes.size()); ++n) {
    const kin::Node& node = m.down.nodes[static_cast<std::size_t>(n)];
    if (node.ground || node.first_variable < 0) continue;
    const int f = full.node_index(node.name);
    const dynamics::BodyInertia& b = model.bodies[static_cast<std::size_t>(f)];
    Impl::Body body{n, -1, b.mass, b.inertia, b.cg};
    if (node.kind == NodeKind::rotational) body.angle_variable = node.first_variable;
    if (node.kind == NodeKind::floating) body.angle_variable = node.first_variable + 2;
    m.bodies.push_back(body);
  }
  for (const dynamics::Spring& s : model.springs)
    if (const int n = down_index(s.node); n >= 0) {
      m.springs.push_back({n, s});
      springs_.push_back(s.name);
    }
  for (const dynamics::GasForce& g : model.gas_forces)
    if (const int n = down_index(g.node); n >= 0) m.gas.push_back({n, g});

  // the cam contact loads every body; a contact behind it loads the bodies on the valve's
  // side when removing it separates them from the follower
  contacts_.push_back(design.connections[static_cast<std::size_t>(cut.connection)].name);
  m.beyond.emplace_back(m.down.nodes.size(), 1);
  const int follower = m.down.node_index(cut.follower_node), valve = m.down.node_index(design.output_node);
  for (int c = 0; c < static_cast<int>(m.down.connections.size()); ++c) {
    if (m.down.connections[static_cast<std::size_t>(c)].kind != ConnectionKind::contact) continue;
    const std::vector<int> comp = components(m.down, c);
    if (comp[static_cast<std::size_t>(follower)] == comp[static_cast<std::size_t>(valve)]) continue;
    std::vector<char> mask(m.down.nodes.size(), 0);
    for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = comp[n] == comp[static_cast<std::size_t>(valve)] ? 1 : 0;
    contacts_.push_back(m.down.connections[static_cast<std::size_t>(c)].name);
    m.beyond.push_back(std::move(mask));
  }
}

bool DownstreamLoads::carries(std::size_t contact, std::size_t spring) const {
  return impl_->beyond[contact][static_cast<std::size_t>(impl_->springs[spring].node)] != 0;
}

LoadWorkspace DownstreamLoads::make_workspace(const std::vector<double>& controls) const {
  auto state = std::make_unique<LoadWorkspace::State>(impl_->down);
  state->kin.set_controls(controls);
  return LoadWorkspace(std::move(state));
}

Status DownstreamLoads::evaluate(double cam_rad, const double lift[3], LoadWorkspace& lws,
                                 std::vector<ContactLoad>& out) const {
  const Impl& m = *impl_;
  kin::Workspace& ws = lws.state_->kin;
  Status st = kin::solve(m.down, ws, lift[0], {3, false});
  if (!st.ok()) {
    st.message = "the loads at valve lift " + format_value(lift[0], 6) + " mm: " + st.message;
    st.where = "cam " + format_value(cam_rad * deg_per_rad, 6) + " deg";
    return st;
  }
  const double L1 = lift[1], L2 = lift[2];
  const std::size_t nc = m.beyond.size(), ns = m.springs.size();
  std::vector<Sums> sums(nc);
  out.resize(nc);
  for (auto& o : out) o.spring.assign(ns, Grad3(0.0));
  const auto& vars = ws.vars;

  // inertia: M = sum m |cg_L|^2 + I phi_L^2, N = sum m cg_L . cg_LL + I phi_L phi_LL, and N'
  for (const Impl::Body& b : m.bodies) {
    const auto pose = kin::node_pose(m.down, b.node, vars.data(), ws.pivots().data());
    const auto cg = pose.apply(b.cg.x(), b.cg.y());
    const Eigen::Vector2d d1{cg.x.c[1], cg.y.c[1]}, d2{2 * cg.x.c[2], 2 * cg.y.c[2]}, d3{6 * cg.x.c[3], 6 * cg.y.c[3]};
    double p1 = 0, p2 = 0, p3 = 0;
    if (b.angle_variable >= 0) {
      const auto& a = vars[static_cast<std::size_t>(b.angle_variable)];
      p1 = a.c[1];
      p2 = 2 * a.c[2];
      p3 = 6 * a.c[3];
    }
    const double mm = b.mass * d1.dot(d1) + b.inertia * p1 * p1;
    const double nn = b.mass * d1.dot(d2) + b.inertia * p1 * p2;
    const double nl = b.mass * (d2.dot(d2) + d1.dot(d3)) + b.inertia * (p2 * p2 + p1 * p3);
    for (std::size_t c = 0; c < nc; ++c) {
      if (!m.beyond[c][static_cast<std::size_t>(b.node)]) continue;
      sums[c].mass += mm;
      sums[c].half_mass_rate += nn;
      sums[c].half_mass_rate_rate += nl;
    }
  }

  // springs and their dampers: load(x) x' and c x'^2 L', x the spring's travel
  for (std::size_t s = 0; s < ns; ++s) {
    const Impl::SpringLoad& sl = m.springs[s];
    const dynamics::Spring& sp = sl.spring;
    const kin::Node& node = m.down.nodes[static_cast<std::size_t>(sl.node)];
    double x0, x1, x2;
    if (!sp.on_point) {
      const auto& x = vars[static_cast<std::size_t>(node.first_variable)];
      x0 = x.c[0];
      x1 = x.c[1];
      x2 = 2 * x.c[2];
    } else {
      const auto p = kin::node_pose(m.down, sl.node, vars.data(), ws.pivots().data()).apply(sp.point.x(), sp.point.y());
      x0 = sp.direction.x() * (p.x.c[0] - sp.point.x()) + sp.direction.y() * (p.y.c[0] - sp.point.y());
      x1 = sp.direction.x() * p.x.c[1] + sp.direction.y() * p.y.c[1];
      x2 = 2 * (sp.direction.x() * p.x.c[2] + sp.direction.y() * p.y.c[2]);
    }
    const double load = sp.load(x0), k = sp.stiffness(x0);
    Grad3 f(load * x1);
    f.d = {k * x1 * x1 + load * x2, 0.0, 0.0};
    Grad3 damp(sp.damping * x1 * x1 * L1);
    damp.d = {2 * sp.damping * x1 * x2 * L1, sp.damping * x1 * x1, 0.0};
    for (std::size_t c = 0; c < nc; ++c) {
      if (!m.beyond[c][static_cast<std::size_t>(sl.node)]) continue;
      sums[c].statics = sums[c].statics + f;
      sums[c].damping_rate = sums[c].damping_rate + damp;
      out[c].spring[s] = f;
    }
  }

  // gas force against the valve's opening at this crank angle
  const double crank_deg = cam_rad * deg_per_rad * m.crank_per_cam;
  for (const Impl::Gas& g : m.gas) {
    const auto& x = vars[static_cast<std::size_t>(m.down.nodes[static_cast<std::size_t>(g.node)].first_variable)];
    const double f = g.gas.at(crank_deg);
    Grad3 q(f * x.c[1]);
    q.d = {2 * f * x.c[2], 0.0, 0.0};
    for (std::size_t c = 0; c < nc; ++c)
      if (m.beyond[c][static_cast<std::size_t>(g.node)]) sums[c].statics = sums[c].statics + q;
  }

  for (std::size_t c = 0; c < nc; ++c) {
    const Sums& s = sums[c];
    ContactLoad& o = out[c];
    o.statics = s.statics;
    o.damping = s.damping_rate;
    // (M L'' + N L'^2) with M' = 2 N [kg mm/rad^2 -> N per (rad/s)^2]
    o.inertia = Grad3(kMilli * (s.mass * L2 + s.half_mass_rate * L1 * L1));
    o.inertia.d = {kMilli * (2 * s.half_mass_rate * L2 + s.half_mass_rate_rate * L1 * L1),
                   kMilli * 2 * s.half_mass_rate * L1, kMilli * s.mass};
  }
  return Status::success();
}

}  // namespace camopt::opt
