#pragma once
// position, velocity, acceleration and jerk of every node at one driver position.
// kernel: solve(const Mechanism&, Workspace&, driver value, request). Derivatives are
// taylor coefficients with respect to the driver [per rad or per mm of driver], exact:
// closed forms run on jets, implicit blocks use implicit differentiation J x_k = -r_k.
#include <Eigen/Core>
#include <cmath>
#include <span>
#include <memory>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/kinematics/detail/geometry.hpp"
#include "camopt/kinematics/mechanism.hpp"

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

class Workspace;

namespace detail {
// the kernel's per-workspace buffers, warm starts, pose caches and step control: private to
// src/kinematics (workspace_state.hpp), reached through WorkspaceAccess
struct WorkspaceState;
struct WorkspaceAccess;
// owns a WorkspaceState and copies it deeply, so that a Workspace copies like a value
class WorkspaceStateHandle {
 public:
  WorkspaceStateHandle();
  WorkspaceStateHandle(const WorkspaceStateHandle& other);
  WorkspaceStateHandle(WorkspaceStateHandle&& other) noexcept;
  WorkspaceStateHandle& operator=(const WorkspaceStateHandle& other);
  WorkspaceStateHandle& operator=(WorkspaceStateHandle&& other) noexcept;
  ~WorkspaceStateHandle();
  WorkspaceState* get() const noexcept { return state_.get(); }

 private:
  std::unique_ptr<WorkspaceState> state_;
};
}  // namespace detail

// what kin::solve needs besides the model: the results a caller reads, and the kernel's own
// buffers behind state_ (nothing allocates in the per-point loop)
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

  // pivot of every node at the current controls, drawing frame [mm] (the pivots of
  // node_pose), placed by the first solve after set_controls
  const std::vector<Eigen::Vector2d>& pivots() const noexcept;
  // every variable's value at the last point solved [rad or mm], as one array (for node_pose
  // on values)
  const std::vector<double>& values() const noexcept;
  // per plan step: its lash gap open at the last point
  const std::vector<bool>& lash_open() const noexcept;

 private:
  friend struct detail::WorkspaceAccess;
  std::vector<double> controls_;
  detail::WorkspaceStateHandle state_;  // the kernel's buffers
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
