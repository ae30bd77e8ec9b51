#pragma once
// position, velocity, acceleration and jerk of every node at one driver position.
// kernel: solve(const Mechanism&, Workspace&, driver value, request). Derivatives are
// taylor coefficients with respect to the driver [per rad or per mm of driver], exact:
// closed forms run on jets, implicit blocks use implicit differentiation J x_k = -r_k.
#include <Eigen/Core>
#include <cmath>
#include <span>
#include <tuple>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/kinematics/detail/geometry.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/small_lu.hpp"

namespace camopt::kin {

using Jet3 = Jet<3>;

// what a solve returns. The continuation itself always solves the Taylor series to order 3
// (its predictor and step control need them), whatever is requested: the request only
// decides what is kept (Workspace::vars beyond the order are zeroed) and what is computed
// after a point is accepted (contact quantities).
struct Request {
  int derivative_order = 3;  // 0: positions only, up to 3: jerk
  bool contacts = false;     // per-contact quantities (needs order >= 1)

  // InputError naming the field, its value and the rule it breaks
  void validate() const;
};

// toggle margin (Workspace::toggle_margin) below which a point counts as near a singular
// configuration (a linkage at toggle, a pressure angle near 90 deg): a closed-form step
// with a transmission angle below 1.15 deg; a four-bar whose coupler is a floating body
// held by link pairs (margin about 0.11 x the sine) below about 10 deg. The bundled
// designs stay above 0.05.
inline constexpr double near_singular_margin = 0.02;

// per-contact kinematic quantities; rates are per rad (or mm) of driver
struct ContactState {
  double x = 0, y = 0;                   // contact point, global [mm]
  double local_a_x = 0, local_a_y = 0;   // on body a, drawing frame [mm]
  double local_b_x = 0, local_b_y = 0;   // on body b, drawing frame [mm]
  double polar_angle_a = 0;              // cam (profile) parameter at the contact [rad], a side
  double normal_x = 0, normal_y = 0;     // unit normal from a into b
  double pressure_angle = 0;             // [rad] between normal and follower's direction of motion
  double curvature_a = 0, curvature_b = 0;  // [1/mm], + convex, 0 flat
  double entrainment = 0;                // mean surface speed relative to contact point [mm/driver]
  double sliding = 0;                    // tangential relative speed of material points [mm/driver]
  double roller_speed = 0;               // roller spin relative to its carrier, perfect rolling [rad/driver]
  double gap = 0;                        // open clearance [mm] (0 when closed)
  bool open = false;
};

struct SolveStats {
  long broyden_iterations = 0, newton_iterations = 0, newton_fallbacks = 0, points = 0;
  long rejected_steps = 0;  // driver (or control) steps halved by the trust check
  // work done for outputs (a run computes only what it asked for; tests check these):
  long taylor_orders = 0;     // implicit blocks' taylor orders solved (one per block and order)
  long jet_closed_forms = 0;  // closed-form steps run on jets (derivatives) instead of values
  long contact_outputs = 0;   // contacts whose per-contact quantities were computed
};

class Workspace {
 public:
  explicit Workspace(const Mechanism& mech);

  // set control positions [deg or mm], in Mechanism::controls order (InputError unless one
  // value per control); resets warm starts unless keep_warm_start (then the next solve
  // continues from the last point, with the trust check below bounding the change)
  void set_controls(std::span<const double> values, bool keep_warm_start = false);
  const std::vector<double>& controls() const { return controls_; }
  void reset();  // forget warm starts (next solve scans for contact points)

  // results of the last solve
  std::vector<Jet3> vars;             // every variable's jet w.r.t. the driver
  std::vector<ContactState> contacts; // per connection (contacts only meaningful)
  double max_condition = 0.0;         // largest block condition estimate at this point
  // margin from a singular configuration at this point, the smallest over its solve steps
  // (1: well conditioned, 0: singular): for a block solved simultaneously 1 / (1-norm
  // condition number of its jacobian with every angle measured as arc length at
  // Mechanism::length_scale), for a closed-form step the sine of its transmission angle
  // (between the link, or the contact normal, and the unknown pin's direction of motion)
  double toggle_margin = 1.0;
  // the smallest toggle_margin over the points accepted by the last solve() at its controls
  // (the point, and the driver continuation and halved steps leading to it), and where
  // [driver rad or mm]
  double path_margin = INFINITY, path_margin_at = 0.0;
  SolveStats stats;

