// the hydraulic lash adjusters of the flexible model (flexible_system.hpp, docs/hla.md): a
// plunger coordinate under a rotational node's pivot or in series on a translational node
// (between its contact side and its valve side), the HLA element's force and hydraulic
// states (hla.hpp) in the same CVODE system, its roots and the plunger's travel stops
#include <cmath>

#include "camopt/core/units.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

namespace {

constexpr double kMilli = 1e-3;  // kg -> N s^2/mm
// the plunger's travel stops: a one-sided linear spring-damper (steel on steel, the body's
// bottom or the retaining clip) [N/mm], damped at this ratio of the plunger's own mode
constexpr double kStopStiffness = 1e5;
constexpr double kStopDampingRatio = 0.2;
// the static start's pin of every plunger at z = 0 [N/mm]
constexpr double kPinStiffness = 1e9;

// the crank angle at time t [deg] (the supply table's abscissa)
double crank_deg(const System& s, double t) {
  return (s.theta0 + s.omega * t) / rad_per_deg * s.flex.crank_per_cam;
}

const Hla& hla_of(const System& s, const Plunger& p) { return s.flex.hlas[p.hla].hla; }

// how far the plunger is past a stop [mm] (> 0: on it), and its side (+1 pushes out)
double stop_overlap(const Hla& hla, double z, double& side) {
  if (z < hla.travel_min) return side = 1.0, hla.travel_min - z;
  if (z > hla.travel_max) return side = -1.0, z - hla.travel_max;
  return side = 0.0, 0.0;
}

double stop_damping(const Plunger& p) { return 2.0 * kStopDampingRatio * std::sqrt(kStopStiffness * p.mass); }

}  // namespace

namespace {

std::string vec_text(const Eigen::Vector2d& v) { return "(" + format_value(v.x()) + ", " + format_value(v.y()) + ")"; }

// an HLA in series on a solved translational node: its contact side of mass series_body_mass
// moves by z along the axis from the valve side, which keeps the rest of the node's mass
void place_in_series(const System& s, const Model& model, const HlaData& data, Plunger& p) {
  const kin::Node& node = s.mech.nodes[data.node];
  const Hla& hla = data.hla;
  const std::string who = "hla '" + hla.name + "' in series on node '" + node.name + "'";
  if (!(hla.series_body_mass > 0.0))
    throw InputError(hla.where, who + ": series_body_mass_kg is required (the mass of the part on the contacts' side)");
  const double whole = kMilli * model.bodies[data.node].mass;
  if (!(hla.series_body_mass < whole))
    throw InputError(hla.where, who + ": series_body_mass_kg " + format_value(hla.series_body_mass / kMilli) +
                                    " must be < the node's mass " + format_value(whole / kMilli) +
                                    " kg (the valve side keeps the rest)");
  const double along = hla.axis.dot(node.direction.normalized());
  if (!(std::abs(along) > 1.0 - 1e-9))
    throw InputError(hla.where, who + ": axis " + vec_text(hla.axis) + " must be along the node's direction " +
                                    vec_text(node.direction) + " (the plunger moves the contact side along the node)");
  p.series = true;
  p.along = along > 0.0 ? 1.0 : -1.0;
  p.mass = hla.series_body_mass;
}

}  // namespace

