// compile_dynamics: the dynamics data of the design, validated and converted to the units of
// the models (model.hpp); and the force laws of springs and gas forces
#include "camopt/dynamics/model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "camopt/core/units.hpp"

namespace camopt::dynamics {

namespace {

constexpr double kMilli = 1e-3;                    // N s/m -> N s/mm
constexpr double kSteelE = 210e3, kSteelNu = 0.3;  // [N/mm^2], [-] a seat insert without a material

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void require_positive(const SourceRef& where, const std::string& what, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError(where, what + ": value " + num(v) + " must be > 0");
}

// linear interpolation in a strictly increasing table, linear extrapolation from the end segments
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at, double* slope) {
  const std::size_t n = x.size();
  std::size_t i = std::upper_bound(x.begin(), x.end(), at) - x.begin();
  i = std::clamp<std::size_t>(i, 1, n - 1);
  const double s = (y[i] - y[i - 1]) / (x[i] - x[i - 1]);
  if (slope) *slope = s;
  return y[i - 1] + s * (at - x[i - 1]);
}

void require_table(const SourceRef& where, const std::string& what, const std::vector<double>& x,
                   const std::vector<double>& y, std::size_t min_points) {
  if (x.size() < min_points || x.size() != y.size())
    throw InputError(where, what + ": needs at least " + std::to_string(min_points) +
                                " points and arrays of the same length (got " + std::to_string(x.size()) + " and " +
                                std::to_string(y.size()) + ")");
  for (std::size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1]))
      throw InputError(where, what + ": abscissa value " + num(x[i]) + " at index " + std::to_string(i) +
                                  " is not greater than the previous " + num(x[i - 1]));
}

}  // namespace

double Spring::load(double x) const {
  if (table_x.empty()) return preload + rate * x;
  return interpolate(table_x, table_f, x, nullptr);
}

double Spring::stiffness(double x) const {
  if (table_x.empty()) return rate;
  double s = 0.0;
  interpolate(table_x, table_f, x, &s);
  return s;
}

double Spring::energy(double x) const {
  if (table_x.empty()) return preload * x + 0.5 * rate * x * x;
  // piecewise linear law (linear extrapolation): trapezoids from 0 to x
  auto integral_to = [&](double to) {
    // breakpoints strictly between 0 and `to`, then the end
    double sum = 0.0, from = 0.0;
    const double dir = to >= 0 ? 1.0 : -1.0;
    std::vector<double> cuts;
    for (double b : table_x)
      if (b * dir > 0 && b * dir < to * dir) cuts.push_back(b);
    if (dir < 0) std::reverse(cuts.begin(), cuts.end());
    cuts.push_back(to);
    for (double b : cuts) {
      sum += 0.5 * (load(from) + load(b)) * (b - from);
      from = b;
    }
    return sum;
  };
  return integral_to(x);
}

double GasForce::at(double crank_angle_deg) const {
  const double first = crank_deg.front();
  double x = std::fmod(crank_angle_deg - first, period_deg);
  if (x < 0) x += period_deg;
  x += first;
  if (x > crank_deg.back()) return 0.0;
  return interpolate(crank_deg, force, x, nullptr);
}

double contact_modulus(double e_a, double nu_a, double e_b, double nu_b) {
  return 1.0 / ((1.0 - nu_a * nu_a) / e_a + (1.0 - nu_b * nu_b) / e_b);
}

