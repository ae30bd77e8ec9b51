#pragma once
// plain description of a mechanism as read from a design file. No validation beyond
// types happens here; compile() (kinematics/mechanism.hpp) checks it and builds the model.
//
// Geometry convention: every coordinate is given in the *drawing* - the assembly at
// zero displacement of every node - in the global frame [mm]. A node's displacement maps
// its drawing geometry to the current configuration. Angles are counter-clockwise
// positive [deg].
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/hla_spec.hpp"

namespace camopt {

using Vec2 = std::array<double, 2>;

enum class NodeKind { rotational, translational, floating };

// force law of a flexible-model contact or valve seat (docs/dynamics.md, "Contact laws")
enum class ContactLaw { hertz, linear };
enum class ContactDampingLaw { hunt_crossley, linear };
struct ContactLawSpec {
  ContactLaw law = ContactLaw::hertz;
  ContactDampingLaw damping_law = ContactDampingLaw::hunt_crossley;  // hertz law only
  std::optional<double> stiffness_N_per_mm;  // linear law: k (required there)
  // linear law: c in F = max(0, k d + c d'); hertz + linear damping: c in max(0, F_H + c d');
  // hertz + hunt_crossley: alpha matched to c at the reference load
  std::optional<double> damping_N_s_per_m;
  std::optional<double> restitution;  // hertz + hunt_crossley: coefficient of restitution, (0, 1]
};

// the seat of a valve (a translational node): a one-sided contact at its rest displacement
struct SeatSpec {
  bool enabled = true;             // false: no seat (a mechanism that is not a valvetrain)
  double diameter_mm = 29.0;       // seat (gauge) diameter
  double angle_deg = 45.0;         // seat face angle from the valve head plane
  double width_mm = 1.5;           // width of the seat face
  double crown_radius_mm = 5.0;    // hertz law: reduced radius of the section across the face
  std::string material;            // hertz law: insert material; "" = the valve's contact material
  ContactLawSpec law;
  bool given = false;              // a seat table was written in the design
  SourceRef where;
};

// a pivot moved by a control input: it rotates about `about_mm` by gain * control
// (eccentric control shaft, or an arc centred on a roller as in the CVVL)
struct PivotMotionSpec {
  std::string control;
  Vec2 about_mm{};
  double gain = 1.0;  // [deg of pivot rotation per control unit]
  SourceRef where;
};

struct NodeSpec {
  std::string name;
  NodeKind kind = NodeKind::rotational;
  Vec2 pivot_mm{};                              // rotational: pivot in the drawing
  std::optional<PivotMotionSpec> pivot_motion;  // rotational: pivot set by a control
  Vec2 origin_mm{};                             // translational: a point on its line
  Vec2 direction{0.0, 1.0};                     // translational: positive sense (any length)
  std::optional<std::string> control;  // displacement set by this control (not solved)
  double rest = 0.0;  // displacement held while a lash gap is open [deg or mm]

