#pragma once
// envelope-theory synthesis of a cam profile from a target valve lift (SAE 2010-01-1193,
// "cam lobe solution algorithm"; Chakraborty & Dhande, Kinematics and Geometry of Planar
// and Spatial Cam Mechanisms, ch. 3). synthesize() runs these steps (each a named function
// of detail/envelope_steps.hpp, in the file named):
//
// 1. cut (cut_and_compile, envelope.cpp): the designed contact (a profile on the cam node
//    against a roller, pad or flat face on the follower) is cut out of the mechanism; the
//    rest splits into the upstream part (driver -> cam node) and the downstream part
//    (follower -> valve);
// 2. inversion (invert_downstream, downstream_inversion.cpp): the downstream part is driven
//    by the valve at the target lift L(theta), and the follower's motion comes out as jets
//    in the valve travel, composed with the jets of L(theta) (Faa di Bruno) into exact jets
//    in the cam angle; a floating follower (an intermediate lever) is inverted through its
//    cam roller's travel instead (floating_inversion.hpp). The cam's own motion comes from
//    the upstream part (solve_cam_motion, cam_motion.cpp), and both give the follower in
//    the profile frame (trace_follower, follower_path.cpp);
// 3. envelope (envelope_of_follower, envelope.cpp): the follower surface is taken into the
//    profile frame of the cam node; a roller or pad gives the offset of its centre path
//    (p = c - r nu), a flat face the envelope of its lines (F = (x - q).n = 0,
//    dF/dtheta = 0: p = q + t (q'.n)/(t.n')); it must wind once round without folding back
//    (check_winding);
// 4. resampling (resample_polar, polar_resampling.cpp): the envelope, sampled with its first
//    two derivatives, is resampled by quintic hermite interpolation in theta at polar angles
//    no further apart than the resolution in polar angle, cam angle or tangent turn, giving
//    the polar table.
//
// A swing cam is traced over a stretch of its profile only: steps 3 and 4 are then
// swing_profile (swing_profile.cpp), with the follower's rest over the control range from
// idle_family (idle_family.cpp).
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/synthesis/undercut_windows.hpp"

namespace camopt::synthesis {

struct SynthesisOptions {
  std::string cam = "rotational";  // "rotational": the driver's profile; "swing": a profile on another rotational node or a floating lever
  std::vector<double> controls;    // every control [deg or mm]; empty = defaults
  // resolution of the profile table: neighbouring points are at most 360 / points deg
  // apart in polar angle, in cam angle and in turn of the tangent (so a sharp nose or a
  // short swing-cam stretch gets more points than a uniform polar table would give it)
  int points = 1440;
  // envelope samples per revolution of the driver (>= points); raised to a multiple of the
  // target's knot count when its knots are uniform from 0, so no sample interval straddles
  // a knot of the target
  int samples = 1440;
  double wheel_radius_mm = 0.0;    // grinding wheel radius; concave radii must be >= it (0: no check)
  // smallest allowed radius of curvature [mm]: reported against; a swing cam's untouched nose
  // beyond its traced stretch keeps its convex radius >= this and >= the roller's
  double min_radius_mm = 0.0;
  std::string target_node;         // node whose motion is the target (empty: the valve, design.output_node)
  // a swing cam whose traced stretch folds back: bisect the valve-lift target's scale for the
  // largest that synthesizes and give it in the message (swing_remedy.hpp; ~9 more syntheses)
  bool remedies = true;

  // throws InputError naming the field, its value and the rule it breaks (one rule per check)
  void validate() const;
};

struct SynthesisResult {
  ProfileSpec profile;  // the new polar table, same name and placement as the profile it replaces
  std::string connection, cam_node, follower_node, follower_shape;
  std::vector<double> angle_deg, radius_mm, x_mm, y_mm, radius_of_curvature_mm;  // per polar point
  double base_radius_mm = 0, max_radius_mm = 0;
  double min_radius_of_curvature_mm = 0, min_radius_of_curvature_at_deg = 0;  // convex (> 0) minimum
  bool has_concave = false;
  double min_concave_radius_mm = 0, min_concave_radius_at_deg = 0;  // smallest |radius| of concave parts
  bool concave_narrower_than_wheel = false;
  // where a concave radius is below the grinding wheel's, and where |radius of curvature| is
  // below options.min_radius_mm: windows in profile angle [deg], worst the smallest |radius| [mm]
  std::vector<FailureWindow> concave_below_wheel, below_min_radius;
  double face_offset_min_mm = 0, face_offset_max_mm = 0;  // flat face: contact offset along the face
  int upstream_solves = 0;  // work: kinematic solves of a cam that is not the driver (1 per deg where it moves)
  std::vector<std::string> notes;
};

// throws InputError for bad options (SynthesisOptions::validate) or a design that cannot be
// synthesized (no such cam, unsupported follower shape); returns a Status for numerical failures (inversion fails, undercut)
// with the cam angle where it happened
// lift_of_cam_rad: the target node's displacement against the driver angle [rad], in the
// node's internal unit (mm for a translational node, rad for a rotational one)
Status synthesize(const DesignSpec& spec, const PeriodicSpline& lift_of_cam_rad, const SynthesisOptions& options,
                  SynthesisResult& result);

// the design with the profile replaced by `profile` and every lash set to zero
DesignSpec with_profile(const DesignSpec& spec, const ProfileSpec& profile);

struct RoundTrip {
  double max_error_mm = 0, max_error_at_deg = 0, rms_error_mm = 0;
  double max_pressure_angle_deg = 0, max_pressure_angle_at_deg = 0;
};

// forward kinematics of `spec` (the synthesized design) against the target motion of
// target_node (empty: the valve lift from its rest position); errors in mm or rad.
// InputError when target_node is not a node of spec
Status round_trip(const DesignSpec& spec, const PeriodicSpline& lift_of_cam_rad, const std::vector<double>& controls,
                  const std::string& connection, RoundTrip& out, const std::string& target_node = "");

// grinding table: lift of a master roller of radius master_radius_mm (0: a flat master)
// translating along the profile frame's +x axis through the cam centre, as the cam turns
// counter-clockwise [cam deg, 0 .. 360 - step] -> [mm above the base circle]. InputError
// when master_radius_mm is negative or step_deg is not in (0, 360)
Status grinding_table(const ProfileSpec& profile, double master_radius_mm, double step_deg, std::vector<double>& cam_deg,
                      std::vector<double>& lift_mm);

}  // namespace camopt::synthesis
