#pragma once
// the loads the designed cam contact, and every contact behind it, carry as functions of the
// valve motion, from the design's own dynamics data: the rigid, kinematically constrained
// model of `camopt dynamics --model rigid` (dynamics::compile_dynamics: masses with 1/3 of
// each spring mass, inertias, springs with their viscous dampers, gas force).
//
// The part downstream of the cam contact (follower -> valve) has one degree of freedom, the
// valve lift L, so by virtual work the cam must supply the generalized force (at L, per mm)
//     F(theta, omega) = S(L) + G(crank) x_g'(L) + D(L) L' omega + (M(L) L'' + N(L) L'^2) omega^2
// with M = sum m |cg_L|^2 + I phi_L^2 the generalized mass, N = M'/2, S = sum spring
// load(x_s) x_s', D = sum c x_s'^2 (the springs' dampers), x' = dx/dL from the kinematic
// solver's third-order jets of the downstream part driven by the valve (exact: the
// gradients with respect to L need d^3 x / dL^3). The contact's normal force is F times
// its force ratio (CamContactModel). A contact c behind the cam (a pad on the valve tip) is
// loaded by the bodies beyond it (on the valve's side): the same sums over those bodies give
// a force of the same sign as its normal force, so it opens where that sum reaches zero.
//
// left out: friction at the contacts and joints (the rigid model's Coulomb terms; on a
// translating flat tappet the cam's friction does no work on the tappet), and the
// upstream part (the camshaft's own inertia and a swing cam's drive).
// angles in rad, derivatives per cam radian; Grad3: gradient with respect to (L, L', L'').
#include <memory>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/opt/cam_contact.hpp"

namespace camopt::opt {

struct ContactLoad {
  Grad3 statics;              // springs and gas [N]
  Grad3 damping;              // per rad/s of cam speed [N s/rad]
  Grad3 inertia;              // per (rad/s)^2 of cam speed [N s^2/rad^2]
  std::vector<Grad3> spring;  // per DownstreamLoads::spring_names(): its part of statics [N]
  // the generalized force at cam speed omega [rad/s]
  Grad3 at(double omega) const { return statics + damping * omega + inertia * (omega * omega); }
};

// per-thread state (the downstream kinematic solve); movable
class LoadWorkspace {
 public:
  LoadWorkspace(LoadWorkspace&&) noexcept;
  LoadWorkspace& operator=(LoadWorkspace&&) noexcept;
  ~LoadWorkspace();

 private:
  friend class DownstreamLoads;
  struct State;
  explicit LoadWorkspace(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

class DownstreamLoads {
 public:
  // cam_kind as CamContactModel. InputError (naming the field) when the design lacks the
  // dynamics data of a downstream body (mass_kg, inertia_kg_mm2)
  DownstreamLoads(const DesignSpec& design, const std::string& cam_kind);
  ~DownstreamLoads();
  DownstreamLoads(const DownstreamLoads&) = delete;
  DownstreamLoads& operator=(const DownstreamLoads&) = delete;

  LoadWorkspace make_workspace(const std::vector<double>& controls) const;

  // the loads at cam angle cam_rad [rad] for valve motion lift[0..2] = L [mm], L' [mm/rad],
  // L'' [mm/rad^2]; out[0] the cam contact, out[k] contact_names()[k]
  Status evaluate(double cam_rad, const double lift[3], LoadWorkspace& ws, std::vector<ContactLoad>& out) const;

  // the cam contact, then the contacts behind it that one body set loads alone
  const std::vector<std::string>& contact_names() const noexcept { return contacts_; }
  // the springs of the downstream part (design names)
  const std::vector<std::string>& spring_names() const noexcept { return springs_; }
  // whether spring s loads contact k (it acts on a body the contact carries)
  bool carries(std::size_t contact, std::size_t spring) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::string> contacts_, springs_;
};

}  // namespace camopt::opt
