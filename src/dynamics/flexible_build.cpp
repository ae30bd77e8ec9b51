// the flexible model's build: extended coordinates, force laws, seats, damping and the static
// start (flexible_system.hpp)
#include <Eigen/Eigenvalues>
#include <algorithm>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

namespace {

constexpr double kMilli = 1e-3;      // kg mm/s^2 -> N; N s/m -> N s/mm
constexpr double kSeatReach = 0.01;  // [mm] a seated valve's kinematic rest within this of its seat

// the connections that solve a node in the kinematic plan (its drive side)
std::vector<int> drive_side(const kin::Mechanism& mech, int node) {
  const int v = mech.nodes[node].first_variable;
  for (const kin::SolveStep& step : mech.plan)
    if (std::find(step.unknowns.begin(), step.unknowns.end(), v) != step.unknowns.end()) {
      std::vector<int> out;
      for (int c : step.connections)
        if (mech.connections[c].node_a == node || mech.connections[c].node_b == node) out.push_back(c);
      return out;
    }
  return {};
}

// a contact or seat law from its design keys; hertz needs length and e_star set by the caller
ForceLaw make_law(const ContactLawSpec& keys, const FlexibleOptions& opt, const std::string& who, const SourceRef& where) {
  ForceLaw law;
  law.law = keys.law;
  law.damping_law = keys.damping_law;
  law.scale = opt.contact_stiffness_scale;
  const double alpha_default = hunt_crossley_alpha(keys.restitution.value_or(opt.contact_restitution),
                                                   opt.restitution_speed_m_per_s * 1e3);
  const std::optional<double> c = keys.damping_N_s_per_m ? std::optional<double>(*keys.damping_N_s_per_m * kMilli)
                                                         : std::nullopt;  // [N s/mm]
  if (keys.law == ContactLaw::linear) {
    if (!keys.stiffness_N_per_mm)
      throw InputError(where, who + ": law = \"linear\" needs stiffness_N_per_mm");
    law.k = *keys.stiffness_N_per_mm;
    law.c = c.value_or(0.0);
    return law;
  }
  // hertz: a design damping c is matched at the reference load (dF/d rate = 1.5 alpha F)
  law.alpha = c ? *c / (1.5 * opt.reference_force) : alpha_default;
  law.c = c ? *c : 1.5 * alpha_default * opt.reference_force;
  return law;
}

// a far end for every compliant node the kinematic plan solves (a prescribed motion does not
// deform the train)
void add_elements(System& s, const Model& model) {
  const kin::Mechanism& mech = s.mech;
  int next = s.R;
  for (const NodeCompliance& nc : model.compliances) {
    const kin::Node& node = mech.nodes[nc.node];
    if (node.kind == NodeKind::floating)
      throw InputError(nc.where, "node '" + node.name +
                                     "': torsional_stiffness_Nm_per_rad on a floating node is not supported by the "
                                     "flexible model (split it into two nodes joined by a connection)");
    if (nc.node == mech.driver_node || node.control >= 0) continue;
    Element e;
    e.node = nc.node;
    e.near = model.row_of_variable[node.first_variable];
    e.far = next++;
    e.k = nc.stiffness;
    e.zeta = nc.damping_ratio.value_or(s.opt.component_damping_ratio);
    if (nc.damping) e.c = *nc.damping, e.damping_given = true;
    s.far_of_row[e.near] = e.far;
    s.elements.push_back(e);
  }
  s.E = static_cast<int>(s.elements.size());
}

// every compression spring on a solved translational node becomes a chain; its end mass goes to the node
void add_chains(System& s, const Model& model) {
  const kin::Mechanism& mech = s.mech;
  std::vector<Spring> kept;
  int next = s.core();
  for (const Spring& sp : model.springs) {
    // torsion springs and springs on floating bodies stay in the path
    if (sp.kind != SpringKind::compression || sp.on_point || mech.nodes[sp.node].control >= 0) {
      kept.push_back(sp);
      continue;
    }
    Chain ch;
    ch.name = sp.name;
    ch.law = sp;
    ch.node = sp.node;
    ch.row = model.row_of_variable[mech.nodes[sp.node].first_variable];
    ch.masses = sp.surge_masses;
    ch.spring_damping = sp.damping;
    const double spring_mass = sp.mass;
    if (ch.masses > 0) {
      // internal masses m/(N+1), half a segment's mass at each end; the rigid model had m/3
      s.flex.bodies[sp.node].mass += spring_mass / (2.0 * (ch.masses + 1)) - spring_mass / 3.0;
      ch.mass = kMilli * spring_mass / (ch.masses + 1);
      ch.first = next;
      next += ch.masses;
      ch.band = static_cast<int>(std::count_if(s.chains.begin(), s.chains.end(), [](const Chain& c) { return c.masses > 0; }));
      // coil-to-coil: a damper between adjacent coil masses, or stiffness-proportional damping
      // giving the first surge mode (fixed-fixed, w1 = pi sqrt(k/m)) the ratio: c = 2 zeta k / w1
      if (sp.coil_damping) {
        ch.coil_damping = *sp.coil_damping / (ch.masses + 1.0);
      } else {
        const double rate = sp.stiffness(0.0);
        const double w1 = pi * std::sqrt(rate / (kMilli * spring_mass));
        ch.coil_damping = 2.0 * sp.coil_damping_ratio.value_or(s.opt.spring_damping_ratio) * rate / w1;
      }
    }
    ch.segment_damping = ch.spring_damping + ch.coil_damping;
    ch.solid_travel = sp.solid_travel;
    ch.table_index = static_cast<int>(s.chains.size());
    s.chains.push_back(ch);
  }
  s.flex.springs = kept;
  s.N = next;
}

// the model's seats on nodes the kinematic plan solves (a seat under a control is an error)
void add_seats(System& s) {
  const kin::Mechanism& mech = s.mech;
  for (std::size_t i = 0; i < s.flex.seats.size(); ++i) {
    const SeatData& sd = s.flex.seats[i];
    const kin::Node& node = mech.nodes[sd.node];
    const int r = node.control >= 0 ? -1 : s.flex.row_of_variable[node.first_variable];
    if (r < 0) {
      if (sd.given) throw InputError(sd.seat_where, "node '" + node.name + "': seat: a node set by a control has no seat");
      continue;
    }
    Seat st;
    st.node = sd.node;
    st.source = static_cast<int>(i);
    st.near = r;
    st.row = s.far_of_row[r] >= 0 ? s.far_of_row[r] : r;
    st.table_index = static_cast<int>(s.seats.size());
    st.law = make_law(sd.law, s.opt, "node '" + node.name + "': seat", sd.seat_where.line ? sd.seat_where : sd.node_where);
    if (sd.law.law == ContactLaw::hertz) {
      st.law.length = pi * sd.diameter;
      st.law.e_star = sd.e_star;
      st.cos_angle = std::cos(sd.angle_deg * pi / 180.0);
      st.radius = sd.crown_radius;
    }
    st.area = pi * sd.diameter * sd.width;
    s.seats.push_back(st);
  }
}

// contacts: their force laws; links and gears: their stiffness
void set_contact_laws(System& s) {
  const kin::Mechanism& mech = s.mech;
  s.laws.assign(s.C, ForceLaw{});
  s.link_k.assign(s.C, 0.0);
  s.link_c.assign(s.C, 0.0);
  for (int c = 0; c < s.C; ++c) {
    const ContactData& cd = s.flex.contacts[c];
    if (!cd.is_contact) {
      const ConnectionKind kind = mech.connections[c].kind;
      const bool angular = kind == ConnectionKind::gear || kind == ConnectionKind::variable_gear;
      const LinkCompliance& link = s.flex.links[c];
      s.link_k[c] = link.stiffness ? *link.stiffness : angular ? s.opt.link_stiffness * 1e-3 * 1e3 : s.opt.link_stiffness;
      continue;
    }
    const std::string who = "connection '" + mech.connections[c].name + "'";
    if (cd.law.law == ContactLaw::hertz && !cd.has_hertz)
      throw InputError(cd.where, who + ": the flexible model's hertz law needs materials and width_mm "
                                       "(or law = \"linear\" with stiffness_N_per_mm)");
    s.laws[c] = make_law(cd.law, s.opt, who, cd.where);
    s.laws[c].length = cd.width;
    s.laws[c].two_sided = cd.two_sided;
    s.laws[c].e_star = cd.e_star;
    if (cd.held_node > 0) s.lash.push_back(c);
  }
}

// the seats' opening direction from the path and their reach: a valve opens one way from its seat
void check_seats(System& s) {
  for (Seat& st : s.seats) {
    double lo = 0.0, hi = 0.0, at_lo = 0.0;
    for (std::size_t i = 0; i < s.row_angle.size(); ++i) {
      const double d = s.table[i * s.L.size + s.L.seat + st.table_index];
      if (d < lo) lo = d, at_lo = s.row_angle[i];
      hi = std::max(hi, d);
    }
    double low = lo;
    st.sign = 1.0;
    if (-lo > hi) st.sign = -1.0, low = -hi;
    double rest = 1e300, at_rest = 0.0;  // closest approach to the seat
    for (std::size_t i = 0; i < s.row_angle.size(); ++i) {
      const double d = st.sign * s.table[i * s.L.size + s.L.seat + st.table_index];
      if (d < rest) rest = d, at_rest = s.row_angle[i];
    }
    const std::string name = s.mech.nodes[st.node].name;
    const SeatData& sd = s.flex.seats[st.source];
    const SourceRef& where = sd.given ? sd.seat_where : sd.node_where;
    if (rest > kSeatReach)
      throw InputError(where, "node '" + name + "': seat: the valve never reaches its seat (closest " +
                                  format_number(rest) + " mm at cam " + format_number(at_rest * 180.0 / pi) +
                                  " deg; it must return within " + format_number(kSeatReach) +
                                  " mm of its rest displacement)");
    if (low < -kSeatReach)
      throw InputError(where, "node '" + name + "': seat: the kinematic motion passes " + format_number(-low) +
                                  " mm through the seat at cam " + format_number(at_lo * 180.0 / pi) +
                                  " deg (at most " + format_number(kSeatReach) + " mm)");
  }
}

// first natural frequency [rad/s] of the train at the output's kinematic peak: every contact
// closed at its tangent stiffness under reference_force, links stiff, the springs lumped on
// their nodes (surge masses left out), seats open. 0 when none is positive.
double train_frequency(System& s) {
  std::size_t peak = 0;
  for (std::size_t i = 1; i < s.row_angle.size(); ++i)
    if (std::abs(s.table[i * s.L.size + s.L.out]) > std::abs(s.table[peak * s.L.size + s.L.out])) peak = i;
  for (int k = 0; k < static_cast<int>(s.pieces.size()); ++k)
    if (static_cast<int>(peak) >= s.pieces[k].first && static_cast<int>(peak) < s.pieces[k].first + s.pieces[k].count)
      s.active_piece = k;
  s.evaluated_theta = std::nan("");
  s.evaluate_angle(s.row_angle[peak]);
  const int n = s.core();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < s.R; ++r)
    for (int j = 0; j < s.R; ++j) k(r, j) += s.path[s.L.spring_k + r + s.R * j];
  for (const Element& e : s.elements) {
    k(e.near, e.near) += e.k;
    k(e.far, e.far) += e.k;
    k(e.near, e.far) -= e.k;
    k(e.far, e.near) -= e.k;
  }
  for (int c = 0; c < s.C; ++c) {
    const ContactData& cd = s.flex.contacts[c];
    const ForceLaw& law = s.laws[c];
    const double kc = !cd.is_contact              ? s.link_k[c]
                      : law.law == ContactLaw::linear ? law.k
                                                      : law.scale * line_contact_tangent_stiffness(
                                                                        s.opt.reference_force, law.length, law.e_star,
                                                                        s.reduced_radius(c));
    s.for_gradient(c, [&](int i, double gi, double) {
      s.for_gradient(c, [&](int j, double gj, double) { k(i, j) += kc * gi * gj; });
    });
  }
  for (const Chain& ch : s.chains) k(ch.row, ch.row) += ch.law.stiffness(s.path[s.L.xs + ch.table_index]);
  for (const Plunger& p : s.plungers) k(p.coord, p.coord) += hla_static_stiffness(s, p);
  s.mass_matrix(s.m);
  const Eigen::MatrixXd m = s.m.core;
  s.evaluated_theta = std::nan("");
  s.active_piece = 0;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (k + k.transpose()), m);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) return 0.0;
  return std::sqrt(eig.eigenvalues().minCoeff());
}

