#pragma once
// a kinematic sweep over the driver range at one or more control positions (solved in
// parallel, one workspace per thread), and the per-position summary engineers read first.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::kin {

struct SweepSpec {
  double start = 0.0, stop = 360.0, step = 1.0;       // driver [deg or mm], both ends included
  std::vector<std::vector<double>> control_positions;  // each: every control [deg or mm]
  Request request;
  int threads = 1;  // worker threads (at most one per position; < 1 runs on the caller's thread)
  // progress hook; called from worker threads (an exception it throws reaches sweep()'s caller)
  std::function<void()> on_position_done;

  // InputError naming the field, its value and the rule it breaks (one rule per line)
  void validate() const;
};

// one control position: values and derivatives per driver unit (deg or mm) of every
// variable at every driver point; value(point, v, k) is the k-th derivative (k = 0..3) of
// variable v [deg or mm per driver deg^k or mm^k], output_lift() the output node's lift
struct PositionResult {
  std::vector<double> controls;
  std::size_t variables = 0;  // mechanism variables per point
  Status status;
  std::vector<double> data;
  std::vector<ContactState> contacts;  // [point * connections + c] (request.contacts)
  std::vector<double> condition;       // largest block condition estimate per point
  // per point: bit s set while plan step s holds a lash gap open (steps from 63 on share bit 63)
  std::vector<std::uint64_t> lash_open;
  // per point: the smallest toggle margin on the way to it (Workspace::path_margin) and
  // where [driver deg or mm]
  std::vector<double> toggle_margin, toggle_margin_at;
  SolveStats stats;

  double value(std::size_t point, int variable, int order = 0) const {
    return data[(point * variables + static_cast<std::size_t>(variable)) * 4 + static_cast<std::size_t>(order)];
  }
};

// the output node's displacement from its rest position at a point (order 0) or its
// order-th derivative per driver unit: [mm or deg] per driver deg^order (or mm^order)
double output_lift(const Mechanism& mech, const PositionResult& result, std::size_t point, int order = 0);

struct SweepResult {
  std::vector<double> driver;  // [deg or mm]
  int derivative_order = 0;    // derivatives computed at every point (Request::derivative_order)
  std::vector<PositionResult> positions;
};

// solve every driver point at every control position. InputError for an invalid spec
// (SweepSpec::validate) or a control position without one value per Mechanism::controls;
// an exception thrown in a worker thread (on_position_done, or out of memory) is rethrown
// here once every worker has stopped. A failing solve is not an exception: it is the
// position's status, and its later points are zeros.
SweepResult sweep(const Mechanism& mech, const SweepSpec& spec);

// a value and the driver position where it occurs
struct Extreme {
  double value = 0, at = 0;  // the quantity, driver [deg or mm]
};

// the radius of curvature met by one surface of a contact, at the points where it touches
struct SurfaceRadii {
  std::string contact;  // the [[connection]]
  std::string body;     // the node that carries the surface
  std::string surface;  // the [[profile]] name, or "circle" / "roller"
  bool convex = false, concave = false;  // touched where convex / concave
  Extreme min_convex;    // smallest convex radius [mm] (> 0)
  Extreme sharpest_concave;  // concave radius of smallest magnitude [mm] (< 0)
};

// driver span where the lift exceeds a height
struct Duration {
  double height = 0;  // [output unit: mm, or deg for a rotating output]
  double span = 0;    // [driver deg or mm]
};

// a lash contact whose gap opens
struct Separation {
  std::string contact;
  double open_span = 0;                              // [driver deg or mm]
  std::vector<std::pair<double, double>> intervals;  // open from .. to [driver deg or mm]
};

struct SummaryOptions {
  std::vector<double> duration_heights{1.0, 0.1};  // [output unit: mm, or deg for a rotating output]
};

// what a valvetrain engineer reads first, per control position. The lift and its
// derivatives (extremes, crossings, area) are refined between the grid points on the
// hermite interpolant of the sweep's derivatives (grid_refine.hpp) when the sweep computed
// any (SweepResult::derivative_order > 0), except across an interval where a lash gap opens
// or closes. The contact extremes (pressure angle, radii of curvature, roller speed and
// sliding) are refined by solving the mechanism between the grid points: every grid-local
// extreme that could beat the best grid value is maximised by Brent's method over the span
// to its neighbouring grid points, each trial solved in one step from the nearest grid point
// (solve_near), to about 1e-9 driver deg or mm; a value reported is one the mechanism takes
// and never falls short of the best grid value. The condition number and the toggle margin
// are grid values.
struct PositionSummary {
  bool refined = false;                          // lift values refined between grid points
  double max_lift = 0, max_lift_at = 0;          // output node [mm or deg], driver [deg]
  std::vector<Duration> durations;               // one per SummaryOptions::duration_heights
  double lift_area = 0;                          // integral of lift over the driver [mm deg]
  double max_velocity = 0, max_velocity_at = 0, min_velocity = 0, min_velocity_at = 0;  // [per driver deg]
  double max_acceleration = 0, max_acceleration_at = 0, min_acceleration = 0, min_acceleration_at = 0;
  double max_jerk_abs = 0, max_jerk_abs_at = 0;
  bool have_contacts = false;
  // every contact extreme refined between the grid points (false: a trial solve failed,
  // and some may be grid values)
  bool contacts_refined = false;
  double max_pressure_angle_deg = 0, max_pressure_angle_at = 0;
  std::string max_pressure_angle_contact;
  std::vector<SurfaceRadii> cam_surfaces;       // every contact surface from a [[profile]]
  std::vector<SurfaceRadii> follower_surfaces;  // every other curved surface (circles, rollers)
  // the smallest convex radius over the cam surfaces only (never a pad or a roller)
  bool have_convex_cam = false;
  double min_convex_cam_radius_mm = 0, min_convex_cam_radius_at = 0;
  std::string min_convex_cam_radius_contact;
  double max_roller_speed = 0, max_roller_speed_at = 0;  // |roller spin| [rad per driver deg or mm], driver [deg or mm]
  double max_sliding = 0, max_sliding_at = 0;            // |scrub| [mm per driver deg or mm], driver [deg or mm]
  double max_condition = 0, max_condition_at = 0;
  // the closest approach to a singular configuration: the smallest toggle margin
  // (Workspace::toggle_margin) and where [driver deg or mm]; near_toggle when it is below
  // near_singular_margin
  double min_toggle_margin = 1.0, min_toggle_margin_at = 0;
  bool near_toggle = false;
  std::vector<Separation> separations;  // lash contacts that open

  double duration_at(double height) const;  // the duration at one of the options' heights
};

PositionSummary summarize(const Mechanism& mech, const SweepResult& result, std::size_t position,
                          const SummaryOptions& options = {});

// the displacement of one node over one revolution of a rotational driver, interpolated
// periodically: [driver rad] -> [rad or mm] (the node's internal unit); lash as designed.
// Sampled at step_deg (> 0); the status names the failing angle. InputError for a
// translating driver, a node that is not a body of the mechanism or a bad step.
Status periodic_motion(const Mechanism& mech, int node, const std::vector<double>& controls, double step_deg,
                       PeriodicSpline& motion);

}  // namespace camopt::kin
