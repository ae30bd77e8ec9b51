#pragma once
// the mechanism animation of a run (report_data.hpp, Scene): every body drawn to scale in
// drawing coordinates from the design, and per control position and driver angle every
// body's pose, every contact's point and normal and the output node's lift, solved by the
// kinematics kernel (kin::solve; nothing here computes kinematics of its own).
//
// bodies: the mechanism's nodes in Mechanism::nodes order (ground first), then one body per
// link or crank-slider connection (its bar, named after the connection) and one per pivot
// moved by a control (the carrier that turns the pivot about its centre, "<node> pivot").
// shapes (SceneShape::role): cam and swing-cam profiles ("profile": a polygon of the whole
// profile on the driver or where the contacts sweep it all round, else an open polyline over
// the part they sweep plus a margin), discs, pads and circles ("profile"), rollers
// ("roller"), flat faces ("profile": the swept contact extent plus a margin, at least the
// face's half-width), ground guides ("profile": the swept arc), link bars and lever
// skeletons ("lever": the pivot or reference joined to each feature), pivots and pins
// ("pivot"), the valve stem and head ("valve", a translational node with a seat), the valve
// seat ("seat", on ground) and springs ("spring", from a ground seat point to the point of
// the body they push).
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/report/report_data.hpp"

namespace camopt::report {

struct SceneRequest {
  // the run's positions of the design's first control [deg or mm], one ScenePosition each
  // (the other controls at their defaults, as `camopt kinematics --control`); empty: the
  // control's default. A design without a control takes nothing or {0}.
  std::vector<double> controls;
  // the driver sweep [deg, or mm for a translating driver], both ends included (the last step
  // may be short), as `camopt kinematics --step`
  double start_deg = 0.0, stop_deg = 360.0, step_deg = 1.0;

  // InputError naming the field, its value and the rule it breaks (one rule per line)
  void validate(const kin::Mechanism& mech) const;
};

// the scene of `mech` compiled from `spec`. ScenePosition::lift_mm is the lift column of
// `camopt kinematics` bit for bit: lift_mm, or lift_deg for a rotating output node.
// InputError for an invalid request; a position whose kinematics fail throws NumericalError
// naming the angle and the control position.
Scene build_scene(const DesignSpec& spec, const kin::Mechanism& mech, const SceneRequest& request);

}  // namespace camopt::report