  // dynamics data (required only by the dynamics models)
  std::optional<double> mass_kg;
  std::optional<double> inertia_kg_mm2;  // about the centre of gravity
  std::optional<Vec2> cg_mm;             // centre of gravity in the drawing
  std::optional<double> torsional_stiffness_Nm_per_rad;  // rotational compliance
  std::optional<double> axial_stiffness_N_per_mm;        // translational compliance
  std::optional<double> damping_ratio;                   // of that compliance [-]
  std::optional<double> damping_N_s_per_m;      // translational compliance: damper [N s/m]
  std::optional<double> damping_Nm_s_per_rad;   // rotational compliance: damper [N m s/rad]
  SeatSpec seat;  // the output node always has one (unless disabled); others when given
  SourceRef where;
};

enum class ProfileForm { polar, xy, base_plus_lift, circle, eccentric };

struct ProfileSpec {
  std::string name;
  ProfileForm form = ProfileForm::polar;
  std::vector<double> angle_deg;  // polar / base_plus_lift: polar angle in the profile frame
  std::vector<double> radius_mm;  // polar: radius at angle_deg
  std::vector<double> lift_mm;    // base_plus_lift: radius = base_radius_mm + lift_mm
  std::vector<double> x_mm, y_mm; // xy: closed curve, counter-clockwise, no repeated end point
  double base_radius_mm = 0.0;    // base_plus_lift
  double disc_radius_mm = 0.0;    // circle / eccentric
  double eccentricity_mm = 0.0;   // eccentric: disc centre offset along the profile's 0 deg axis
  std::string source_file;        // set when the table came from a CSV file
  SourceRef where;
};

enum class SurfaceShape { profile, circle, line };

// one side of a contact: a surface fixed to a node
struct SurfaceSpec {
  std::string node;
  SurfaceShape shape = SurfaceShape::circle;
  std::string profile;         // profile: name of a [[profile]]
  Vec2 origin_mm{};            // profile: polar origin; circle: centre; line: a point on it
  double orientation_deg = 0;  // profile: drawing angle of the profile's 0 deg axis
  double radius_mm = 0.0;      // circle
  bool concave = false;        // circle: contact on the inside (a concave pad)
  bool roller = false;         // circle: free roller turning on its own pin
  Vec2 normal{0.0, 1.0};       // line: outward normal (towards the other body)
  std::optional<double> half_width_mm;  // line: usable face half-width
  SourceRef where;
};

enum class ConnectionKind { link, crank_slider, gear, variable_gear, rack_pinion, contact };

struct PinSpec {
  std::string node;
  Vec2 point_mm{};
  SourceRef where;
};

struct ConnectionSpec {
  std::string name;
  ConnectionKind kind = ConnectionKind::link;
  // link, crank_slider: pin-pin coupler of fixed length
  PinSpec pin_a, pin_b;
  std::optional<double> length_mm;  // default: drawing distance between the pins
  // gear, variable_gear, rack_pinion: relation between node_a (input side) and node_b
  std::string node_a, node_b;
  double ratio = 1.0;  // gear: d(angle_b)/d(angle_a) [-]
  std::vector<double> ratio_input_deg, ratio_values;  // variable_gear: ratio against angle_a
  double pitch_radius_mm = 0.0;  // rack_pinion: rack travel = pitch radius * pinion angle [rad]
  // contact
  SurfaceSpec surface_a, surface_b;
  double lash_mm = 0.0;               // clearance on the base circle [mm]
  std::string material_a, material_b; // names of [[material]] (dynamics / Hertz)
  std::optional<double> width_mm;     // contact line length for Hertz stress
  std::optional<double> friction_coefficient;
  ContactLawSpec contact_law;  // flexible model's force law
  bool two_sided = false;      // a roller in a slot: guided both ways, the force may pull
  // the contact touches in the drawing: kin::compile places side b's circle centre or line
  // point on the contact normal so it does (docs/design-format.md, "Contacts that touch at rest")
  bool touch_at_rest = false;
  std::optional<Vec2> drawn_b_mm;  // b's centre or point as written, once the solved one replaced it
  double moved_b_mm = 0.0;         // how far it moved: along the contact normal, + away from a [mm]
  // link, crank_slider, rack_pinion [N/mm]; gear, variable_gear [N m/rad]: flexible model's
  // bilateral stiffness, and the damping ratio of its local mode
  std::optional<double> stiffness_N_per_mm, stiffness_Nm_per_rad;
  std::optional<double> damping_ratio;
  SourceRef where;
};

struct MaterialSpec {
  std::string name;
  double youngs_modulus_GPa = 0.0;
  double poisson_ratio = 0.0;
  std::optional<double> density_kg_per_m3;
  SourceRef where;
};

enum class SpringKind { compression, torsion };
constexpr int kMaxSurgeMasses = 500;

struct SpringSpec {
  std::string name;
  SpringKind kind = SpringKind::compression;
  std::string node;  // translational node (compression) or rotational node (torsion)
  // linear law: force = preload + rate * displacement; a table replaces it (progressive)
  double rate_N_per_mm = 0.0;
  double preload_N = 0.0;
  std::vector<double> table_displacement_mm, table_force_N;
  double rate_Nmm_per_deg = 0.0;  // torsion
  double preload_Nmm = 0.0;       // torsion
  // mass-elastic data (flexible model; mass also adds 1/3 to the node in rigid mode)
  std::optional<double> mass_kg;
  int surge_masses = 0;  // lumped masses for the surge model (0 = massless), at most kMaxSurgeMasses
  // compression spring on a floating node: the point of the body it pushes (drawing) and its
  // line of action; the spring compresses as the point moves along +direction
  std::optional<Vec2> point_mm, direction;
  std::optional<double> damping_N_s_per_m;       // viscous damping between the spring's ends
  std::optional<double> coil_damping_ratio;      // coil-to-coil: ratio of the first surge mode
  std::optional<double> coil_damping_N_s_per_m;  // coil-to-coil: damper between adjacent coil masses
  std::optional<double> installed_length_mm, solid_length_mm;
  std::optional<double> wire_diameter_mm, mean_coil_diameter_mm, active_coils, shear_modulus_GPa;
  SourceRef where;
};

struct GasForceSpec {
  std::string node;
  std::vector<double> crank_angle_deg, force_N;  // force opposing valve opening
  std::string source_file;
  SourceRef where;
};

// the engine oil at operating temperature ([oil], docs/design-format.md): what the EHL film
// thickness of the contacts needs (docs/dynamics.md, "EHL film thickness")
struct OilSpec {
  double viscosity_mPa_s = 0, pressure_viscosity_per_GPa = 0;  // inlet dynamic viscosity; Barus alpha
  std::optional<double> composite_roughness_um;  // sigma = sqrt(Rq_a^2 + Rq_b^2); no lambda without it
  std::string where;                             // "file:line:column: oil" of the table
};

struct ControlSpec {
  std::string name;
  std::string unit = "deg";  // "deg" or "mm"
  double min = 0.0, max = 0.0, default_value = 0.0;
  SourceRef where;
};

struct DriverSpec {
  std::string node;             // the node whose displacement is prescribed
  double start_deg = 0.0;       // sweep start [driver deg, or mm for a translational driver]
  double stop_deg = 360.0;      // sweep stop
  double step_deg = 1.0;        // default output step
  double crank_per_cam = 2.0;   // crank degrees per cam degree (4-stroke: 2)
  SourceRef where;
};

struct DesignSpec {
  std::string name;
  std::string description;
  std::string file;       // path of the design file ("" when built in code)
  std::string directory;  // where relative file references are resolved
  std::string output_node;  // the node reported as valve lift
  DriverSpec driver;
  std::vector<ControlSpec> controls;
  std::vector<NodeSpec> nodes;
  std::vector<ProfileSpec> profiles;
  std::vector<ConnectionSpec> connections;
  std::vector<MaterialSpec> materials;
  std::vector<SpringSpec> springs;
  std::vector<GasForceSpec> gas_forces;
  std::optional<OilSpec> oil;
  std::vector<HlaSpec> hlas;  // hydraulic lash adjusters (docs/hla.md)
};

const char* to_string(NodeKind kind);
const char* to_string(ConnectionKind kind);
const char* to_string(ProfileForm form);
const char* to_string(SurfaceShape shape);
const char* to_string(ContactLaw law);
const char* to_string(ContactDampingLaw law);

}  // namespace camopt