namespace {

// a rotational driver and a positive crank ratio
void compile_driver(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  model.crank_per_cam = spec.driver.crank_per_cam;
  model.driver_start_deg = spec.driver.start_deg;
  require_positive(spec.driver.where, "driver.crank_per_cam", model.crank_per_cam);
  if (!mech.driver_is_angle())
    throw InputError(spec.driver.where, "driver.node: the dynamics models need a rotational driver (node '" +
                                            mech.nodes[mech.driver_node].name + "' is translational)");
}

// mass, inertia and centre of gravity of every node; a moving node needs what its kind needs
void compile_bodies(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  model.bodies.resize(mech.nodes.size());
  for (const NodeSpec& ns : spec.nodes) {
    const int n = mech.node_index(ns.name);
    CAMOPT_ASSERT(n > 0);
    const kin::Node& node = mech.nodes[n];
    BodyInertia& b = model.bodies[n];
    b.cg = node.kind == NodeKind::rotational ? node.pivot : node.kind == NodeKind::translational
                                                                ? Eigen::Vector2d(ns.origin_mm[0], ns.origin_mm[1])
                                                                : node.reference;
    const std::string who = "node '" + ns.name + "'";
    if (ns.mass_kg) require_positive(ns.where, who + ": mass_kg", *ns.mass_kg);
    if (ns.inertia_kg_mm2) require_positive(ns.where, who + ": inertia_kg_mm2", *ns.inertia_kg_mm2);
    b.mass = ns.mass_kg.value_or(0.0);
    b.inertia = ns.inertia_kg_mm2.value_or(0.0);
    if (ns.cg_mm) b.cg = {(*ns.cg_mm)[0], (*ns.cg_mm)[1]};
    const bool moving = n != mech.driver_node && node.control < 0;
    if (!moving) continue;
    auto missing = [&](const char* key, const char* why) {
      throw InputError(ns.where, who + ": " + key + " is required by the rigid dynamics model (" + why + ")");
    };
    switch (node.kind) {
      case NodeKind::translational:
        if (!ns.mass_kg) missing("mass_kg", "a moving translational node");
        break;
      case NodeKind::rotational:
        if (!ns.inertia_kg_mm2) missing("inertia_kg_mm2", "a moving rotational node");
        if (ns.cg_mm && !ns.mass_kg) missing("mass_kg", "a rotational node with cg_mm");
        break;
      case NodeKind::floating:
        if (!ns.mass_kg) missing("mass_kg", "a floating node");
        if (!ns.inertia_kg_mm2) missing("inertia_kg_mm2", "a floating node");
        break;
    }
  }
}

// a compression spring's load law: on a translational node, or pushing a point of a floating one
void compile_compression_law(const kin::Mechanism& mech, const SpringSpec& ss, const std::string& who, Spring& s) {
  const NodeKind kind = mech.nodes[s.node].kind;
  if (kind != NodeKind::translational && kind != NodeKind::floating)
    throw InputError(ss.where, who + ": a compression spring needs a translational or floating node ('" + ss.node +
                                   "' is " + to_string(kind) + ")");
  if (kind == NodeKind::floating) {
    if (!ss.point_mm || !ss.direction)
      throw InputError(ss.where, who + ": on the floating node '" + ss.node +
                                     "' it needs point_mm and direction (the point it pushes and its line)");
    if (ss.surge_masses > 0)
      throw InputError(ss.where, who + ": surge_masses on a floating node's spring is not supported");
    s.on_point = true;
    s.point = {(*ss.point_mm)[0], (*ss.point_mm)[1]};
    s.direction = Eigen::Vector2d((*ss.direction)[0], (*ss.direction)[1]).normalized();
  } else if (ss.point_mm || ss.direction) {
    throw InputError(ss.where, who + ": point_mm and direction are for a spring on a floating node");
  }
  if (!ss.table_displacement_mm.empty() || !ss.table_force_N.empty()) {
    require_table(ss.where, who + ": table", ss.table_displacement_mm, ss.table_force_N, 2);
    for (std::size_t i = 1; i < ss.table_force_N.size(); ++i)
      if (!(ss.table_force_N[i] > ss.table_force_N[i - 1]))
        throw InputError(ss.where, who + ": table.force_N value " + num(ss.table_force_N[i]) + " at index " +
                                       std::to_string(i) + " must be greater than the previous (a spring stiffens)");
    s.table_x = ss.table_displacement_mm;
    s.table_f = ss.table_force_N;
    return;
  }
  require_positive(ss.where, who + ": rate_N_per_mm", ss.rate_N_per_mm);
  if (ss.preload_N < 0) throw InputError(ss.where, who + ": preload_N: value " + num(ss.preload_N) + " must be >= 0");
  s.rate = ss.rate_N_per_mm;
  s.preload = ss.preload_N;
}

// every spring's load law, damper and coil data; a spring's mass puts 1/3 on its node
void compile_springs(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  for (const SpringSpec& ss : spec.springs) {
    Spring s;
    s.name = ss.name;
    s.kind = ss.kind;
    s.node = mech.node_index(ss.node);
    const std::string who = "spring '" + ss.name + "'";
    if (s.node <= 0) throw InputError(ss.where, who + ": node '" + ss.node + "' does not exist");
    if (ss.kind == SpringKind::compression) {
      compile_compression_law(mech, ss, who, s);
    } else {
      const NodeKind kind = mech.nodes[s.node].kind;
      if (kind != NodeKind::rotational)
        throw InputError(ss.where, who + ": a torsion spring needs a rotational node ('" + ss.node + "' is " +
                                       to_string(kind) + ")");
      require_positive(ss.where, who + ": rate_Nmm_per_deg", ss.rate_Nmm_per_deg);
      s.rate = ss.rate_Nmm_per_deg / rad_per_deg;  // [N mm/rad]
      s.preload = ss.preload_Nmm;
    }
    if (ss.damping_N_s_per_m) s.damping = *ss.damping_N_s_per_m * kMilli;  // [N s/mm]
    if (ss.mass_kg) {
      require_positive(ss.where, who + ": mass_kg", *ss.mass_kg);
      s.mass = *ss.mass_kg;
      model.bodies[s.node].mass += *ss.mass_kg / 3.0;  // effective moving mass of a uniform coil
    }
    s.surge_masses = ss.surge_masses;
    s.coil_damping_ratio = ss.coil_damping_ratio;
    if (ss.coil_damping_N_s_per_m) s.coil_damping = *ss.coil_damping_N_s_per_m * kMilli;  // [N s/mm]
    if (ss.installed_length_mm && ss.solid_length_mm) s.solid_travel = *ss.installed_length_mm - *ss.solid_length_mm;
    model.springs.push_back(std::move(s));
  }
}

// cylinder gas forces on translational nodes, tables against crank angle over one cycle
void compile_gas_forces(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  for (const GasForceSpec& gs : spec.gas_forces) {
    GasForce g;
    g.node = mech.node_index(gs.node);
    if (g.node <= 0 || mech.nodes[g.node].kind != NodeKind::translational)
      throw InputError(gs.where, "gas_force.node: '" + gs.node + "' is not a translational node");
    require_table(gs.where, "gas_force (node '" + gs.node + "')", gs.crank_angle_deg, gs.force_N, 2);
    g.crank_deg = gs.crank_angle_deg;
    g.force = gs.force_N;
    g.period_deg = 360.0 * model.crank_per_cam;
    model.gas_forces.push_back(std::move(g));
  }
}

const MaterialSpec* find_material(const DesignSpec& spec, const std::string& name) {
  for (const MaterialSpec& m : spec.materials)
    if (m.name == name) return &m;
  return nullptr;
}

const ConnectionSpec& connection_spec(const DesignSpec& spec, const std::string& name) {
  const ConnectionSpec* cs = nullptr;
  for (const auto& s : spec.connections)
    if (s.name == name) cs = &s;
  CAMOPT_ASSERT(cs != nullptr);
  return *cs;
}

// E* of a contact with both materials and a width; Johnson, Contact Mechanics, 1985, eq. 4.22
void compile_contact_materials(const DesignSpec& spec, const ConnectionSpec& cs, const std::string& who,
                               ContactData& d) {
  const MaterialSpec* ma = find_material(spec, cs.material_a);
  const MaterialSpec* mb = find_material(spec, cs.material_b);
  if (!cs.material_a.empty() && !ma)
    throw InputError(cs.where, who + ": materials: '" + cs.material_a + "' is not a [[material]]");
  if (!cs.material_b.empty() && !mb)
    throw InputError(cs.where, who + ": materials: '" + cs.material_b + "' is not a [[material]]");
  if (!(ma && mb && cs.width_mm)) return;
  require_positive(cs.where, who + ": width_mm", *cs.width_mm);
  for (const MaterialSpec* m : {ma, mb}) {
    require_positive(m->where, "material '" + m->name + "': youngs_modulus_GPa", m->youngs_modulus_GPa);
    if (!(m->poisson_ratio >= 0.0 && m->poisson_ratio < 0.5))
      throw InputError(m->where, "material '" + m->name + "': poisson_ratio: value " + num(m->poisson_ratio) +
                                     " must be in [0, 0.5)");
  }
  d.has_hertz = true;
  d.width = *cs.width_mm;
  d.e_star = contact_modulus(ma->youngs_modulus_GPa * 1e3, ma->poisson_ratio, mb->youngs_modulus_GPa * 1e3,
                             mb->poisson_ratio);
}

// per contact: materials, friction, damping, force law and the node its lash holds; per
// link or gear: its flexible-model stiffness and damping ratio
void compile_connections(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  model.contacts.resize(mech.connections.size());
  model.links.resize(mech.connections.size());
  for (std::size_t ci = 0; ci < mech.connections.size(); ++ci) {
    const kin::Connection& c = mech.connections[ci];
    const ConnectionSpec& cs = connection_spec(spec, c.name);
    ContactData& d = model.contacts[ci];
    d.where = cs.where;
    if (c.kind != ConnectionKind::contact) {
      const bool angular = c.kind == ConnectionKind::gear || c.kind == ConnectionKind::variable_gear;
      LinkCompliance& link = model.links[ci];
      if (angular && cs.stiffness_Nm_per_rad) link.stiffness = *cs.stiffness_Nm_per_rad * 1e3;  // [N mm/rad]
      if (!angular && cs.stiffness_N_per_mm) link.stiffness = *cs.stiffness_N_per_mm;
      link.damping_ratio = cs.damping_ratio;
      continue;
    }
    const std::string who = "connection '" + c.name + "'";
    d.is_contact = true;
    d.two_sided = cs.two_sided;
    d.law = cs.contact_law;
    d.rolling = (c.surface_a.kind == kin::SurfaceKind::point && c.surface_a.roller) ||
                (c.surface_b.kind == kin::SurfaceKind::point && c.surface_b.roller);
    if (cs.friction_coefficient) {
      if (!(*cs.friction_coefficient >= 0))
        throw InputError(cs.where, who + ": friction_coefficient: value " + num(*cs.friction_coefficient) +
                                       " must be >= 0");
      d.friction = *cs.friction_coefficient;
    }
    if (cs.contact_law.damping_N_s_per_m) d.damping = *cs.contact_law.damping_N_s_per_m * kMilli;  // [N s/mm]
    compile_contact_materials(spec, cs, who, d);
    if (c.one_sided)
      for (const kin::SolveStep& step : mech.plan)
        if (step.one_sided && std::find(step.connections.begin(), step.connections.end(), static_cast<int>(ci)) !=
                                  step.connections.end())
          d.held_node = step.output_node;
  }
}

// nodes with an axial or torsional stiffness, in design order
void compile_compliances(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  for (const NodeSpec& ns : spec.nodes) {
    const std::optional<double> stiffness =
        ns.torsional_stiffness_Nm_per_rad ? std::optional<double>(*ns.torsional_stiffness_Nm_per_rad * 1e3)
                                          : ns.axial_stiffness_N_per_mm;  // [N mm/rad] or [N/mm]
    if (!stiffness) continue;
    NodeCompliance e;
    e.node = mech.node_index(ns.name);
    e.stiffness = *stiffness;
    e.damping_ratio = ns.damping_ratio;
    if (ns.damping_N_s_per_m) e.damping = *ns.damping_N_s_per_m * kMilli;    // [N s/mm]
    if (ns.damping_Nm_s_per_rad) e.damping = *ns.damping_Nm_s_per_rad * 1e3;  // [N mm s/rad]
    e.where = ns.where;
    model.compliances.push_back(e);
  }
}

// E* of a seat: the valve's material (its side of a contact) against the insert's
double seat_modulus(const DesignSpec& spec, const std::string& node, const SeatSpec& seat) {
  const MaterialSpec* valve = nullptr;
  for (const ConnectionSpec& c : spec.connections) {
    if (c.kind != ConnectionKind::contact) continue;
    if (c.surface_a.node == node && !c.material_a.empty()) valve = find_material(spec, c.material_a);
    if (c.surface_b.node == node && !c.material_b.empty()) valve = find_material(spec, c.material_b);
    if (valve) break;
  }
  const MaterialSpec* insert = seat.material.empty() ? valve : find_material(spec, seat.material);
  const double ev = valve ? valve->youngs_modulus_GPa * 1e3 : kSteelE, nv = valve ? valve->poisson_ratio : kSteelNu;
  const double ei = insert ? insert->youngs_modulus_GPa * 1e3 : kSteelE, ni = insert ? insert->poisson_ratio : kSteelNu;
  return contact_modulus(ev, nv, ei, ni);
}

// the seat of the output node (a translational valve) and of every node with a seat table
void compile_seats(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  for (int n = 0; n < static_cast<int>(mech.nodes.size()); ++n) {
    const kin::Node& node = mech.nodes[n];
    if (node.kind != NodeKind::translational || n == mech.driver_node) continue;
    const NodeSpec* ns = nullptr;
    for (const NodeSpec& x : spec.nodes)
      if (x.name == node.name) ns = &x;
    CAMOPT_ASSERT(ns != nullptr);
    const SeatSpec& sp = ns->seat;
    if (!sp.enabled || (n != mech.output_node && !sp.given)) continue;
    SeatData seat;
    seat.node = n;
    seat.given = sp.given;
    seat.diameter = sp.diameter_mm;
    seat.angle_deg = sp.angle_deg;
    seat.width = sp.width_mm;
    seat.crown_radius = sp.crown_radius_mm;
    seat.e_star = seat_modulus(spec, node.name, sp);
    seat.law = sp.law;
    seat.seat_where = sp.where;
    seat.node_where = ns->where;
    model.seats.push_back(seat);
  }
}

// free node variables (not the driver, not set by a control): the rows of the force balance
void compile_free_rows(const kin::Mechanism& mech, Model& model) {
  model.row_of_variable.assign(mech.variables.size(), -1);
  for (std::size_t n = 1; n < mech.nodes.size(); ++n) {
    const kin::Node& node = mech.nodes[n];
    if (static_cast<int>(n) == mech.driver_node || node.control >= 0 || node.first_variable < 0) continue;
    for (int k = 0; k < node.dof; ++k) {
      model.row_of_variable[node.first_variable + k] = static_cast<int>(model.free_variables.size());
      model.free_variables.push_back(node.first_variable + k);
    }
  }
  if (model.free_variables.size() != mech.connections.size())
    throw InputError(mech.file + ": the rigid dynamics model needs as many connections (" +
                     std::to_string(mech.connections.size()) + ") as free node coordinates (" +
                     std::to_string(model.free_variables.size()) + ")");
}

// InputError unless `mech` was compiled from `spec`: the same name, nodes and connections
void check_compiled_from(const DesignSpec& spec, const kin::Mechanism& mech) {
  bool same = spec.name == mech.name && spec.nodes.size() + 1 == mech.nodes.size() &&
              spec.connections.size() == mech.connections.size();
  for (std::size_t i = 0; same && i < spec.nodes.size(); ++i) same = spec.nodes[i].name == mech.nodes[i + 1].name;
  for (std::size_t i = 0; same && i < spec.connections.size(); ++i)
    same = spec.connections[i].name == mech.connections[i].name;
  if (!same)
    throw InputError("compile_dynamics: the design spec '" + spec.name + "' is not the one mechanism '" + mech.name +
                     "' was compiled from (rule: the same nodes and connections, in order)");
}

}  // namespace

