#include "camopt/kinematics/mechanism.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/contact_assembly.hpp"

namespace camopt::kin {

namespace {

Eigen::Vector2d vec(const Vec2& v) { return {v[0], v[1]}; }

[[noreturn]] void fail(const SourceRef& where, const std::string& message) { throw InputError(where, message); }

// which variables each equation touches
std::vector<int> connection_variables(const Mechanism& m, const Connection& c) {
  std::vector<int> vars;
  auto add_node = [&](int n) {
    const Node& node = m.nodes[n];
    for (int k = 0; k < node.dof; ++k) vars.push_back(node.first_variable + k);
  };
  add_node(c.node_a);
  add_node(c.node_b);
  if (c.kind == ConnectionKind::contact) {
    if (c.surface_a.variable >= 0) vars.push_back(c.surface_a.variable);
    if (c.surface_b.variable >= 0) vars.push_back(c.surface_b.variable);
  }
  return vars;
}

Surface build_surface(Mechanism& m, const SurfaceSpec& s, const std::string& conn_name,
                      const std::map<std::string, int>& profile_index, int node, const char* side) {
  Surface out;
  out.node = node;
  switch (s.shape) {
    case SurfaceShape::profile: {
      auto it = profile_index.find(s.profile);
      if (it == profile_index.end()) fail(s.where, "unknown profile '" + s.profile + "'");
      const CamProfile& p = m.profiles[it->second];
      out.source_profile = it->second;
      const double co = std::cos(s.orientation_deg * rad_per_deg), so = std::sin(s.orientation_deg * rad_per_deg);
      if (p.is_disc()) {
        // a disc (circle or eccentric) is an exact circle surface
        out.kind = SurfaceKind::point;
        out.origin = vec(s.origin_mm) + Eigen::Vector2d(co, so) * p.disc_center_x_mm();
        out.offset = p.disc_radius_mm();
      } else {
        out.kind = SurfaceKind::curve;
        out.profile = it->second;
        out.origin = vec(s.origin_mm);
        out.cos_orient = co;
        out.sin_orient = so;
      }
      break;
    }
    case SurfaceShape::circle:
      if (!(s.radius_mm > 0)) fail(s.where, "radius_mm must be > 0");
      out.kind = SurfaceKind::point;
      out.origin = vec(s.origin_mm);
      out.offset = s.concave ? -s.radius_mm : s.radius_mm;
      out.roller = s.roller;
      break;
    case SurfaceShape::line: {
      const Eigen::Vector2d n = vec(s.normal);
      if (!(n.norm() > 0)) fail(s.where, "normal must be a non-zero vector");
      out.kind = SurfaceKind::line;
      out.origin = vec(s.origin_mm);
      out.normal = n.normalized();
      break;
    }
  }
  if (out.kind != SurfaceKind::point) {
    out.variable = static_cast<int>(m.variables.size());
    m.variables.push_back({conn_name + ".u_" + side, -1, true});
  }
  return out;
}

// maximum bipartite matching of equations to unknown variables (augmenting paths)
struct Matching {
  std::vector<int> var_of_eq, eq_of_var;
};

Matching match(const std::vector<std::vector<int>>& eq_vars, int var_count, const std::vector<bool>& known) {
  Matching mt;
  mt.var_of_eq.assign(eq_vars.size(), -1);
  mt.eq_of_var.assign(var_count, -1);
  std::vector<int> seen(var_count, -1);
  std::function<bool(int, int)> augment = [&](int e, int stamp) {
    for (int v : eq_vars[e]) {
      if (known[v] || seen[v] == stamp) continue;
      seen[v] = stamp;
      if (mt.eq_of_var[v] < 0 || augment(mt.eq_of_var[v], stamp)) {
        mt.eq_of_var[v] = e;
        mt.var_of_eq[e] = v;
        return true;
      }
    }
    return false;
  };
  for (int e = 0; e < static_cast<int>(eq_vars.size()); ++e) augment(e, e);
  return mt;
}

}  // namespace

int Mechanism::node_index(const std::string& node_name) const {
  for (int i = 0; i < static_cast<int>(nodes.size()); ++i)
    if (nodes[i].name == node_name) return i;
  return -1;
}

namespace {

// what compile() builds up before the plan: the name indexes and the extents of the
// features (for Mechanism::length_scale)
struct CompileState {
  const DesignSpec& spec;
  Mechanism& m;
  std::map<std::string, int> control_index, profile_index;
  std::vector<double> extent;  // distances of pivots, pins and surfaces from the origin [mm]