  // ---- internals used by the kernel ----
  static constexpr int max_block = max_block_unknowns;  // unknowns solved simultaneously
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, max_block, max_block>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, max_block, 1>;
  struct Block {
    std::vector<int> connections;
    std::vector<std::pair<int, int>> equations;  // (connection, local equation)
    std::vector<int> unknowns;
    std::vector<char> solving;  // per node: its variables are unknowns here
    Matrix inverse;             // broyden inverse jacobian (warm start)
    bool have_inverse = false;
    SmallLU<max_block> lu;
    Matrix jacobian;            // exact jacobian at x when jacobian_at_x
    bool jacobian_at_x = false;
    double contraction = 0.0;   // last residual reduction of a broyden step (|f_new| / |f|)
    // branch guard: solved at this point (by either form), its toggle margin, and the sign
    // of its jacobian's determinant (general form +-1, one-equation form +-2, 0 unknown)
    // here and at the last accepted point
    bool solved = false;
    double margin = 1.0, accepted_margin = 1.0;
    int sign = 0, accepted_sign = 0;
    // exact jacobians at the last two solved points, extrapolated linearly in the driver
    // to start broyden at the next one
    Matrix last_jacobian, prev_jacobian;
    double last_driver = 0.0, prev_driver = 0.0;
    int jacobians = 0;
    Vector x, f, dx, f_new, u, row, r1;  // r1: order-1 residual coefficient (jacobian sweep)
    // a curve on a known body against a circle on the block's one unknown body: solved as
    // one equation in the curve parameter (the circle centre on the curve's offset)
    struct OffsetContact {
      bool active = false;
      int connection = -1, known_node = -1, unknown_node = -1;
      int curve_variable = -1, node_variable = -1;
      bool curve_on_a = true;
      double centre_offset = 0.0;       // circle radius - lash [mm] along the curve's outward normal
      Eigen::Vector2d centre{0, 0};     // circle centre, drawing [mm]
      double arm = 0.0, arm_angle = 0.0;  // rotational: centre about the pivot [mm], [rad]
      double cos_arm = 1.0, sin_arm = 0.0;  // of arm_angle
    } offset;
  };
  std::vector<Block> full_blocks;      // per plan step
  std::vector<Block> tangency_blocks;  // per plan step (one-sided contacts: params only)
  std::vector<double> values, prev_values, prev2_values;
  std::vector<Jet3> prev_jets, prev2_jets;
  std::vector<Jet<1>> vars1;  // contact outputs
  std::vector<Jet<2>> vars2;
  // the jacobian sweep: Dual<n + 1> for a block of n <= max_dual - 1 unknowns, larger
  // blocks in chunks of max_dual - 1 columns
  static constexpr int max_dual = 5;
  std::tuple<std::vector<Dual<2>>, std::vector<Dual<3>>, std::vector<Dual<4>>,
             std::vector<Dual<5>>>
      dual_vars;
  template <int M>
  std::vector<Dual<M>>& vars_dual() {
    return std::get<M - 2>(dual_vars);
  }
  std::vector<Eigen::Vector2d> pivots;
  bool pivots_stale = true;  // set_controls moved them: place them again on the next solve
  detail::PoseCache<double> poses0;
  detail::PoseCache<Jet<2>> poses2;
  detail::PoseCache<Jet3> poses3;
  detail::PoseCache<Jet<1>> poses1;   // contact outputs
  std::vector<char> no_node_solving;  // per node: 0 (poses once every variable is final)
  long point_id = 0;
  void invalidate_pose(int node) {
    poses0.invalidate(node);
    poses2.invalidate(node);
    poses3.invalidate(node);
    poses1.invalidate(node);
  }
  std::vector<bool> open;  // per plan step: lash gap open
  // step control: a point is accepted only if no solved variable moved farther than its
  // trust radius from the prediction and the prediction's highest taylor terms are within
  // it too, and the branch guard (detail/branch_guard.hpp) finds it on the predicted
  // branch; otherwise the step from the last accepted point is halved
  std::vector<double> trust_radius;     // per variable [rad or mm]; infinite for known ones
  std::vector<double> variable_scale;   // per variable: 1 / length_scale for angles and curve parameters, else 1
  std::vector<double> predicted;        // per variable: the predictor's value at this point
  std::vector<double> predicted_error;  // per variable: its error estimate (the highest terms taken)
  std::vector<bool> prev_open;          // per plan step: lash gap open at the last accepted point
  bool controls_moved = false;          // set_controls since the last accepted point
  bool offset_contacts = true;  // use the one-equation form where it applies (off: tests compare)
  double prev_driver = 0.0, prev2_driver = 0.0;
  int history = 0;  // number of previous points available for prediction
  std::vector<double> residual_buffer;
  std::vector<Jet<2>> residual_buffer2;
  std::vector<Jet3> residual_buffer3;

