#pragma once
// the motion of a floating swing cam (the intermediate lever of a Valvetronic-type system)
// that the rotational driver moves through one cam contact on a roller of the lever.
//
// Without that contact the lever's other contacts leave it one degree of freedom, whatever
// the driver does. So the lever is scanned once against the travel q of a radial probe on
// that roller (detail/radial_probe.hpp): kinematics with exact jets in q at scan points
// kLeverPathStep apart, septic hermite between them. At a driver angle theta the cam
// contact is then two equations in q and the cam's contact parameter u (the roller centre
// on the cam's offset curve, in the cam's turning frame), solved by newton; their jets in
// theta follow order by order (implicit differentiation, Faa di Bruno). This replaces a
// solve of the lever's whole contact cluster at every upstream node of the synthesis.
#include <array>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/hermite.hpp"

namespace camopt::synthesis {

struct LeverPath {
  int contact = -1;             // the driver's cam contact in the upstream mechanism (-1: no lever path)
  int lever_node = -1;          // the swing cam (floating) in the upstream mechanism
  double centre_offset = 0.0;   // the roller's radius: its centre's offset from the cam curve [mm]
  std::array<double, 2> roller{};     // the roller's centre on the lever, drawing [mm]
  std::array<double, 2> probe_at{};   // the probe's line: through the drawing roller centre [mm]
  std::array<double, 2> direction{};  // ... along the cam pivot's radial direction (unit)
  double q_first = 0.0;         // [mm] probe travel of the first scan point
  double step = 0.0;            // [mm] between scan points
  // septic hermite pieces in q between the scan points, from each point's value and three
  // derivatives in q of five fields: the lever's three variables in the upstream mechanism
  // (x, y [mm], phi [rad]), then its roller's centre (global x, y [mm])
  SepticPieces pieces{5};
};

// the lever path of `lever` (a floating node of the upstream mechanism `up`, compiled from
// `upstream`) at the control positions `controls`. out.contact stays -1 when the upstream is
// not of that form (the driver touches the lever through anything but one cam contact on a
// lever roller, the lever is not held by its other contacts, or one of them is a profile
// table, which leaves the lever's pose too rough for the path's steps): the caller then
// solves the upstream whole. A Status when the scan fails.
Status build_lever_path(const DesignSpec& upstream, const kin::Mechanism& up, int lever,
                        const std::vector<double>& controls, LeverPath& out);

// where the lever was last found: the probe travel q [mm] and the cam's contact parameter u
// as jets in the driver angle at theta [rad] (newton's start at the next angle)
struct LeverState {
  double theta = 0.0;
  Jet<3> q{0.0}, u{0.0};
};

// the lever's three variables as jets in the driver angle theta [rad], newton started from
// `state`, which is moved to theta. `ws`: a solved workspace of `up` (its pivots). A Status
// when newton fails or the travel leaves the scan.
Status lever_at(const LeverPath& path, const kin::Mechanism& up, const kin::Workspace& ws, double theta,
                LeverState& state, Jet<3> out[3]);

// the state of the upstream workspace `ws` as solved at driver angle theta (its values only)
void lever_path_state(const LeverPath& path, const kin::Mechanism& up, const kin::Workspace& ws, double theta,
                      LeverState& state);

}  // namespace camopt::synthesis