  int control_of(const std::string& name, const SourceRef& where) const {
    auto it = control_index.find(name);
    if (it == control_index.end()) fail(where, "unknown control '" + name + "'");
    return it->second;
  }
  int node_of(const std::string& name, const SourceRef& where) const {
    const int i = m.node_index(name);
    if (i < 0) fail(where, "unknown node '" + name + "'");
    return i;
  }
};

void add_controls(CompileState& s) {
  for (const auto& c : s.spec.controls) {
    if (s.control_index.count(c.name)) fail(c.where, "duplicate control '" + c.name + "'");
    s.control_index[c.name] = static_cast<int>(s.m.controls.size());
    s.m.controls.push_back({c.name, c.unit != "mm", c.min, c.max, c.default_value});
  }
}

// one node from its spec, with its variables: one for a rotational [rad] or translational
// [mm] node, three (x, y [mm], phi [rad]) for a floating one
Node build_node(CompileState& s, const NodeSpec& ns) {
  Mechanism& m = s.m;
  Node n;
  n.name = ns.name;
  n.kind = ns.kind;
  n.where = ns.where;
  n.first_variable = static_cast<int>(m.variables.size());
  switch (ns.kind) {
    case NodeKind::rotational:
      n.pivot = vec(ns.pivot_mm);
      n.rest = ns.rest * rad_per_deg;
      if (ns.pivot_motion) {
        n.pivot_control = s.control_of(ns.pivot_motion->control, ns.pivot_motion->where);
        n.pivot_about = vec(ns.pivot_motion->about_mm);
        n.pivot_gain = ns.pivot_motion->gain * rad_per_deg;
      }
      m.variables.push_back({ns.name, static_cast<int>(m.nodes.size()), true});
      s.extent.push_back(n.pivot.norm());
      break;
    case NodeKind::translational: {
      const Eigen::Vector2d d = vec(ns.direction);
      if (!(d.norm() > 0)) fail(ns.where, "node '" + ns.name + "': direction must be a non-zero vector");
      n.direction = d.normalized();
      n.pivot = vec(ns.origin_mm);
      n.rest = ns.rest;
      m.variables.push_back({ns.name, static_cast<int>(m.nodes.size()), false});
      s.extent.push_back(n.pivot.norm());
      break;
    }
    case NodeKind::floating:
      n.dof = 3;
      m.variables.push_back({ns.name + ".x", static_cast<int>(m.nodes.size()), false});
      m.variables.push_back({ns.name + ".y", static_cast<int>(m.nodes.size()), false});
      m.variables.push_back({ns.name + ".phi", static_cast<int>(m.nodes.size()), true});
      break;
  }
  if (ns.control) {
    if (ns.kind == NodeKind::floating) fail(ns.where, "a floating node cannot be set by a control");
    n.control = s.control_of(*ns.control, ns.where);
  }
  return n;
}

// nodes[0] is the implicit fixed frame "ground", then the spec's nodes in order
void add_nodes(CompileState& s) {
  Node ground;
  ground.name = "ground";
  ground.ground = true;
  ground.dof = 0;
  s.m.nodes.push_back(ground);
  for (const auto& ns : s.spec.nodes) {
    if (ns.name == "ground") fail(ns.where, "the node name 'ground' is reserved for the fixed frame");
    if (s.m.node_index(ns.name) >= 0) fail(ns.where, "duplicate node '" + ns.name + "'");
    s.m.nodes.push_back(build_node(s, ns));
  }
}

void set_driver_and_output(CompileState& s) {
  const DesignSpec& spec = s.spec;
  Mechanism& m = s.m;
  m.driver_node = s.node_of(spec.driver.node, spec.driver.where);
  if (m.nodes[m.driver_node].ground || m.nodes[m.driver_node].kind == NodeKind::floating)
    fail(spec.driver.where, "driver node '" + spec.driver.node + "' must be rotational or translational");
  if (m.nodes[m.driver_node].control >= 0)
    fail(spec.driver.where, "driver node '" + spec.driver.node + "' is also set by a control");
  m.output_node = s.node_of(spec.output_node, spec.driver.where);
  if (m.nodes[m.output_node].ground) fail(spec.driver.where, "output_node cannot be the ground");
  m.driver = {spec.driver.start_deg, spec.driver.stop_deg, spec.driver.step_deg, spec.driver.crank_per_cam};
}

void add_profiles(CompileState& s) {
  for (const auto& ps : s.spec.profiles) {
    if (s.profile_index.count(ps.name)) fail(ps.where, "duplicate profile '" + ps.name + "'");
    s.profile_index[ps.name] = static_cast<int>(s.m.profiles.size());
    s.m.profiles.push_back(CamProfile::build(ps));
  }
}

// a link or a crank-slider: two pins at a fixed distance
void build_link(CompileState& s, const ConnectionSpec& cs, Connection& c) {
  const Mechanism& m = s.m;
  c.node_a = s.node_of(cs.pin_a.node, cs.pin_a.where);
  c.node_b = s.node_of(cs.pin_b.node, cs.pin_b.where);
  c.pin_a = vec(cs.pin_a.point_mm);
  c.pin_b = vec(cs.pin_b.point_mm);
  c.length = cs.length_mm ? *cs.length_mm : (c.pin_b - c.pin_a).norm();
  if (!(c.length > 0)) fail(cs.where, "connection '" + cs.name + "': link length must be > 0");
  if (cs.kind == ConnectionKind::crank_slider) {
    const bool ab =
        m.nodes[c.node_a].kind == NodeKind::rotational && m.nodes[c.node_b].kind == NodeKind::translational;
    const bool ba =
        m.nodes[c.node_b].kind == NodeKind::rotational && m.nodes[c.node_a].kind == NodeKind::translational;
    if (!(ab || ba) || m.nodes[c.node_a].ground || m.nodes[c.node_b].ground)
      fail(cs.where, "connection '" + cs.name + "': crank_slider needs one rotational and one translational node");
  }
  s.extent.push_back(c.pin_a.norm());
  s.extent.push_back(c.pin_b.norm());
}

// a node of the kind a connection needs (`role`: "first", "pinion", ...)
void require_kind(const Mechanism& m, const ConnectionSpec& cs, int n, NodeKind k, const char* role) {
  if (m.nodes[n].ground || m.nodes[n].kind != k) {
    const std::string kind = m.nodes[n].ground ? std::string("ground") : to_string(m.nodes[n].kind);
    fail(cs.where, "connection '" + cs.name + "' (" + to_string(cs.kind) + "): " + role + " node '" +
                       m.nodes[n].name + "' is " + kind + ", must be " + to_string(k));
  }
}

// a gear of constant ratio, or a variable gear whose ratio is tabulated against the first
// gear's angle [deg -> rad]
void build_gear(CompileState& s, const ConnectionSpec& cs, Connection& c) {
  c.node_a = s.node_of(cs.node_a, cs.where);
  c.node_b = s.node_of(cs.node_b, cs.where);
  require_kind(s.m, cs, c.node_a, NodeKind::rotational, "first");
  require_kind(s.m, cs, c.node_b, NodeKind::rotational, "second");
  if (cs.kind == ConnectionKind::gear) {
    if (cs.ratio == 0.0) fail(cs.where, "connection '" + cs.name + "': ratio must be non-zero");
    c.ratio = cs.ratio;
    return;
  }
  if (cs.ratio_input_deg.size() < 3 || cs.ratio_input_deg.size() != cs.ratio_values.size())
    fail(cs.where, "connection '" + cs.name + "': ratio_table needs >= 3 points of equal count");
  std::vector<double> x(cs.ratio_input_deg.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = cs.ratio_input_deg[i] * rad_per_deg;
    if (i > 0 && !(x[i] > x[i - 1]))
      fail(cs.where, "connection '" + cs.name + "': ratio_table.input_deg must be strictly increasing");
    if (cs.ratio_values[i] == 0.0) fail(cs.where, "connection '" + cs.name + "': ratio_table.ratio must be non-zero");
  }
  c.ratio_table = Spline::interpolate(x, cs.ratio_values);
}

void build_rack(CompileState& s, const ConnectionSpec& cs, Connection& c) {
  c.node_a = s.node_of(cs.node_a, cs.where);
  c.node_b = s.node_of(cs.node_b, cs.where);
  require_kind(s.m, cs, c.node_a, NodeKind::rotational, "pinion");
  require_kind(s.m, cs, c.node_b, NodeKind::translational, "rack");
  if (cs.pitch_radius_mm == 0.0) fail(cs.where, "connection '" + cs.name + "': pitch_radius_mm must be non-zero");
  c.pitch_radius = cs.pitch_radius_mm;
}

// a contact between two surfaces: closure plus one tangency equation per surface parameter
void build_contact(CompileState& s, const ConnectionSpec& cs, Connection& c) {
  c.node_a = s.node_of(cs.surface_a.node, cs.surface_a.where);
  c.node_b = s.node_of(cs.surface_b.node, cs.surface_b.where);
  c.surface_a = build_surface(s.m, cs.surface_a, cs.name, s.profile_index, c.node_a, "a");
  c.surface_b = build_surface(s.m, cs.surface_b, cs.name, s.profile_index, c.node_b, "b");
  if (c.surface_a.kind == SurfaceKind::line && c.surface_b.kind == SurfaceKind::line)
    fail(cs.where, "connection '" + cs.name + "': a flat face cannot contact another flat face");
  if (c.surface_a.kind == SurfaceKind::point && c.surface_b.kind == SurfaceKind::point && c.surface_a.offset < 0 &&
      c.surface_b.offset < 0)
    fail(cs.where, "connection '" + cs.name + "': two concave circles cannot touch");
  if (!(cs.lash_mm >= 0)) fail(cs.where, "connection '" + cs.name + "': lash_mm must be >= 0");
  c.lash = cs.lash_mm;
  c.one_sided = cs.lash_mm > 0;
  c.equation_count = 1 + (c.surface_a.variable >= 0) + (c.surface_b.variable >= 0);
  s.extent.push_back(c.surface_a.origin.norm());
  s.extent.push_back(c.surface_b.origin.norm());
}

// every connection with its equations (numbered in order: Connection::first_equation)
void add_connections(CompileState& s) {
  Mechanism& m = s.m;
  std::set<std::string> connection_names;
  for (const auto& cs : s.spec.connections) {
    if (!connection_names.insert(cs.name).second) fail(cs.where, "duplicate connection '" + cs.name + "'");
    Connection c;
    c.name = cs.name;
    c.kind = cs.kind;
    c.where = cs.where;
    c.first_equation = m.equation_count;
    switch (cs.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider: build_link(s, cs, c); break;
      case ConnectionKind::gear:
      case ConnectionKind::variable_gear: build_gear(s, cs, c); break;
      case ConnectionKind::rack_pinion: build_rack(s, cs, c); break;
      case ConnectionKind::contact: build_contact(s, cs, c); break;
    }
    if (c.node_a == c.node_b)
      fail(cs.where, "connection '" + cs.name + "' connects node '" + m.nodes[c.node_a].name + "' to itself");
    m.equation_count += c.equation_count;
    m.connections.push_back(std::move(c));
  }
}

// the largest extent of a pivot, pin, surface or profile [mm], at least 1 mm
void set_length_scale(CompileState& s) {
  for (const auto& p : s.m.profiles) s.extent.push_back(p.max_radius_mm());
  s.m.length_scale = 1.0;
  for (double e : s.extent) s.m.length_scale = std::max(s.m.length_scale, e);
}

// a floating body's reference point: the centroid of its features, for a well-conditioned pose
void set_floating_references(Mechanism& m) {
  for (auto& n : m.nodes) {
    if (n.kind != NodeKind::floating) continue;
    Eigen::Vector2d sum(0, 0);
    int count = 0;
    const int self = static_cast<int>(&n - m.nodes.data());
    for (const auto& c : m.connections) {
      auto add = [&](int node, const Eigen::Vector2d& p) {
        if (node == self) {
          sum += p;
          ++count;
        }
      };
      if (c.kind == ConnectionKind::contact) {
        add(c.node_a, c.surface_a.origin);
        add(c.node_b, c.surface_b.origin);
      } else {
        add(c.node_a, c.pin_a);
        add(c.node_b, c.pin_b);
      }
    }
    if (count > 0) n.reference = sum / count;
  }
}

// the equations matched to the unknowns they solve
struct Assembly {
  std::vector<bool> known;                // per variable: the driver and control-set nodes
  std::vector<std::vector<int>> eq_vars;  // per equation: the variables it touches
  std::vector<int> eq_connection;         // per equation: its connection
  Matching matching;
};

Assembly match_equations(const Mechanism& m) {
  Assembly a;
  const int var_count = static_cast<int>(m.variables.size());
  a.known.assign(var_count, false);
  a.known[m.driver_variable()] = true;
  for (const auto& n : m.nodes)
    if (n.control >= 0) a.known[n.first_variable] = true;
  a.eq_vars.resize(m.equation_count);
  a.eq_connection.resize(m.equation_count);
  for (int ci = 0; ci < static_cast<int>(m.connections.size()); ++ci) {
    const auto& c = m.connections[ci];
    const auto vars = connection_variables(m, c);
    for (int k = 0; k < c.equation_count; ++k) {
      a.eq_vars[c.first_equation + k] = vars;
      a.eq_connection[c.first_equation + k] = ci;
    }
  }
  a.matching = match(a.eq_vars, var_count, a.known);
  return a;
}

// an equation left without an unknown (over-constrained) or an unknown without an
// equation (under-constrained) is an InputError naming them
void check_constrained(const Mechanism& m, const DesignSpec& spec, const Assembly& a) {
  const int var_count = static_cast<int>(m.variables.size());
  std::vector<std::string> unsolved, surplus;
  for (int v = 0; v < var_count; ++v)
    if (!a.known[v] && a.matching.eq_of_var[v] < 0) unsolved.push_back(m.variables[v].name);
  std::set<std::string> surplus_set;
  for (int e = 0; e < m.equation_count; ++e)
    if (a.matching.var_of_eq[e] < 0) surplus_set.insert(m.connections[a.eq_connection[e]].name);
  surplus.assign(surplus_set.begin(), surplus_set.end());
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + ("'" + x + "'");
    return s;
  };
  if (!surplus.empty()) {
    SourceRef where;
    for (const auto& c : m.connections)
      if (c.name == surplus.front()) where = c.where;
    fail(where, "over-constrained: connection(s) " + join(surplus) +
                    " close a loop that leaves no freedom (more equations than unknowns among the nodes they "
                    "connect); remove a connection or free a node");
  }
  if (!unsolved.empty()) {
    SourceRef where = spec.driver.where;
    fail(where, "under-constrained: nothing positions " + join(unsolved) + " when the driver '" + spec.driver.node +
                    "' moves; connect each node to the driver through links, gears or contacts");
  }
}

// the blocks of equations solved together, in solve order: strongly connected components
// (Tarjan) of the graph e -> e' when e uses the variable that e' is matched to
std::vector<std::vector<int>> order_blocks(const Mechanism& m, const Assembly& a) {
  const int ne = m.equation_count;
  std::vector<int> index(ne, -1), low(ne, 0), stack;
  std::vector<bool> on_stack(ne, false);
  int counter = 0;
  std::vector<std::vector<int>> blocks;
  std::function<void(int)> strongconnect = [&](int e) {
    index[e] = low[e] = counter++;
    stack.push_back(e);
    on_stack[e] = true;
    for (int v : a.eq_vars[e]) {
      if (a.known[v]) continue;
      const int f = a.matching.eq_of_var[v];
      if (f == e) continue;
      if (index[f] < 0) {
        strongconnect(f);
        low[e] = std::min(low[e], low[f]);
      } else if (on_stack[f]) {
        low[e] = std::min(low[e], index[f]);
      }
    }
    if (low[e] == index[e]) {
      std::vector<int> block;
      int f;
      do {
        f = stack.back();
        stack.pop_back();
        on_stack[f] = false;
        block.push_back(f);
      } while (f != e);
      std::sort(block.begin(), block.end());
      blocks.push_back(block);
    }
  };
  for (int e = 0; e < ne; ++e)
    if (index[e] < 0) strongconnect(e);
  return blocks;
}

// assembly branch (+1 / -1) of a distance constraint |pin_u - pin_k| = L in the drawing
int distance_branch(const Connection& c, const Node& u, const Eigen::Vector2d& pin_u, const Eigen::Vector2d& pin_k,
                    double L) {
  if (u.kind == NodeKind::rotational) {
    const Eigen::Vector2d d = pin_k - u.pivot, a = pin_u - u.pivot;
    if (a.norm() == 0) fail(c.where, "connection '" + c.name + "': pin lies on the pivot of '" + u.name + "'");
    return d.x() * a.y() - d.y() * a.x() >= 0 ? 1 : -1;
  }
  const Eigen::Vector2d e = pin_u - pin_k;
  const double w = u.direction.dot(e), cc = e.squaredNorm() - L * L;
  const double disc = std::sqrt(std::max(0.0, w * w - cc));
  return std::abs(-w + disc) <= std::abs(-w - disc) ? 1 : -1;
}

// a step of one connection solving one node: the closed form that applies, if any, and its
// assembly branch from the drawing
void choose_closed_form(const Mechanism& m, SolveStep& step) {
  if (step.connections.size() != 1 || step.output_node < 0) return;
  const Connection& c = m.connections[step.connections[0]];
  const int unknown = step.output_node;
  const Node& u = m.nodes[unknown];
  if (c.kind == ConnectionKind::contact) {
    const Surface& su = unknown == c.node_a ? c.surface_a : c.surface_b;
    const Surface& sk = unknown == c.node_a ? c.surface_b : c.surface_a;
    if (su.kind == SurfaceKind::point && sk.kind == SurfaceKind::point && u.dof == 1) {
      step.method = StepMethod::contact_distance_closed_form;
      step.branch = distance_branch(c, u, su.origin, sk.origin, std::abs(su.offset + sk.offset));
    } else if (u.kind == NodeKind::translational &&
               ((su.kind == SurfaceKind::line && sk.kind == SurfaceKind::point) ||
                (su.kind == SurfaceKind::point && sk.kind == SurfaceKind::line))) {
      step.method = StepMethod::contact_line_closed_form;
    }
    return;
  }
  if (step.unknowns.size() != 1) return;
  switch (c.kind) {
    case ConnectionKind::link:
    case ConnectionKind::crank_slider:
      step.method = StepMethod::link_closed_form;
      step.branch = distance_branch(c, u, unknown == c.node_a ? c.pin_a : c.pin_b,
                                    unknown == c.node_a ? c.pin_b : c.pin_a, c.length);
      break;
    case ConnectionKind::gear: step.method = StepMethod::gear_closed_form; break;
    case ConnectionKind::rack_pinion: step.method = StepMethod::rack_closed_form; break;
    case ConnectionKind::variable_gear:
      if (unknown == c.node_b) step.method = StepMethod::variable_gear_closed_form;
      break;
    case ConnectionKind::contact: break;
  }
}

// one plan step from a block of equations: its connections and unknowns, the node it
// solves (single-node steps), its method, and whether a lash contact may hold it at rest
SolveStep make_step(const Mechanism& m, const Assembly& a, const std::vector<int>& block) {
  SolveStep step;
  std::set<int> conns;
  for (int e : block) {
    conns.insert(a.eq_connection[e]);
    step.unknowns.push_back(a.matching.var_of_eq[e]);
  }
  step.connections.assign(conns.begin(), conns.end());
  // every equation of a connection belongs to one block (its params are private to it)
  for (int ci : step.connections)
    if (m.connections[ci].equation_count != static_cast<int>(std::count_if(block.begin(), block.end(), [&](int e) {
          return a.eq_connection[e] == ci;
        })))
      fail(m.connections[ci].where,
           "connection '" + m.connections[ci].name + "' is split between solve blocks; its geometry is degenerate");
  if (static_cast<int>(step.unknowns.size()) > max_block_unknowns) {
    std::string names;
    for (int ci : step.connections) names += (names.empty() ? "'" : ", '") + m.connections[ci].name + "'";
    fail(m.connections[step.connections.front()].where,
         "connections " + names + " form a coupled cluster of " + std::to_string(step.unknowns.size()) +
             " unknowns; at most " + std::to_string(max_block_unknowns) +
             " are solved simultaneously (split the cluster with a closed-form connection)");
  }
  std::vector<int> step_nodes;
  for (int v : step.unknowns)
    if (m.variables[v].node >= 0) step_nodes.push_back(m.variables[v].node);
  std::sort(step_nodes.begin(), step_nodes.end());
  step_nodes.erase(std::unique(step_nodes.begin(), step_nodes.end()), step_nodes.end());
  if (step_nodes.size() == 1 && m.nodes[step_nodes[0]].dof == 1) step.output_node = step_nodes[0];
  choose_closed_form(m, step);
  for (int ci : step.connections) {
    const Connection& c = m.connections[ci];
    if (!c.one_sided) continue;
    if (step.connections.size() != 1 || step.output_node < 0)
      fail(c.where, "connection '" + c.name +
                        "': lash is supported on a contact that alone positions its "
                        "follower, not inside a coupled cluster");
    step.one_sided = true;
  }
  return step;
}

}  // namespace