void add_plungers(System& s, const Model& model) {
  const kin::Mechanism& mech = s.mech;
  int next = s.R + s.E;
  for (std::size_t i = 0; i < model.hlas.size(); ++i) {
    const HlaData& data = model.hlas[i];
    const kin::Node& node = mech.nodes[data.node];
    const bool solved = node.control < 0 && node.pivot_control < 0 && data.node != mech.driver_node &&
                        node.first_variable >= 0 && model.row_of_variable[node.first_variable] >= 0;
    const bool pivot = node.kind == NodeKind::rotational && data.hla.series_body_mass == 0.0;
    const bool series = node.kind == NodeKind::translational;
    if (!solved || !(pivot || series))
      throw InputError(data.hla.where, "hla '" + data.hla.name + "' on node '" + node.name +
                                           "': the flexible model places an HLA under the fixed pivot of a solved "
                                           "rotational node (an end-pivot finger follower or a rocker arm), or in "
                                           "series on a solved translational node with series_body_mass_kg (a bucket "
                                           "tappet, a rocker arm's valve-side insert)");
    Plunger p;
    p.hla = static_cast<int>(i);
    p.node = data.node;
    p.row = model.row_of_variable[node.first_variable];
    p.far = s.far_of_row[p.row];
    p.coord = next++;
    p.table_index = static_cast<int>(s.plungers.size());
    p.axis = data.hla.axis;
    p.pivot = node.pivot;
    p.mass = kMilli * model.bodies[data.node].mass + data.hla.plunger_mass;
    if (series) place_in_series(s, model, data, p);
    p.touches.assign(s.C, 0);
    for (int c = 0; c < s.C; ++c) {
      const kin::Connection& conn = mech.connections[c];
      if (conn.node_a != data.node && conn.node_b != data.node) continue;
      if (conn.kind != ConnectionKind::contact)
        throw InputError(data.hla.where, "hla '" + data.hla.name + "': connection '" + conn.name + "' joins node '" +
                                             node.name + "' by a " + to_string(conn.kind) +
                                             "; the flexible model moves a node on an HLA against contacts only");
      p.touches[c] = 1;
    }
    p.first_state = s.H;
    s.H += kHlaStates;
    s.plungers.push_back(p);
  }
  s.P = static_cast<int>(s.plungers.size());
  s.hla_modes.assign(s.plungers.size(), HlaMode{});
}

double plunger_force(const System& s, const Plunger& p, const double* q, const double* qd) {
  if (s.pin_plungers) return -kPinStiffness * q[p.coord];
  const Hla& hla = hla_of(s, p);
  const double z = q[p.coord];
  // evaluated at the system's current time: the path's angle
  const double crank = s.evaluated_theta / rad_per_deg * s.flex.crank_per_cam;
  // a stop pushes back while it is compressed: side max(0, k overlap - side c z')
  double side = 0.0;
  const double overlap = stop_overlap(hla, z, side);
  const double stop =
      overlap > 0.0 ? side * std::max(0.0, kStopStiffness * overlap - side * stop_damping(p) * qd[p.coord]) : 0.0;
  return hla_force(hla, crank, s.hyd(p.first_state + kHlaPressure), z) + stop;
}

double plunger_stiffness(const System& s, const Plunger& p, const double* q) {
  if (s.pin_plungers) return kPinStiffness;
  const Hla& hla = hla_of(s, p);
  double side = 0.0;
  return hla.spring_rate + (stop_overlap(hla, q[p.coord], side) > 0.0 ? kStopStiffness : 0.0);
}

double plunger_damping(const System& s, const Plunger& p, const double* q) {
  if (s.pin_plungers) return 0.0;
  double side = 0.0;
  return stop_overlap(hla_of(s, p), q[p.coord], side) > 0.0 ? stop_damping(p) : 0.0;
}

double hla_static_stiffness(const System& s, const Plunger& p) {
  const Hla& hla = hla_of(s, p);
  const double pressure = s.hyd(p.first_state + kHlaPressure);
  return hla.plunger_area * hla.plunger_area * hla_bulk_modulus(hla, pressure) / hla_chamber_volume(hla, 0.0) +
         hla.spring_rate;
}

void initial_hydraulics(const System& s, double t, double* h) {
  // the chamber at the gallery pressure, no void, the ball on its seat
  for (std::size_t k = 0; k < s.plungers.size(); ++k) {
    const Plunger& p = s.plungers[k];
    const Hla& hla = hla_of(s, p);
    double* x = h + p.first_state;
    x[kHlaPressure] = hla.supply_at(crank_deg(s, t));
    x[kHlaVoid] = x[kHlaBallLift] = x[kHlaBallVelocity] = 0.0;
  }
}

void settle_hydraulics(System& s, double t, const double* q, const double* qd, double* h) {
  for (std::size_t k = 0; k < s.plungers.size(); ++k) {
    const Plunger& p = s.plungers[k];
    s.hla_modes[k] = hla_settle_mode(hla_of(s, p), crank_deg(s, t), q[p.coord], qd[p.coord], h + p.first_state);
  }
}

namespace {

// a series HLA's valve side on its seat (after forces): the load between the bodies is then
// shared with the seat by the contacts' approaches, not set by the train
bool seated(const System& s, const Plunger& p) {
  for (std::size_t k = 0; k < s.seats.size(); ++k)
    if (s.seats[k].node == p.node && s.fr.seat[k] > 0.0) return true;
  return false;
}

}  // namespace