// damping of links (a ratio of their local mode) and components (Rayleigh on the train's
// first mode: c = 2 zeta k / w1 gives it the ratio zeta; Clough & Penzien, Dynamics of
// Structures, 2nd ed., sec. 12-5)
void set_damping(System& s) {
  s.evaluated_theta = std::nan("");
  s.evaluate(0.0);
  s.mass_matrix(s.m);
  const Eigen::MatrixXd m_inv = s.m.core.inverse();
  for (int c = 0; c < s.C; ++c) {
    if (s.flex.contacts[c].is_contact) continue;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(s.core());
    s.for_gradient(c, [&](int row, double gn, double) { g(row) += gn; });
    const double inv_mass = g.dot(m_inv * g);
    const double m_c = inv_mass > 0 ? 1.0 / inv_mass : 0.0;
    const double link_ratio = s.flex.links[c].damping_ratio.value_or(s.opt.contact_damping_ratio);
    s.link_c[c] = 2.0 * link_ratio * std::sqrt(s.link_k[c] * m_c);
  }
  const double w1 = train_frequency(s);
  s.train_frequency_hz = w1 / (2.0 * pi);
  s.evaluated_theta = std::nan("");
  s.evaluate(0.0);
  s.mass_matrix(s.m);
  for (Element& e : s.elements) {
    if (e.damping_given) continue;
    // without a train mode: the ratio of the two halves' own mode (reduced mass M/4)
    e.c = w1 > 0.0 ? 2.0 * e.zeta * e.k / w1 : 2.0 * e.zeta * std::sqrt(e.k * 0.5 * s.m.core(e.near, e.near));
  }
}

}  // namespace

