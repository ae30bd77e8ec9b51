#pragma once
// the steps of envelope synthesis (envelope.hpp), each in its own source file:
//   envelope.cpp            synthesize(): the steps in order; the cut, the target's samples,
//                           the envelope of a rotational cam and its winding check
//   downstream_inversion.cpp  inversion: the follower as a function of the target motion
//   cam_motion.cpp          the cam's motion from upstream solves, interpolated in the driver angle
//   follower_path.cpp       the follower (centre, or face point and normal) in the cam's profile frame
//   idle_family.cpp         a swing cam's resting follower over the control range
//   swing_profile.cpp       a swing cam's profile: the traced stretch, its rest side and the bridge
//   polar_resampling.cpp    resampling of an envelope into the polar table
// Angles are radians throughout; lengths mm.
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/kinematics/pose.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/detail/fold_status.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "camopt/synthesis/floating_inversion.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::synthesis::detail {

using Jet3 = Jet<3>;
using Jet2 = Jet<2>;

// a number for a message, 6 significant digits
inline std::string fmt(double v) { return format_value(v, 6); }

// d/dt of a jet, one order lower
inline Jet2 derivative_of(const Jet3& x) {
  Jet2 d;
  for (int k = 0; k < 3; ++k) d.c[k] = (k + 1) * x.c[k + 1];
  return d;
}

// v^1.5 [mm^3]: the denominator of a curvature from a squared speed v
inline double curvature_denominator(double v) { return v * std::sqrt(v); }

// the placement of the designed profile on the cam node: origin (ox, oy) [mm] and the
// cosine and sine of its orientation in the cam's drawing
struct ProfileFrame {
  double ox = 0.0, oy = 0.0, co = 1.0, so = 0.0;

  // a global point into the profile frame, for the cam at pose `cam`: global -> cam
  // drawing -> profile frame
  P2<Jet3> point(const kin::Pose<Jet3>& cam, const kin::V2<Jet3>& g) const {
    const Jet3 dx = g.x - cam.tx, dy = g.y - cam.ty;
    const Jet3 lx = cam.rx + cam.c * dx + cam.s * dy - ox;
    const Jet3 ly = cam.ry - cam.s * dx + cam.c * dy - oy;
    return P2<Jet3>{co * lx + so * ly, -so * lx + co * ly};
  }
  // a global direction into the profile frame
  P2<Jet3> direction(const kin::Pose<Jet3>& cam, const kin::V2<Jet3>& v) const {
    const Jet3 lx = cam.c * v.x + cam.s * v.y, ly = -cam.s * v.x + cam.c * v.y;
    return P2<Jet3>{co * lx + so * ly, -so * lx + co * ly};
  }
};

// ---- step 1: the cut ----

// the designed contact cut out of the mechanism, and both halves compiled at the controls:
// up (driver -> cam node) and down (driven by the target node -> follower)
struct Halves {
  Halves(kin::Mechanism up_mech, kin::Mechanism down_mech)
      : up(std::move(up_mech)), down(std::move(down_mech)), up_ws(up), down_ws(down) {}

  std::string target_node;  // whose motion is the target
  MechanismCut cut;
  const SurfaceSpec* cam_surface = nullptr;       // the profile's surface (in the caller's spec)
  const SurfaceSpec* follower_surface = nullptr;  // the follower's surface (in the caller's spec)
  bool floating_follower = false;  // a floating lever: inverted through its cam roller (floating_inversion.hpp)
  bool needs_downstream = false;   // down is compiled (a conventional follower, or a swing cam's idle family)
  kin::Mechanism up, down;
  kin::Workspace up_ws, down_ws;
  std::vector<double> controls;  // every control [deg or mm]
  int cam = -1;                  // the cam node in up
  int follower = -1;             // the follower node in down (-1: down not compiled)
  int cam_angle_variable = -1;   // the cam's angle in up: its one variable, or a floating lever's phi
  bool roller = false;           // the follower is a circle (roller or pad), else a flat face
  double radius = 0.0;           // [mm] the circle's radius
  ProfileFrame frame;
};

// cut the designed contact out of spec and compile both halves (InputError: no such cam,
// a driver that is not rotational)
Halves cut_and_compile(const DesignSpec& spec, const SynthesisOptions& options);

// ---- the target motion, sampled ----

struct TargetSamples {
  int n = 0;                  // samples per revolution of the driver
  std::vector<double> theta;  // [rad] 2 pi i / n
  std::vector<Jet3> motion;   // the target L(theta) as jets in theta [mm or rad]
  double lo = 0.0, hi = 0.0;  // its range
};

TargetSamples sample_target(const PeriodicSpline& lift, int requested_samples);

// ---- step 2: inversion ----

// the follower as a function F(L) of the target motion: septic hermite pieces in L between
// solves of the downstream half at levels across L's range, or (a floating follower) its
// roller centre at every sample (floating_inversion.hpp)
struct FollowerInverse {
  bool floating = false;       // through_lever holds the follower
  bool invert_centre = false;  // the fields are a roller's centre (global x, y), else the follower's variables
  int fields = 0;              // functions of L interpolated: 2 (centre x, y) or the follower's dof
  int first_variable = -1;     // the follower's first variable in down
  int levels = 0;
  double motion_lo = 0.0, level_step = 0.0;  // the lowest level and the spacing [mm or rad]
  SepticPieces pieces{1};      // the fields between levels
  FloatingInversion through_lever;
};

