#pragma once
// CamProblem's rows that need the loads (separation speed, contact force, spring margin, cam
// torque, Hertz load, EHL film) and the one source those loads come from: the design's own
// rigid model (DownstreamLoads), or a constraint set's [load] for a design without dynamics
// data or with load.override_design = true. A set whose [load] or [oil] disagrees with its
// design without override_design is an InputError naming both files and keys.
//
// every row is a function of the valve motion (L, L', L'') at one grid angle with its exact
// gradient (Grad3), and of the cam contact's force ratio (rotational cam: a Grad3 from
// CamContactModel; swing cam: a value, its sensitivity returned for the caller's u-row).
#include <memory>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/opt/cam_contact.hpp"
#include "camopt/opt/downstream_loads.hpp"
#include "camopt/opt/optimization_spec.hpp"
#include "camopt/opt/problem.hpp"

namespace camopt::opt::detail {

struct LoadRowSpec {
  ConstraintKind kind;
  int item = 0;  // separation, spring margin: the contact (contact_names()); margin: contact * springs + spring
};

struct LoadRowValue {
  Grad3 g;               // normalised, <= 0 feasible
  double physical = 0.0; // in unit_of(kind)
  double d_ratio = 0.0;  // dg / d(force ratio) at fixed motion
};

class LoadRows {
 public:
  // omega: cam speed at the set's rpm [rad/s]; controls: per control position (swing: every
  // position; rotational: one)
  LoadRows(const DesignSpec& design, const OptimizationSpec& spec, const CamContactModel& contact, double omega,
           const std::vector<std::vector<double>>& controls);
  ~LoadRows();

  // the rows at every grid angle where the valve is off its seat
  const std::vector<LoadRowSpec>& point_rows() const noexcept { return rows_; }
  // the loads at one grid angle (once per angle, before row() and cam_force())
  Status prepare(double cam_rad, const double lift[3], int position);
  // the cam contact's generalized force at the set's speed [N] (times the force ratio: the normal force)
  Grad3 cam_force() const;
  LoadRowValue row(const LoadRowSpec& r, const Grad3& force_ratio, const ContactQuantities* contact) const;

  // contact data for Hertz and the film: E* [MPa], line length [mm]; 0 when unknown
  double e_star_MPa() const noexcept { return e_star_MPa_; }
  double width_mm() const noexcept { return width_mm_; }
  // where the loads come from, and what the set overrides
  const std::string& source() const noexcept { return source_; }
  const std::vector<LoadOverride>& overrides() const noexcept { return overrides_; }
  const std::vector<std::string>& contact_names() const noexcept { return contacts_; }
  const std::vector<std::string>& spring_names() const noexcept { return springs_; }

 private:
  void check_set_against_design(const DesignSpec& design, const OptimizationSpec& spec, const CamContactModel& contact);
  void contact_data(const DesignSpec& design, const OptimizationSpec& spec, const CamContactModel& contact);
  void build_rows(const OptimizationSpec& spec);
  OptimizationSpec spec_;
  std::unique_ptr<DownstreamLoads> design_;
  std::vector<LoadWorkspace> ws_;
  std::vector<ContactLoad> loads_;
  std::vector<std::string> contacts_, springs_;
  std::vector<double> reference_;  // per contact: force scale of its rows [N]
  std::vector<LoadRowSpec> rows_;
  std::vector<LoadOverride> overrides_;
  std::string source_;
  OilSetSpec oil_;  // the film's oil: the set's or the design's
  double omega_ = 0.0, crank_per_cam_ = 2.0;
  double e_star_MPa_ = 0.0, width_mm_ = 0.0;
  double lift_[3] = {0, 0, 0};
};

}  // namespace camopt::opt::detail