namespace {

// connection row maps: the far end of a compliant node takes the connections not on its drive side
void map_rows(System& s) {
  const kin::Mechanism& mech = s.mech;
  s.row_map.assign(s.C, std::vector<int>(s.R));
  for (int c = 0; c < s.C; ++c)
    for (int r = 0; r < s.R; ++r) s.row_map[c][r] = r;
  for (const Element& e : s.elements) {
    const std::vector<int> drive = drive_side(mech, e.node);
    for (int c = 0; c < s.C; ++c) {
      const auto& conn = mech.connections[c];
      if ((conn.node_a == e.node || conn.node_b == e.node) && std::find(drive.begin(), drive.end(), c) == drive.end())
        s.row_map[c][e.near] = e.far;
    }
  }
}

// the buffers of the forces, the structured matrices and the coil masses' inverse
void allocate_work(System& s) {
  s.frozen.assign(s.C, 0);
  s.frozen_force.assign(s.C, 0.0);
  s.hertz_start.assign(s.C, 0.0);
  s.fr.connection.assign(s.C, 0.0);
  s.fr.mu_eff.assign(s.C, 0.0);
  s.fr.friction_power.assign(s.C, 0.0);
  s.fr.seat.assign(s.seats.size(), 0.0);
  s.fr.coil_top.assign(s.chains.size(), 0.0);
  s.fr.coil_base.assign(s.chains.size(), 0.0);
  s.fr.static_load.assign(s.chains.size(), 0.0);
  for (Structured* a : {&s.m, &s.jk, &s.jd}) a->resize(s.core(), s.chains);
  s.inv_coil_mass.resize(s.N - s.core());
  for (const Chain& ch : s.chains)
    for (int j = 0; j < ch.masses; ++j) s.inv_coil_mass(ch.first + j - s.core()) = 1.0 / ch.mass;
}

// root functions: one-sided contacts, seats, and the coil gaps of chains with a solid length
void add_roots(System& s) {
  for (int c = 0; c < s.C; ++c)
    if (s.flex.contacts[c].is_contact && !s.flex.contacts[c].two_sided) s.root_list.push_back({0, c, 0});
  for (int i = 0; i < static_cast<int>(s.seats.size()); ++i) s.root_list.push_back({1, i, 0});
  add_hla_roots(s);
  for (std::size_t i = 0; i < s.chains.size(); ++i)
    if (s.chains[i].solid_travel >= 0)
      for (int j = 1; j <= s.chains[i].masses + 1; ++j) s.root_list.push_back({2, static_cast<int>(i), j});
}

// the output node's extended row (the far end of a compliant valve)
void set_output(System& s) {
  const kin::Node& on = s.mech.nodes[s.mech.output_node];
  s.output_angle = on.kind != NodeKind::translational;
  if (on.first_variable >= 0 && s.flex.row_of_variable[on.first_variable] >= 0) {
    const int r = s.flex.row_of_variable[on.first_variable];
    s.output_row = s.far_of_row[r] >= 0 ? s.far_of_row[r] : r;
  }
}

}  // namespace

