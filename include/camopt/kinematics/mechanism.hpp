#pragma once
// the compiled, immutable mechanism: nodes (bodies), connections, their scalar variables
// and equations, and the solve plan found once by assembly analysis.
//
// variables: one per rotational [rad] / translational [mm] node, three per floating node
// (x [mm], y [mm], phi [rad]), and one parameter per curve or line surface of a contact.
// equations: link, crank-slider, gear, variable gear, rack-pinion: 1 each; a contact:
// one more than its surface parameters (closure + tangency).
// plan: perfect matching of equations to unknowns, then strongly connected components
// (Tarjan) give the block-triangular solve order; a block is solved by a closed form
// when it is a single explicit connection, otherwise simultaneously (a coupled cluster).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/kinematics/cam_profile.hpp"

namespace camopt::kin {

struct Control {
  std::string name;
  bool is_angle = true;  // deg (else mm)
  double min = 0.0, max = 0.0, default_value = 0.0;  // [deg or mm]
};

struct Node {
  std::string name;
  NodeKind kind = NodeKind::rotational;
  bool ground = false;             // the implicit fixed frame "ground"
  Eigen::Vector2d pivot{0, 0};     // rotational: drawing pivot [mm]
  int pivot_control = -1;          // control moving the pivot (-1: fixed)
  Eigen::Vector2d pivot_about{0, 0};
  double pivot_gain = 0.0;         // [rad per control unit]
  Eigen::Vector2d direction{0, 1}; // translational: unit direction
  Eigen::Vector2d reference{0, 0}; // floating: body reference point [mm]
  int control = -1;                // displacement set by this control
  int first_variable = -1;         // its first variable (-1 for ground)
  int dof = 1;                     // 0 ground, 1, or 3 floating
  double rest = 0.0;               // [rad or mm]
  SourceRef where;
};

enum class SurfaceKind { curve, point, line };

struct Surface {
  int node = -1;
  SurfaceKind kind = SurfaceKind::point;
  int profile = -1;                   // curve: index into Mechanism::profiles
  int source_profile = -1;            // the profile it is made from (a curve or a disc), else -1
  Eigen::Vector2d origin{0, 0};       // curve: profile origin; point: centre; line: a point
  double cos_orient = 1.0, sin_orient = 0.0;  // curve: profile frame rotation
  double offset = 0.0;                // point: signed radius (< 0: concave) [mm]
  Eigen::Vector2d normal{0, 1};       // line: unit outward normal
  bool roller = false;
  int variable = -1;                  // curve/line: its parameter variable
};

struct Connection {
  std::string name;
  ConnectionKind kind = ConnectionKind::link;
  int node_a = -1, node_b = -1;
  Eigen::Vector2d pin_a{0, 0}, pin_b{0, 0};  // link: drawing pin positions [mm]
  double length = 0.0;                       // link [mm]
  double ratio = 1.0;                        // gear
  Spline ratio_table;                        // variable gear: ratio against angle_a [rad]
  double pitch_radius = 0.0;                 // rack-pinion [mm]
  Surface surface_a, surface_b;              // contact
  double lash = 0.0;                         // [mm]
  bool one_sided = false;                    // lash given: may open
  int first_equation = 0, equation_count = 1;
  SourceRef where;
};

enum class StepMethod {
  link_closed_form,
  gear_closed_form,
  rack_closed_form,
  variable_gear_closed_form,
  contact_distance_closed_form,  // circle on circle: a link between the centres
  contact_line_closed_form,      // circle on a flat face, translating unknown: linear in it
  implicit
};

// the most unknowns one plan step solves simultaneously (compile() rejects a larger coupled
// cluster; WorkspaceState::max_block in src/kinematics)
inline constexpr int max_block_unknowns = 16;

struct SolveStep {
  std::vector<int> connections;  // whose equations form this block
  std::vector<int> unknowns;     // variables solved here
  StepMethod method = StepMethod::implicit;
  int output_node = -1;          // the node solved (single-node steps)
  int branch = 1;                // closed-form assembly branch (+1 / -1) from the drawing
  bool one_sided = false;        // a lash contact: holds the output node at rest while open
};

struct VariableInfo {
  std::string name;  // "valve", "lever.x", "cam_contact.u_a"
  int node = -1;     // owning node, or -1 for a surface parameter
  bool is_angle = true;
};

// a contact that touches at rest (touch_at_rest), solved at compile: side b's circle centre or
// line point moved along the contact normal so the shapes touch in the drawing
struct AssembledContact {
  int connection = -1;
  std::string key;     // the key of side b that moved: "b.center_mm" or "b.point_mm"
  Vec2 drawn_mm{};     // as written in the design [mm]
  Vec2 solved_mm{};    // where it touches [mm]
  double moved_mm = 0;  // along the contact normal, + away from side a [mm]
};

// the driver's sweep and crank ratio as the design gives them (its [driver] table)
struct DriverDefaults {
  double start = 0.0;          // sweep start [driver deg, or mm for a translational driver]
  double stop = 360.0;         // sweep stop [driver deg or mm]
  double step = 1.0;           // default output step [driver deg or mm]
  double crank_per_cam = 2.0;  // crank degrees per cam degree [-]
};

// the compiled model. It keeps no DesignSpec: a consumer that needs the source description
// (the dynamics data, an edited recompile) is handed the spec beside the model.
struct Mechanism {
  std::string name;  // the design's name
  std::string file;  // the design file, for messages ("" when built in code)
  DriverDefaults driver;
  std::vector<Control> controls;
  std::vector<Node> nodes;           // nodes[0] is "ground"
  std::vector<CamProfile> profiles;
  std::vector<Connection> connections;
  std::vector<VariableInfo> variables;
  std::vector<SolveStep> plan;
  int driver_node = -1, output_node = -1;
  int equation_count = 0;
  double length_scale = 1.0;  // characteristic size [mm] for tolerances
  std::vector<AssembledContact> assembled;  // the contacts that touch at rest, as solved

  int node_index(const std::string& name) const;  // -1 if absent
  int driver_variable() const { return nodes[driver_node].first_variable; }
  bool driver_is_angle() const { return nodes[driver_node].kind == NodeKind::rotational; }
  // every control at its default [deg or mm], in `controls` order (the drawing's setting)
  std::vector<double> default_controls() const {
    std::vector<double> d;
    d.reserve(controls.size());
    for (const Control& c : controls) d.push_back(c.default_value);
    return d;
  }
};

// validate the spec and build the immutable model; throws InputError naming the field
Mechanism compile(const DesignSpec& spec);

// human-readable description: nodes, connections, solve order (camopt validate)
std::string describe(const Mechanism& mech);

}  // namespace camopt::kin
