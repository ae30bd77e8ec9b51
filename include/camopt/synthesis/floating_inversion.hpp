#pragma once
// inversion of a target motion through a downstream part whose follower (the body carrying
// the roller on the cam under design) is a floating lever held by other contacts, as the
// intermediate lever of a Valvetronic-type system.
//
// The valve lift alone does not fix such a lever: while its working curve's idle arc slides
// past the next roller (idle travel) the lever moves and the valve does not, so the solve
// driven by the valve is singular there. Instead the lever is parameterised by the travel q
// of its cam roller's centre along the cam's radial direction in the drawing (a probe face
// pushing the roller; the lever's other contacts fix the rest of its pose, solved by the
// kinematics with exact jets in q):
//   1. the probe mechanism is placed through the lever's rest pose (its cam roller on the
//      base circle), and L(q) with the roller's centre is scanned from the rest (q = 0) up
//      past the target's largest lift (detail/floating_scan.hpp);
//   2. L(q) is split into monotone pieces at its turning points (a Valvetronic lever's
//      valve lift first dips while the idle arc slides past the finger roller, then rises);
//   3. from the target's peak back along the opening stroke and on along the closing one
//      the lever's travel falls: each sample is inverted on the piece the lever is on
//      (safeguarded newton; jets by series reversion of L(q) composed with L(theta)),
//      moving to the previous piece where the target turns back at that piece's turning
//      lift (else the lift does not fix the lever: a Status naming the angle), down to
//      the rest (q = 0, the base circle) where the target reaches the lever's rest lift;
//   4. samples where dL/dq is too small to invert (next to a turning point or the rest)
//      are bridged by septic hermite pieces in theta between their neighbours' q jets;
//      the lever's lift there misses the target by at most fill_error_mm (reported).
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::synthesis {

struct FloatingInversion {
  std::vector<Jet<3>> centre_x, centre_y;  // follower surface centre, global [mm], jets in the cam angle
  double rest_lift = 0.0;       // [mm] the lever's lift at rest (q = 0)
  double rest_travel_mm = 0.0;  // cam-roller travel on the base circle when the target never reaches rest_lift
  double fill_error_mm = 0.0;   // largest |L(q) - target| where q is bridged [mm]
  double fill_error_at_rad = 0.0;
  std::string fill_span;        // how many samples rest, how many are bridged
};

// motion: the target L at each theta [rad] as jets in theta (internal unit of target_node).
// InputError when the follower is not a circle (roller or pad); a Status when the lever
// cannot be solved, the target leaves the lever's reach or the fill cannot meet the branch.
Status invert_floating_follower(const DesignSpec& spec, const MechanismCut& cut, const std::string& target_node,
                                const std::vector<double>& controls, const std::vector<double>& theta,
                                const std::vector<Jet<3>>& motion, FloatingInversion& out);

}  // namespace camopt::synthesis