Status build_system(System& s, const Model& model, const std::vector<double>& controls, double theta_first) {
  s.flex = model;
  s.R = static_cast<int>(model.free_variables.size());
  s.C = static_cast<int>(s.mech.connections.size());
  CAMOPT_ASSERT(s.R == s.C);
  s.far_of_row.assign(s.R, -1);
  // the extended coordinates: far ends of compliant nodes, then the spring chains' masses
  add_elements(s, model);
  add_plungers(s, model);
  add_chains(s, model);
  // the valve seats and the contacts' force laws
  add_seats(s);
  set_contact_laws(s);
  map_rows(s);
  // the kinematic path over one revolution, and the seats checked against it
  s.L = Layout(s.R, s.C, static_cast<int>(s.chains.size()), static_cast<int>(s.seats.size()), s.P);
  const Status st = tabulate_path(s, controls, theta_first);
  if (!st.ok()) return st;
  check_seats(s);
  s.theta0 = theta_first;
  s.hyd = Eigen::VectorXd::Zero(s.H);
  if (s.H > 0) initial_hydraulics(s, 0.0, s.hyd.data());
  allocate_work(s);
  // damping of links and components from the train's first mode
  set_damping(s);
  // root functions and the output row
  add_roots(s);
  set_output(s);
  s.acc.setZero(s.N);
  s.active_piece = s.piece_of(theta_first);
  s.evaluated_theta = std::nan("");
  s.factored_theta = std::nan("");
  return Status::success();
}