void hold_pivot_loads(System& s, Eigen::VectorXd& x) {
  for (const Plunger& p : s.plungers) {
    const Hla& hla = hla_of(s, p);
    const double load = -kPinStiffness * x(p.coord);  // what the pin carried along the axis [N]
    const double supply = hla.supply_at(crank_deg(s, 0.0));
    // (p - supply) A + F_s(0) = load; a seated series HLA at the gallery's pressure (the state
    // leak-down and refill settle to: the seat carries what the return spring does not)
    const double pressure = supply + (load - hla.spring_preload) / hla.plunger_area;
    s.hyd(p.first_state + kHlaPressure) = p.series && seated(s, p) ? supply : std::max(pressure, supply);
    x(p.coord) = 0.0;
  }
  s.pin_plungers = false;
}

double hydraulic_tolerance(const System& s, int i) {
  // a plunger displacement at the mechanical tolerance moves the pressure by about
  // A beta / V ~ 1e3 MPa/mm and the chamber's content by A ~ 1e2 mm^2
  const double atol = s.opt.absolute_tolerance;
  switch (i % kHlaStates) {
    case kHlaPressure: return 1e3 * atol;
    case kHlaVoid: return 1e2 * atol;
    case kHlaBallLift: return atol;
    default: return 1e4 * atol;
  }
}

bool hydraulic_rates(const System& s, double t, const double* q, const double* qd, const double* h, double* hdot) {
  const double crank = crank_deg(s, t);
  bool finite = true;
  for (std::size_t k = 0; k < s.plungers.size(); ++k) {
    const Plunger& p = s.plungers[k];
    hla_rates(hla_of(s, p), crank, q[p.coord], qd[p.coord], h + p.first_state, s.hla_modes[k], hdot + p.first_state);
    for (int i = 0; i < kHlaStates; ++i) finite = finite && std::isfinite(hdot[p.first_state + i]);
  }
  return finite;
}

void add_hla_roots(System& s) {
  for (int k = 0; k < s.P; ++k)
    for (int j = 0; j < kHlaRoots + 2; ++j) s.root_list.push_back({3, k, j});
}

double hla_root_value(const System& s, const System::Root& rt, double t, const double* q, const double* qd,
                      const double* h) {
  const Plunger& p = s.plungers[rt.index];
  const Hla& hla = hla_of(s, p);
  double g[kHlaRoots + 2];
  hla_roots(hla, crank_deg(s, t), q[p.coord], qd[p.coord], h + p.first_state, s.hla_modes[rt.index], g);
  hla_travel_roots(hla, q[p.coord], g + kHlaRoots);
  return g[rt.segment];
}

std::string hla_root_name(const System& s, const System::Root& rt) {
  static const char* const what[] = {"chamber pressure floor", "ball seat", "ball cage", "plunger bottom stop",
                                     "plunger top stop"};
  // named by the node it supports, as its columns
  return "hla " + s.mech.nodes[s.plungers[rt.index].node].name + " " + what[rt.segment];
}

std::uint32_t on_hla_roots(System& s, int plunger, const int* found, double t, const double* q, const double* qd,
                           double* h) {
  const Plunger& p = s.plungers[plunger];
  return hla_on_root(hla_of(s, p), crank_deg(s, t), q[p.coord], qd[p.coord], h + p.first_state, s.hla_modes[plunger],
                     found);
}

HlaPoint hla_point(const System& s, const Plunger& p, double t, const double* q, const double* qd, const double* h) {
  const Hla& hla = hla_of(s, p);
  const double crank = crank_deg(s, t);
  const double* x = h + p.first_state;
  double rates[kHlaStates];
  HlaFlows flows;
  hla_rates(hla, crank, q[p.coord], qd[p.coord], x, s.hla_modes[p.table_index], rates, &flows);
  HlaPoint pt;
  pt.plunger_mm = q[p.coord];
  pt.force_N = hla_force(hla, crank, x[kHlaPressure], q[p.coord]);
  pt.pressure_MPa = x[kHlaPressure];
  pt.ball_lift_mm = x[kHlaBallLift];
  pt.leak_mm3_per_s = flows.leak + flows.orifice;
  pt.refill_mm3_per_s = flows.refill;
  pt.volume_ratio = hla_volume_ratio(hla, x[kHlaPressure]);
  return pt;
}

}  // namespace camopt::dynamics::detail