// notes of a floating follower's inversion go to result.notes
Status invert_downstream(const DesignSpec& spec, Halves& halves, const TargetSamples& target, FollowerInverse& out,
                         SynthesisResult& result);

// ---- the cam's motion ----

// the cam node's variables as jets in the driver angle: the driver itself when the cam is
// the lone upstream body, else solved upstream at nodes (sample indices) and interpolated by
// septic hermite pieces between them
struct CamMotion {
  bool lone_driver = false;               // the cam is the driver and the only upstream body
  std::vector<double> driver_sin, driver_cos;  // the lone driver's pose at every sample
  int dof = 0;                            // the cam node's variables
  int first_variable = 0;
  std::vector<int> node_at;               // sample index of each upstream solve, ascending, the last n
  std::vector<double> values;             // [node][dof][derivative 0..3]
  SepticPieces pieces{1};                 // between nodes
  std::size_t interval = 0;               // cursor: the interval of the last sample asked for
  std::vector<Jet3> angle_at;             // a swing cam's angle at every sample (empty: interpolated on demand)

  // variable first_variable + k at sample i (samples asked for in ascending order)
  Jet3 at(int i, int k);
};

Status solve_cam_motion(Halves& halves, int n, CamMotion& out);

// a swing cam's angle and rate at every sample (its rate says which samples are needed);
// needed[i]: the cam moves at sample i
void swing_angle_at_samples(const Halves& halves, int n, CamMotion& cam, std::vector<double>& cam_rate,
                            std::vector<char>& needed);

// ---- the follower in the profile frame ----

struct FollowerPath {
  FollowerPath(int n, bool roller) : path(n), normal(roller ? 0 : n), cam_rate(n), valve_rate(n) {}

  std::vector<P2<Jet3>> path;    // follower centre (roller) or face point, profile frame [mm]
  std::vector<P2<Jet3>> normal;  // a flat face's unit normal, profile frame (empty for a roller)
  std::vector<double> cam_rate;  // [rad per rad of driver] the cam's angular rate
  std::vector<double> valve_rate;  // [mm per rad] dL/dtheta
};

// at every needed sample (all when needed is all 1): cam_rate must hold a swing cam's rate
// beforehand where a sample is not needed
void trace_follower(Halves& halves, const TargetSamples& target, const FollowerInverse& inverse, CamMotion& cam,
                    const std::vector<char>& needed, FollowerPath& out);

// ---- step 3: envelope (rotational cam) ----

// envelope points with their first two derivatives in theta: a roller's centre path
// offset along its normal, a flat face's envelope of lines
Status envelope_of_follower(const Halves& halves, const TargetSamples& target, const FollowerPath& follower,
                            std::vector<P2<Jet2>>& env, SynthesisResult& result);

// the envelope's unwrapped polar angle (n + 1 entries) and the sense in which it winds;
// an undercut Status where it folds back or does not wind once round
Status check_winding(const Halves& halves, const std::vector<P2<Jet2>>& env, const FollowerPath& follower,
                     std::vector<double>& phi, double& sign);

// ---- step 4: resampling (polar_resampling.cpp) ----

// samples of the envelope per revolution: at least `requested`, a multiple of the target's
// knot count when its knots are uniform from 0
int envelope_samples(const PeriodicSpline& target, int requested);

// an envelope point at a polar angle, between two samples, with derivatives per unit of the
// local parameter t in [0, 1]
struct PolarHit {
  double x, y, x1, y1, x2, y2;
};
PolarHit envelope_at_polar_angle(const P2<Jet2>& a, const P2<Jet2>& b, double phi_a, double phi_b, double h,
                                 double target);

// radius and its first two derivatives in polar angle (out[0..2])
void polar_derivatives(const PolarHit& p, double out[3]);

// polar angles of the profile table for a resolution `step` [rad]
std::vector<double> resolution_angles(const std::vector<P2<Jet2>>& env, const std::vector<double>& phi, double h,
                                      double step, bool closed);

// profile quantities of a polar table r(phi) with its dr/dphi and d2r/dphi2 at every point
void finish_from_polar(SynthesisResult& result, double wheel_radius, const std::vector<double>& dr,
                       const std::vector<double>& ddr);

// the closed envelope of a rotational cam resampled into the result's polar table, with its
// curvature, extreme radii and the profile
void resample_polar(const std::vector<P2<Jet2>>& env, const std::vector<double>& phi, double sign,
                    const SynthesisOptions& options, const std::string& profile_name, SynthesisResult& result);

// ---- a swing cam (idle_family.cpp, swing_profile.cpp) ----

// the resting follower's centre in the cam's profile frame at one control position, with
// its tangent d/dcontrol [mm, mm per control unit]
struct IdleCentre {
  double x, y, tx, ty;
};

// the resting follower's centres over the first control's range (and 10 % beyond each end);
// empty without controls, for a flat face or when the cam never rests. Takes over the
// halves' workspaces (their last use)
std::vector<IdleCentre> idle_family(Halves& halves, const PeriodicSpline& lift, const TargetSamples& target,
                                    const std::vector<double>& cam_rate);

// a swing cam's profile from the follower's path; folds: the traced stretch folds back for
// the target's shape (not its ripple)
Status swing_profile(const Halves& halves, const FollowerPath& follower, const std::vector<double>& theta,
                     const std::vector<IdleCentre>& idle_centres, const SynthesisOptions& options,
                     SynthesisResult& result, bool& folds);

}  // namespace camopt::synthesis::detail