namespace {

// every [[hla]] compiled, on a node of the mechanism
void compile_hlas(const DesignSpec& spec, const kin::Mechanism& mech, Model& model) {
  for (const HlaSpec& h : spec.hlas) {
    const int node = mech.node_index(h.node);
    if (node < 0) throw InputError(h.at("node"), "hla '" + h.name + "': no node named '" + h.node + "'");
    model.hlas.push_back({compile_hla(h), node});
  }
}

}  // namespace

Model compile_dynamics(const DesignSpec& spec, const kin::Mechanism& mech) {
  Model model;
  // the spec is the one the mechanism was compiled from
  check_compiled_from(spec, mech);
  // driver: rotational, with its crank ratio
  compile_driver(spec, mech, model);
  // bodies: mass, inertia and centre of gravity per node
  compile_bodies(spec, mech, model);
  // springs: load laws, dampers, coil masses (1/3 on the node)
  compile_springs(spec, mech, model);
  // gas forces against crank angle
  compile_gas_forces(spec, mech, model);
  // contacts (materials, friction, force laws, lash) and links (compliance)
  compile_connections(spec, mech, model);
  // compliant nodes and valve seats of the flexible model
  compile_compliances(spec, mech, model);
  compile_seats(spec, mech, model);
  // the oil of the EHL film, the hydraulic lash adjusters
  model.oil = spec.oil;
  compile_hlas(spec, mech, model);
  // the rows of the force balance
  compile_free_rows(mech, model);
  return model;
}

}  // namespace camopt::dynamics