namespace detail {

Mechanism compile_as_drawn(const DesignSpec& spec) {
  Mechanism m;
  m.name = spec.name;
  m.file = spec.file;
  CompileState s{spec, m, {}, {}, {}};
  // controls, by name
  add_controls(s);
  // nodes and their variables; nodes[0] is the fixed frame
  add_nodes(s);
  // the driver and the output (valve) node
  set_driver_and_output(s);
  // cam profiles
  add_profiles(s);
  // connections and their equations
  add_connections(s);
  // contacts that touch at rest: side b placed so they touch in the drawing
  assemble_mechanism_contacts(spec, m);
  // the mechanism's size for tolerances
  set_length_scale(s);
  // floating bodies' reference points
  set_floating_references(m);
  // assembly analysis: equations matched to unknowns, none left over
  const Assembly assembly = match_equations(m);
  check_constrained(m, spec, assembly);
  // the solve plan: blocks in block-triangular order, each a closed form or a simultaneous solve
  for (const auto& block : order_blocks(m, assembly)) m.plan.push_back(make_step(m, assembly, block));
  return m;
}

}  // namespace detail

Mechanism compile(const DesignSpec& spec) {
  // contacts that touch at rest are solved into a copy of the spec first, so the model is
  // built from the assembled drawing (as from a design file, whose reader solves them)
  if (detail::has_unsolved_contacts(spec)) {
    DesignSpec solved = spec;
    assemble_contacts(solved);
    return detail::compile_as_drawn(solved);
  }
  return detail::compile_as_drawn(spec);
}

