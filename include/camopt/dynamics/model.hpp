#pragma once
// the dynamics data of a compiled mechanism, validated once: body inertias, springs, gas
// forces, per-contact materials and force laws, component compliances and valve seats.
// compile_dynamics(spec, mech) reads the design spec once; the dynamics models (rigid,
// compliant, flexible, modes) read this Model and the Mechanism's compiled data, never the
// DesignSpec.
// Bad or missing data needed by the rigid model throws InputError naming the field; what
// only the flexible model needs is kept with its source and checked when that model is built.
//
// units inside: lengths [mm], masses [kg], inertias [kg mm^2], forces [N], torques [N mm],
// Young's moduli [N/mm^2 = MPa].
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/dynamics/hla.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::dynamics {

// mass properties of one node (a rigid body)
struct BodyInertia {
  double mass = 0.0;     // [kg], node mass plus 1/3 of every spring mass on it
  double inertia = 0.0;  // about the centre of gravity [kg mm^2]
  Eigen::Vector2d cg{0, 0};  // centre of gravity in the drawing [mm]
};

// a valve spring (compression, on a translational node) or a torsion spring (rotational
// node); the load opposes positive displacement of the node
struct Spring {
  std::string name;
  SpringKind kind = SpringKind::compression;
  int node = -1;
  double rate = 0.0;     // compression [N/mm]; torsion [N mm/rad]
  double preload = 0.0;  // compression [N]; torsion [N mm]
  std::vector<double> table_x, table_f;  // progressive law [mm] -> [N] (empty: linear)
  double damping = 0.0;  // compression: viscous damper between its ends [N s/mm]
  // on a floating node: the point it pushes (drawing) and its line of action (unit); the
  // travel is direction . (point now - point in the drawing)
  bool on_point = false;
  Eigen::Vector2d point{0, 0}, direction{0, 1};

  double mass = 0.0;      // compression: the coil's mass [kg] (0: massless)
  int surge_masses = 0;   // compression: internal masses of the flexible model's coil chain
  std::optional<double> coil_damping_ratio;  // coil-to-coil: ratio of the first surge mode [-]
  std::optional<double> coil_damping;        // coil-to-coil: damper between adjacent coil masses [N s/mm]
  double solid_travel = -1.0;  // node travel at which the coils touch [mm]; < 0: not given

  // load at node displacement x [mm or rad]: force [N] or torque [N mm]
  double load(double x) const;
  // d(load)/dx [N/mm or N mm/rad]
  double stiffness(double x) const;
  // work done compressing it from 0 to x: int_0^x load [N mm]
  double energy(double x) const;
};

// cylinder gas force against a valve's opening, from a table against crank angle
struct GasForce {
  int node = -1;
  std::vector<double> crank_deg, force;  // [crank deg], [N]
  double period_deg = 720.0;             // one engine cycle [crank deg]
  // force at a crank angle: the table wrapped into one cycle from its first angle,
  // linear between points, 0 outside the table's span [N]
  double at(double crank_angle_deg) const;
};

// per connection: what the contact models need
struct ContactData {
  bool is_contact = false;
  bool has_hertz = false;     // materials and width given
  double e_star = 0.0;        // contact modulus E* [N/mm^2]: 1/E* = (1-nu_a^2)/E_a + (1-nu_b^2)/E_b
  double width = 0.0;         // line contact length L [mm]
  double friction = 0.0;      // Coulomb coefficient [-]
  bool rolling = false;       // a free roller: no sliding, no friction
  double damping = -1.0;      // design damping [N s/mm]; < 0 when not given
  int held_node = -1;         // lash contact: the node held at rest while the gap is open
  bool two_sided = false;     // a roller in a slot: the force may pull, the contact never opens
  ContactLawSpec law;         // the flexible model's force law (design keys, checked there)
  SourceRef where;            // the connection in the design file
};

// per connection: the flexible model's bilateral compliance of a link or a gear
struct LinkCompliance {
  std::optional<double> stiffness;      // links [N/mm], gears [N mm/rad]; default: FlexibleOptions
  std::optional<double> damping_ratio;  // of the connection's local mode [-]
};

// the flexible model's compliance of a node (its far end joined to it by a spring-damper)
struct NodeCompliance {
  int node = -1;
  double stiffness = 0.0;               // translational [N/mm], rotational [N mm/rad]
  std::optional<double> damping;        // a damper: [N s/mm] or [N mm s/rad]; else from the ratio
  std::optional<double> damping_ratio;  // [-]; default: FlexibleOptions::component_damping_ratio
  SourceRef where;                      // the node in the design file
};

// a valve seat of the flexible model: a one-sided contact at a translational node's rest
// displacement (the output node always, unless disabled; other nodes when a seat is given)
struct SeatData {
  int node = -1;
  bool given = false;           // a seat table in the design (else the output node's default)
  double diameter = 0.0;        // seat (gauge) diameter [mm]
  double angle_deg = 0.0;       // face angle from the valve head plane [deg]
  double width = 0.0;           // face width [mm]
  double crown_radius = 0.0;    // hertz law: section radius across the face [mm]
  double e_star = 0.0;          // hertz law: valve against insert [N/mm^2] (steel without a material)
  ContactLawSpec law;
  SourceRef seat_where, node_where;  // the seat table and its node in the design file
};

// a hydraulic lash adjuster of the flexible model (hla.hpp) and the node it supports
struct HlaData {
  Hla hla;
  int node = -1;
};

struct Model {
  std::vector<BodyInertia> bodies;     // per node (ground and the driver included)
  std::vector<Spring> springs;
  std::vector<GasForce> gas_forces;
  std::vector<ContactData> contacts;   // per connection
  double crank_per_cam = 2.0;
  // every node variable that is free (not the driver, not set by a control): its row in
  // the force balance; -1 otherwise. indexed by variable
  std::vector<int> row_of_variable;
  std::vector<int> free_variables;     // row -> variable
  std::vector<LinkCompliance> links;   // per connection (links and gears)
  std::vector<NodeCompliance> compliances;  // nodes with a stiffness, in design order
  std::vector<SeatData> seats;         // seat candidates, by node index
  std::optional<OilSpec> oil;          // [oil]: the EHL film of the rigid model's contacts
  std::vector<HlaData> hlas;           // [[hla]]: the flexible model's; the rigid models hold the pivot fixed
  double driver_start_deg = 0.0;       // the design's first driver angle [cam deg]
};

// validate the dynamics data of `spec` for the rigid models and build the model (the only
// place the dynamics read the DesignSpec). `mech` is kin::compile(spec): InputError when its
// name, nodes or connections are not the spec's.
// Required: a rotational driver; every moving node (not the driver, not set by a control)
// needs mass_kg (translational, floating, or rotational with cg_mm) and inertia_kg_mm2
// (rotational, floating). Without cg_mm the centre of gravity is the pivot (rotational),
// the origin (translational) or the centroid of the body's features, the kinematic
// reference point (floating). Positive masses, inertias, rates, widths and moduli.
Model compile_dynamics(const DesignSpec& spec, const kin::Mechanism& mech);

// contact modulus E* [N/mm^2] of two materials (Johnson, Contact Mechanics, 1985, eq. 4.22)
double contact_modulus(double e_a, double nu_a, double e_b, double nu_b);

}  // namespace camopt::dynamics