namespace {

// the approach of a seat under an axial load [mm]
double seat_approach(const Seat& st, double load) {
  if (!(load > 0.0)) return 0.0;
  if (st.law.law == ContactLaw::linear) return load / st.law.k;
  const double normal = load / st.cos_angle;
  return line_contact_approach(normal / st.law.scale, st.law.length, st.law.e_star, st.radius) / st.cos_angle;
}
double contact_approach(const System& s, int c, double load) {
  if (s.laws[c].two_sided && load < 0.0) return -contact_approach(s, c, -load);  // the slot's other wall
  if (!(load > 0.0)) return 0.0;
  const ForceLaw& law = s.laws[c];
  if (law.law == ContactLaw::linear) return load / law.k;
  return line_contact_approach(load / law.scale, law.length, law.e_star, s.reduced_radius(c));
}

// every connection carries its mode (a) force: contacts at the approach of that force, a
// contact open behind its lash puts its held node on its seat at the mode (a) seat reaction
Eigen::VectorXd initial_deviation(System& s, const Eigen::VectorXd& lambda0, const Eigen::VectorXd& seat0,
                                  const std::vector<char>& open0) {
  s.evaluate(0.0);
  const int nc = s.core();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nc, nc);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nc);
  const double w2 = s.omega * s.omega;
  std::vector<int> seat_of_contact(s.C, -1);
  int eq = 0;
  for (int c = 0; c < s.C; ++c, ++eq) {
    if (open0[c]) {
      const int held = s.flex.contacts[c].held_node;
      for (int i = 0; i < static_cast<int>(s.seats.size()); ++i)
        if (s.seats[i].node == held) seat_of_contact[c] = i;
      if (seat_of_contact[c] >= 0) {  // on the seat: displacement + x = -sign approach
        const Seat& st = s.seats[seat_of_contact[c]];
        a(eq, st.row) = 1.0;
        b(eq) = -st.sign * seat_approach(st, std::abs(seat0(c))) - s.path[s.L.seat + st.table_index];
      } else {  // held at its kinematic rest
        a(eq, s.flex.row_of_variable[s.mech.nodes[held].first_variable]) = 1.0;
      }
      continue;
    }
    s.for_gradient(c, [&](int row, double gn, double) { a(eq, row) += gn; });
    if (s.flex.contacts[c].is_contact) b(eq) = -s.path[s.L.gap + c] - contact_approach(s, c, lambda0(c));
    else b(eq) = -lambda0(c) / s.link_k[c];
  }
  for (const Element& e : s.elements) {
    // far-end balance: the element carries half the inertia, the gas and the far connections
    double load = -0.5 * s.path[s.L.inertia + e.near] * w2 - s.path[s.L.gas + e.near];
    for (int c = 0; c < s.C; ++c) {
      if (open0[c]) {
        if (seat_of_contact[c] >= 0 && s.seats[seat_of_contact[c]].row == e.far)
          load += s.seats[seat_of_contact[c]].sign * std::abs(seat0(c));
        continue;
      }
      if (s.row_map[c][e.near] == e.far) load += lambda0(c) * s.gn(e.near, c);
    }
    a(eq, e.far) = e.k;  // k (x_far - x_near) = load
    a(eq, e.near) = -e.k;
    b(eq) = load;
    ++eq;
  }
  // plungers start where the kinematics has them (the static polish then balances the HLA)
  for (const Plunger& p : s.plungers) a(eq++, p.coord) = 1.0;
  CAMOPT_ASSERT(eq == nc);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(s.N);
  x.head(nc) = a.partialPivLu().solve(b);
  for (const Chain& ch : s.chains)  // a uniform compression
    for (int j = 1; j <= ch.masses; ++j)
      x(ch.first + j - 1) = j / (ch.masses + 1.0) * (s.path[s.L.xs + ch.table_index] + x(ch.row));
  return x;
}

}  // namespace