 private:
  std::vector<double> controls_;
};

// solve every node at driver displacement [rad for a rotational driver, mm otherwise].
// On failure the status names the connection, the driver position and the residual.
// InputError for an invalid request (Request::validate).
// A fresh workspace away from the drawing is assembled by continuation from the drawing;
// `drawing` (a workspace after solve_drawing) saves solving the drawing again.
Status solve(const Mechanism& mech, Workspace& ws, double driver, const Request& request,
             const Workspace* drawing = nullptr);

// one point with the variables of node `node` given, as jets in the driver (`node_vars`, in
// the node's variable order), instead of solved: the plan step that solves the node is
// skipped, the later steps solve the rest against it (a lever whose pose the caller already
// has, e.g. interpolated from solves of its own). That step must solve nothing but the node
// and contact parameters; those parameters are not used by any other step, and keep their
// last solved values (so no contact outputs: request.contacts must be false). One step from
// the workspace's last point (which must be a solved point at these controls), under the
// trust check but without halving: a rejected step returns a Status, the workspace keeps its
// last point, and a solve() from there takes the step in full. InputError when the node
// cannot be prescribed (can_prescribe), node_vars is not one jet per variable of the node,
// the request asks for contacts, or the workspace has no solved point yet.
Status solve_prescribed(const Mechanism& mech, Workspace& ws, double driver, const Request& request, int node,
                        std::span<const Jet3> node_vars);

// one point near a solved one, to probe between the points of a sweep: the workspace (at
// the solved point's controls) is set to the solved point - every variable's jet `near` at
// driver `near_driver` [rad or mm], as Workspace::vars after that solve - and `driver` is
// solved in one step from its taylor prediction: no continuation, no step halving, no
// branch guard beyond the trust radius (the caller keeps the step a fraction of a sweep
// step, so a single newton correction stays on the branch). A solved variable farther than
// its trust radius from the prediction returns a Status naming it (another branch, or the
// contact left its surface). InputError when `near` is not one jet per variable or the
// request is invalid.
Status solve_near(const Mechanism& mech, Workspace& ws, double near_driver, std::span<const Jet3> near,
                  double driver, const Request& request);

// whether solve_prescribed can take `node` (the plan step that solves it solves nothing else
// but its contacts' parameters)
bool can_prescribe(const Mechanism& mech, int node);

// the drawing's setting: driver 0 [rad or mm] and every control at its default. A fresh
// workspace asked for any other point is assembled by continuation from the drawing.
bool at_drawing(const Mechanism& mech, const std::vector<double>& controls, double driver);

// the drawing (driver 0, every control at its default) solved in `ws` with derivatives: the
// start of every continuation. A control sweep solves it once per thread and passes it to
// solve() for each position.
Status solve_drawing(const Mechanism& mech, Workspace& ws);

}  // namespace camopt::kin
