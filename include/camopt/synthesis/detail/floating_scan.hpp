#pragma once
// steps 1 and 2 of the inversion through a floating follower (floating_inversion.hpp): the
// probe mechanism through the lever's rest pose, the scan of the lift L(q) and the roller
// centre against the probe travel q, and the monotone pieces of L(q) between its turning
// points (floating_scan.cpp). The walks that invert the target on those pieces are in
// floating_inversion.cpp.
#include <array>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::synthesis::detail {

// probe travel per scan step [mm] and the slope, relative to the mean slope of the lift
// over the scan, below which L(q) counts as flat (idle travel): at a quadratic ramp foot
// the lift there is ~ 1e-8 of the full lift. 0.04 mm: the bundled Valvetronic input cam
// is within 1.4e-7 mm of the 0.01 mm scan's, its round trip 3.15e-8 mm against 3.13e-8 mm
// (the round trip holds up to 0.07 mm; at 0.08 mm it stops at the cam's rest junction)
inline constexpr double kScanStep = 0.04;

// the follower's surface of the designed contact, checked: a circle (roller or pad) on a
// floating lever against a rotational cam, not centred on the cam pivot (InputError
// otherwise)
struct FloatingRoller {
  const SurfaceSpec* surface = nullptr;  // the roller on the lever (drawing)
  double px = 0.0, py = 0.0;             // [mm] the cam pivot
  double base = 0.0;                     // [mm] roller centre from the cam pivot on the base circle
};
FloatingRoller floating_roller(const DesignSpec& spec, const MechanismCut& cut);

// the downstream half with a radial probe (detail/radial_probe.hpp) on the roller, driven
// by the probe, pushing through the lever's rest pose: its cam roller on the base circle
Status probe_through_rest(const MechanismCut& cut, const FloatingRoller& roller, const std::string& target_node,
                          const std::vector<double>& controls, kin::Mechanism& out);

// L(q) and the roller centre with three derivatives in q at scan points kScanStep apart from
// the rest, up past the target's peak: septic hermite pieces between them, a solve beyond
class LeverScan {
 public:
  // the probe mechanism of probe_through_rest at the controls
  LeverScan(kin::Mechanism probe, const std::vector<double>& controls, const MechanismCut& cut,
            const FloatingRoller& roller, const std::string& target_node);

  // the scan up past motion_hi, the target's largest lift [mm]
  Status run(double motion_hi);

  // the lift and the roller centre at travel q [mm] as jets in q
  Status at(double q, Jet<3>& lift, kin::V2<Jet<3>>& centre);

  std::vector<double> lift;                      // [mm] L at each scan point
  std::vector<std::array<double, 12>> jets;      // [L, centre x, centre y][derivative 0..3] at each
  SepticPieces pieces{3};                        // between scan points
  int top = 0;                                   // the last scan point
  const std::string& follower_name() const { return cut_.follower_node; }

 private:
  kin::V2<Jet<3>> centre_in(const kin::Workspace& w) const;

  const kin::Mechanism m_;
  kin::Workspace ws_;  // solves of the whole mechanism (the scan's, and those beyond it)
  const MechanismCut& cut_;
  int lift_var_ = -1, follower_ = -1;
  double c0x_ = 0.0, c0y_ = 0.0;  // [mm] the roller centre in the drawing

  friend class LeverScanner;
};

// the monotone pieces of L(q) between its turning points: piece k runs from turn_q[k] to
// turn_q[k + 1] [mm] (ascending) with the lift turn_lift there [mm]
struct LiftPieces {
  std::vector<double> turn_q, turn_lift;
  int count() const { return static_cast<int>(turn_q.size()) - 1; }
};

// cannot_assemble when the last piece falls towards the target's peak
Status monotone_pieces(const LeverScan& scan, double motion_hi, LiftPieces& out);

}  // namespace camopt::synthesis::detail