double polish_static(System& s, Eigen::VectorXd& x, const Eigen::VectorXd& v, int iterations) {
  s.forces(x.data(), v.data());
  double residual = s.fr.f.norm();
  StructuredLU lu;
  lu.a.resize(s.core(), s.chains);
  Eigen::VectorXd dx(s.N), trial(s.N);
  for (int it = 0; it < iterations && residual > 0.0; ++it) {
    s.newton_matrices(x.data(), v.data(), s.jk, s.jd, true);
    lu.a.copy_from(s.jk);
    if (!lu.factor(s.chains)) break;
    dx = s.fr.f;
    lu.solve(dx.data());
    if (!dx.allFinite()) break;
    // backtracking on the force residual
    double step = 1.0, next = residual;
    for (int half = 0; half < 8; ++half, step *= 0.5) {
      trial = x + step * dx;
      s.forces(trial.data(), v.data());
      next = s.fr.f.norm();
      if (next < residual) break;
    }
    if (!(next < residual)) break;
    x = trial;
    residual = next;
  }
  s.forces(x.data(), v.data());
  return s.fr.f.norm();
}

Status static_start(System& s, const Model& model, const std::vector<double>& controls, double theta,
                    Eigen::VectorXd& x0, Eigen::VectorXd& v0) {
  {
    const Status st = build_system(s, model, controls, theta);
    if (!st.ok()) return st;
  }
  // mode (a) of the full model at the first angle
  RigidWorkspace ws0(s.mech, model);
  ws0.kin.set_controls(controls);
  const Status st0 = solve_rigid(s.mech, model, ws0, theta);
  if (!st0.ok()) return st0;
  Eigen::VectorXd lambda0 = Eigen::VectorXd::Zero(s.C), seat0 = Eigen::VectorXd::Zero(s.C);
  std::vector<char> open0(s.C, 0);

  for (int c = 0; c < s.C; ++c) {
    for (int j = 0; j < ws0.cases(); ++j) {
      lambda0(c) += ws0.case_weight(j, s.omega) * ws0.force(c, j);
      seat0(c) += ws0.case_weight(j, s.omega) * ws0.seat(c, j);
    }
    open0[c] = s.flex.contacts[c].is_contact && ws0.kin.contacts[c].open;
  }
  x0 = initial_deviation(s, lambda0, seat0, open0);
  v0 = Eigen::VectorXd::Zero(s.N);
  for (const Chain& ch : s.chains)
    for (int j = 1; j <= ch.masses; ++j)
      v0(ch.first + j - 1) = j / (ch.masses + 1.0) * s.path[s.L.xs1 + ch.table_index] * s.omega;
  // HLAs: the pivot loads at z = 0 set their chambers' pressures, then the plungers move freely
  if (s.P > 0) {
    s.pin_plungers = true;
    polish_static(s, x0, v0, 30);
    hold_pivot_loads(s, x0);
  }
  polish_static(s, x0, v0, 30);
  if (s.H > 0) settle_hydraulics(s, 0.0, x0.data(), v0.data(), s.hyd.data());
  s.forces(x0.data(), v0.data());
  int contact = -1;
  const double error = s.gap_error(x0.data(), contact);
  if (error > s.opt.max_gap_error_mm)
    return {StatusCode::no_convergence, "the flexible model's static start finds no equilibrium: " +
                                            s.gap_error_message(error, contact),
            "cam " + format_number(theta * 180.0 / pi) + " deg"};
  return Status::success();
}

}  // namespace camopt::dynamics::detail
