#pragma once
// the kernel's side of a kin::Workspace: per-variable buffers, the blocks of the plan steps
// (broyden inverses, LU factors, jacobian history), pose caches, warm starts and the step
// control. Private to src/kinematics: the Workspace holds it through a handle, and the kernel
// reaches it with state(ws). Nothing here allocates once the workspace is built.
#include <Eigen/Core>
#include <tuple>
#include <vector>

#include "camopt/core/jet.hpp"
#include "camopt/kinematics/detail/geometry.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/small_lu.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::kin::detail {

struct WorkspaceState {
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
};

// the kernel's access to a workspace's state (Workspace's only friend)
struct WorkspaceAccess {
  static WorkspaceState& of(Workspace& ws) noexcept { return *ws.state_.get(); }
  static const WorkspaceState& of(const Workspace& ws) noexcept { return *ws.state_.get(); }
};
inline WorkspaceState& state(Workspace& ws) noexcept { return WorkspaceAccess::of(ws); }
inline const WorkspaceState& state(const Workspace& ws) noexcept { return WorkspaceAccess::of(ws); }

}  // namespace camopt::kin::detail
