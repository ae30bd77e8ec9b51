#pragma once
// plain description of a cam optimisation as read from a constraints/*.toml file
// (io/constraint_file.hpp; format in docs/optimisation.md). validate() checks every field
// and the set's consistency (contradictory limits are an InputError naming both fields);
// CamProblem (problem.hpp) compiles it against a design.
#include <optional>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/opt/lift_model.hpp"
#include "camopt/opt/swing_lift.hpp"

namespace camopt::opt {

// quantities whose peak can be minimised, and whose limits can be set
enum class Quantity {
  acceleration,      // valve acceleration, positive peak [mm/deg^2]
  deceleration,      // valve acceleration, negative peak (its magnitude) [mm/deg^2]
  jerk,              // |valve jerk| [mm/deg^3]
  pressure_angle,    // [deg]
  hertz_stress,      // max Hertz pressure p0 [MPa]
  roller_speed,      // |roller spin relative to its carrier| [rpm]
  sliding_speed,     // |scrub velocity| [m/s]
  curvature,         // cam pitch-curve curvature (roller, pad) or 1 / cam radius (flat) [1/mm]
};
const char* to_string(Quantity q);
// InputError "what: unknown quantity 'name' (allowed: ...)"
Quantity parse_quantity(const std::string& name, const std::string& what);

struct LimitSpec {
  std::optional<double> acc_max_mm_per_deg2;     // > 0
  std::optional<double> acc_min_mm_per_deg2;     // < 0 (largest deceleration)
  std::optional<double> jerk_max_mm_per_deg3;    // > 0, on |jerk|
  std::optional<double> min_radius_of_curvature_mm;  // convex cam radius >= this
  std::optional<double> grinding_wheel_radius_mm;    // concave cam radius >= this
  std::optional<double> max_pressure_angle_deg;      // (0, 90)
  std::optional<double> max_roller_speed_rpm;        // roller followers
  std::optional<double> max_sliding_speed_m_per_s;   // pads and flat faces
  std::optional<double> max_hertz_stress_MPa;        // needs [load]
  std::optional<double> max_lift_mm;                 // lift <= this at every angle
  std::optional<double> min_max_lift_mm;             // peak lift >= this
  std::optional<double> duration_check_height_mm;    // duration measured at this lift
  std::optional<double> min_duration_deg, max_duration_deg;  // [cam deg] at the check height
  std::optional<double> max_seating_velocity_m_per_s;  // closing ramp velocity at speed
  std::optional<double> max_opening_ramp_velocity_m_per_s;
  // durability: from the loads of the design's rigid model (opt/downstream_loads.hpp)
  std::optional<double> min_separation_speed_rpm;  // every loaded contact stays closed up to this engine speed
  std::optional<double> min_contact_force_N;       // cam contact's normal force at `rpm`
  std::optional<double> min_spring_margin;         // fraction of each spring's load that could go before a contact opens, at `rpm`
  std::optional<double> max_cam_torque_Nm;        // |cam drive torque| at `rpm` (rotational cam)
  std::optional<double> min_film_thickness_um;     // EHL minimum film of the cam contact at `rpm` (needs [oil])
  std::optional<double> min_lambda;                // film / composite roughness (needs [oil] composite_roughness_um)
};

// the engine oil at operating temperature for the EHL film (Dowson-Higginson line contact)
struct OilSetSpec {
  double viscosity_mPa_s = 0.0;             // dynamic viscosity at the contact inlet
  double pressure_viscosity_per_GPa = 0.0;  // Barus coefficient alpha
  std::optional<double> composite_roughness_um;  // sqrt(Rq1^2 + Rq2^2)
  SourceRef where;
};

// a reduced valve-side load, F = preload + rate * lift + mass * acc, for a design without
// dynamics data, or (override_design) in place of the design's own loads; a set that states
// values the design disagrees with, without override_design, is an InputError
struct LoadSpec {
  bool override_design = false;
  std::vector<std::pair<std::string, SourceRef>> given;  // the keys the file states, where
  SourceRef where;                                        // the [load] table
  double spring_preload_N = 0.0;
  double spring_rate_N_per_mm = 0.0;
  double moving_mass_kg = 0.0;  // valve-equivalent moving mass (valve, retainer, 1/3 spring, follower)
  // contact: from the design's connection (materials, width_mm) unless given here
  std::optional<double> width_mm;
  std::optional<double> youngs_modulus_cam_GPa, poisson_cam, youngs_modulus_follower_GPa, poisson_follower;
};

struct ObjectiveSpec {
  double target_weight = 0.0;  // least squares against the target lift
  double area_weight = 0.0;    // maximise the lift area
  double peak_weight = 0.0;    // minimise the peak of `peak`
  Quantity peak = Quantity::acceleration;
  std::string target_file;     // csv (cam_deg or crank_deg, lift_mm), relative to the constraints file
};

// what `optimize --verify` holds the made design to, beside the limits (docs/optimisation.md)
struct VerifySpec {
  double relative_tolerance = 0.005;  // on every limit: the rows hold at grid points only
  double max_lift_error_mm = 0.01;    // kinematic solver's lift of the made cam against the optimised lift
  std::optional<double> max_lift_loss_mm;  // flexible model: kinematic minus dynamic lift
  double max_bounce_height_mm = 0.001;     // flexible model: seat re-openings after the first closing
  bool flexible = true;               // run the flexible model (separation, bounce, coil clash, seating)
};

struct OptimizationSpec {
  std::string name, description, file, directory;
  std::vector<std::pair<std::string, SourceRef>> locations;  // every key the file states (key path, where)
  // "rotational": the driver's cam, variables = the valve lift (event); "swing": a swing cam
  // of a VVA design, variables = its pitch curve (swing_profile), every control position
  std::string cam = "rotational";
  EventSpec event;
  SwingProfileSpec swing;
  double initial_max_lift_mm = 0.0;  // initial design without a target: 4-5-6-7 event of this lift
  double rpm = 0.0;                  // engine speed [crank rpm] for the speed-dependent limits and the load
  double grid_step_deg = 0.5;        // constraints are evaluated every this many cam deg
  double coefficient_bound = 0.0;    // |acceleration coefficients| <= this [mm/deg^2] (0: 3 x the largest limit)
  std::vector<double> controls;      // control positions [deg or mm] (empty: the design's defaults)
  LimitSpec limits;
  std::optional<LoadSpec> load;
  std::optional<OilSetSpec> oil;
  VerifySpec verify;
  ObjectiveSpec objective;
};

// InputError for the first broken rule, naming the field (as written in the file), its
// value and the rule; contradictions (acc_min above acc_max, min above max duration, a
// ramp faster than the seating limit ...) name both fields
// (each error is located at its key's file:line:column, or says the key takes its default)
void validate(const OptimizationSpec& spec, double crank_per_cam);

// `message`, which starts with a key path ("limits.max_lift_mm = ..."), located at that
// key in the set's file; a key the file does not state is named as taking its default
InputError located_error(const OptimizationSpec& spec, const std::string& message);

}  // namespace camopt::opt