std::string describe(const Mechanism& m) {
  std::ostringstream os;
  os << "mechanism '" << m.name << "': " << m.nodes.size() - 1 << " nodes, " << m.connections.size()
     << " connections, " << m.variables.size() << " variables, " << m.equation_count << " equations\n";
  os << "driver: " << m.nodes[m.driver_node].name << "   output (valve): " << m.nodes[m.output_node].name << "\n";
  os << "nodes:\n";
  for (std::size_t i = 1; i < m.nodes.size(); ++i) {
    const Node& n = m.nodes[i];
    os << "  " << n.name << "  " << to_string(n.kind);
    if (n.kind == NodeKind::rotational) os << "  pivot_mm=(" << n.pivot.x() << ", " << n.pivot.y() << ")";
    if (n.kind == NodeKind::translational)
      os << "  origin_mm=(" << n.pivot.x() << ", " << n.pivot.y() << ") direction=(" << n.direction.x() << ", "
         << n.direction.y() << ")";
    if (n.pivot_control >= 0) os << "  pivot moved by control '" << m.controls[n.pivot_control].name << "'";
    if (n.control >= 0) os << "  set by control '" << m.controls[n.control].name << "'";
    if (static_cast<int>(i) == m.driver_node) os << "  [driver]";
    os << "\n";
  }
  if (!m.profiles.empty()) os << "profiles:\n";
  for (const auto& p : m.profiles)
    os << "  " << p.name() << "  base_circle_radius_mm=" << p.base_radius_mm() << "  max_radius_mm=" << p.max_radius_mm()
       << "  max_excess_radius_mm=" << p.max_radius_mm() - p.base_radius_mm() << "\n";
  os << "connections:\n";
  for (const auto& c : m.connections) {
    os << "  " << c.name << "  " << to_string(c.kind) << "  " << m.nodes[c.node_a].name << " - "
       << m.nodes[c.node_b].name;
    if (c.kind == ConnectionKind::link || c.kind == ConnectionKind::crank_slider) os << "  length_mm=" << c.length;
    if (c.kind == ConnectionKind::contact && c.lash > 0) os << "  lash_mm=" << c.lash;
    os << "\n";
  }
  os << "solve order:\n";
  int k = 1;
  for (const auto& s : m.plan) {
    os << "  " << k++ << ". ";
    for (std::size_t i = 0; i < s.connections.size(); ++i) os << (i ? " + " : "") << m.connections[s.connections[i]].name;
    os << " -> ";
    for (std::size_t i = 0; i < s.unknowns.size(); ++i) os << (i ? ", " : "") << m.variables[s.unknowns[i]].name;
    switch (s.method) {
      case StepMethod::link_closed_form: os << "  (closed form, branch " << (s.branch > 0 ? "+" : "-") << ")"; break;
      case StepMethod::gear_closed_form:
      case StepMethod::rack_closed_form:
      case StepMethod::variable_gear_closed_form:
      case StepMethod::contact_line_closed_form: os << "  (closed form)"; break;
      case StepMethod::contact_distance_closed_form:
        os << "  (closed form, centre distance, branch " << (s.branch > 0 ? "+" : "-") << ")";
        break;
      case StepMethod::implicit:
        os << (s.connections.size() > 1 ? "  (coupled cluster, Broyden/Newton)" : "  (implicit, Broyden/Newton)");
        break;
    }
    if (s.one_sided) os << "  [lash: holds at rest while open]";
    os << "\n";
  }
  return os.str();
}

}  // namespace camopt::kin
