#pragma once
// the designed cam contact as the optimiser sees it: every quantity the constraints need
// at one cam angle, as an explicit function of the valve motion there (lift and its first
// two derivatives), with its exact gradient.
//
// the target motion is inverted through the downstream part of the mechanism
// (synthesis::MechanismCut) by the kinematic solver, driven by the valve: it gives the
// follower coordinate q(L) and dq/dL .. d3q/dL3 (implicit differentiation, exact). the
// follower motion in cam angle follows by the chain rule, q' = Q1 L', q'' = Q2 L'^2 +
// Q1 L''; the cam node's motion psi(theta) comes from the upstream part (it does not
// depend on the lift). the contact then follows from envelope theory in closed form:
//   roller / pad of radius r, centre w = c - O relative to the cam pivot:
//     pitch-curve tangent and curvature in the cam frame (rotation-invariant form)
//       P1 = w' - psi' J w,   P2 = w'' - psi'' J w - 2 psi' J w' - psi'^2 w,
//       kappa_p = s (P1 x P2) / |P1|^3,  s = sign(w x P1)
//     cam radius of curvature rho = 1/kappa_p - r (Chakraborty & Dhande, Kinematics and
//     Geometry of Planar and Spatial Cam Mechanisms, ch. 3), perfect-rolling roller spin
//     relative to its carrier  omega = s |P1| / r + psi' - (carrier rotation rate);
//   flat face with unit normal nu (cam -> follower), support function h = (g - O) . nu,
//     normal angle beta in the cam frame: rho = h + h_bb (the envelope of a line family),
//     h_b = h'/beta', h_bb = (h'' beta' - h' beta'') / beta'^3, contact x = O + h nu + h_b J nu.
// pressure angle: between the normal and the direction of motion of the follower's trace
// point (roller or pad centre, else the contact point), as kin::solve reports it.
// normal force per unit valve force from virtual work: F_n / F_valve = 1 / (Q1 nu . dx/dq).
// entrainment: the contact point moves over the cam at (1 - r kappa_p) |P1| (the offset of
// the pitch curve) or rho (h + h_bb) times the face normal's turning rate relative to the cam.
// angles in rad; derivatives per cam radian of the driver.
#include <memory>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/dual.hpp"

namespace camopt::opt {

// a value and its gradient with respect to (L, L', L'') [per mm, per mm/rad, per mm/rad^2]
using Grad3 = Dual<3>;

enum class FollowerShape { roller, pad, flat };

struct ContactQuantities {
  Grad3 pressure_angle;       // [rad], in [0, pi/2]
  Grad3 pitch_curvature;      // roller / pad: curvature of the centre path [1/mm], + convex; flat: 0
  Grad3 cam_radius;           // cam radius of curvature at the contact [mm], + convex (1/0 -> huge)
  Grad3 inverse_radius_sum;   // 1/R* = cam curvature + follower curvature [1/mm] (Hertz)
  Grad3 roller_speed;         // roller spin relative to its carrier, perfect rolling [rad per cam rad]
  Grad3 sliding;              // relative tangential speed of the material points [mm per cam rad]
  Grad3 force_ratio;          // contact normal force per unit valve force [-]
  Grad3 face_offset;          // flat face: contact offset along the face from its reference point [mm]
  // mean entrainment speed: the mean of the two surfaces' speeds relative to the contact
  // point, along the tangent perp(normal) [mm per cam rad]; the cam's is minus the contact
  // point's speed over the cam (rho_cam times the normal's turning rate relative to the cam),
  // the follower's that minus the sliding speed: u_e = u_cam - sliding / 2
  Grad3 entrainment;
};

// per-thread solver state of a CamContactModel (warm starts); movable
class ContactWorkspace {
 public:
  ContactWorkspace(ContactWorkspace&&) noexcept;
  ContactWorkspace& operator=(ContactWorkspace&&) noexcept;
  ~ContactWorkspace();

 private:
  friend class CamContactModel;
  struct State;
  explicit ContactWorkspace(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

class CamContactModel {
 public:
  // cuts the design at its designed cam contact (cam: "rotational" or "swing") and compiles
  // both halves; controls: every control [deg or mm] (empty: defaults). InputError when
  // the contact cannot be cut or the follower node is floating.
  CamContactModel(const DesignSpec& spec, std::vector<double> controls, const std::string& cam = "rotational");
  ~CamContactModel();
  CamContactModel(const CamContactModel&) = delete;
  CamContactModel& operator=(const CamContactModel&) = delete;

  ContactWorkspace make_workspace() const;
  // a workspace at other control positions (every control, design order)
  ContactWorkspace make_workspace(const std::vector<double>& controls) const;

  // the contact at driver angle cam_rad [rad] for valve motion lift[0..2] = L [mm],
  // dL/dtheta [mm/rad], d2L/dtheta2 [mm/rad^2]. a failing inversion returns its status.
  Status evaluate(double cam_rad, const double lift[3], ContactWorkspace& ws, ContactQuantities& out) const;

  FollowerShape follower_shape() const noexcept { return shape_; }
  double follower_radius_mm() const noexcept { return radius_; }
  const std::string& connection() const noexcept { return connection_; }
  const std::string& follower_node() const noexcept { return follower_node_; }
  const std::string& cam_node() const noexcept { return cam_node_; }
  const std::vector<double>& controls() const noexcept { return controls_; }
  // materials and width of the contact from the design ("" / 0 when not given)
  const std::string& material_cam() const noexcept { return material_cam_; }
  const std::string& material_follower() const noexcept { return material_follower_; }
  double width_mm() const noexcept { return width_; }
  // flat face: usable half-width of the face (0: not given)
  double face_half_width_mm() const noexcept { return half_width_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  FollowerShape shape_ = FollowerShape::roller;
  double radius_ = 0.0;
  std::string connection_, follower_node_, cam_node_, material_cam_, material_follower_;
  double width_ = 0.0, half_width_ = 0.0;
  std::vector<double> controls_;
};

}  // namespace camopt::opt
