#pragma once
// a kinematic sweep over the driver range at one or more control positions (solved in
// parallel, one workspace per thread), and the per-position summary engineers read first.
#include <atomic>
#include <functional>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::kin {

struct SweepSpec {
  double start = 0.0, stop = 360.0, step = 1.0;       // driver [deg or mm], both ends included
  std::vector<std::vector<double>> control_positions;  // each: every control [deg or mm]
  Request request;
  int threads = 1;
  std::function<void()> on_position_done;  // progress hook; called from worker threads
};

// one control position: values and derivatives per driver unit (deg or mm) of every
// variable at every driver point: data[(point * variables + v) * 4 + k], k = 0..3
struct PositionResult {
  std::vector<double> controls;
  Status status;
  std::vector<double> data;
  std::vector<ContactState> contacts;  // [point * connections + c] (request.contacts)
  std::vector<double> condition;       // largest block condition estimate per point
  SolveStats stats;

  double at(std::size_t point, std::size_t variables, int v, int k) const { return data[(point * variables + v) * 4 + k]; }
};

struct SweepResult {
  std::vector<double> driver;  // [deg or mm]
  std::vector<PositionResult> positions;
};

SweepResult sweep(const Mechanism& mech, const SweepSpec& spec);

// what a valvetrain engineer reads first, per control position
struct PositionSummary {
  double max_lift = 0, max_lift_at = 0;          // output node [mm or deg], driver [deg]
  double duration_at_1mm = 0, duration_at_0p1mm = 0;  // driver span above the height [deg]
  double lift_area = 0;                          // integral of lift over the driver [mm deg]
  double max_velocity = 0, min_velocity = 0;     // [per driver deg]
  double max_acceleration = 0, max_acceleration_at = 0, min_acceleration = 0, min_acceleration_at = 0;
  double max_jerk_abs = 0;
  bool have_contacts = false;
  double max_pressure_angle_deg = 0, max_pressure_angle_at = 0;
  std::string max_pressure_angle_contact;
  double min_cam_radius_mm = 0, min_cam_radius_at = 0;  // smallest radius of curvature of a cam surface
  std::string min_cam_radius_contact;
  double max_roller_speed = 0;   // |roller spin| [rad per driver deg]
  double max_sliding = 0;        // |scrub| [mm per driver deg]
  double max_condition = 0, max_condition_at = 0;
  std::vector<std::string> separations;  // lash contacts that open, with their open driver span
};

PositionSummary summarize(const Mechanism& mech, const SweepResult& result, std::size_t position);

// the displacement of one node over one revolution of a rotational driver, interpolated
// periodically: [driver rad] -> [rad or mm] (the node's internal unit); lash as designed.
// Sampled at step_deg; the status names the failing angle.
Status periodic_motion(const Mechanism& mech, int node, const std::vector<double>& controls, double step_deg,
                       PeriodicSpline& motion);

}  // namespace camopt::kin
