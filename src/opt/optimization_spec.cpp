#include "camopt/opt/optimization_spec.hpp"

#include <array>
#include <cmath>
#include <sstream>

namespace camopt::opt {

namespace {

constexpr std::array<Quantity, 8> kQuantities = {Quantity::acceleration,   Quantity::deceleration, Quantity::jerk,
                                                 Quantity::pressure_angle, Quantity::hertz_stress, Quantity::roller_speed,
                                                 Quantity::sliding_speed,  Quantity::curvature};

std::string num(double v) { return format_value(v, 10); }

void require_positive(const std::optional<double>& v, const char* field, const char* unit) {
  if (v && !(std::isfinite(*v) && *v > 0.0))
    throw InputError(std::string(field) + " = " + num(*v) + " " + unit + ": must be finite and > 0");
}

}  // namespace

const char* to_string(Quantity q) {
  switch (q) {
    case Quantity::acceleration: return "acceleration";
    case Quantity::deceleration: return "deceleration";
    case Quantity::jerk: return "jerk";
    case Quantity::pressure_angle: return "pressure_angle";
    case Quantity::hertz_stress: return "hertz_stress";
    case Quantity::roller_speed: return "roller_speed";
    case Quantity::sliding_speed: return "sliding_speed";
    case Quantity::curvature: return "curvature";
  }
  return "?";
}

Quantity parse_quantity(const std::string& name, const std::string& what) {
  std::string allowed;
  for (Quantity q : kQuantities) {
    if (name == to_string(q)) return q;
    allowed += (allowed.empty() ? "" : ", ") + std::string(to_string(q));
  }
  throw InputError(what + ": unknown quantity '" + name + "' (allowed: " + allowed + ")");
}

namespace {

void validate_fields(const OptimizationSpec& s, double crank_per_cam) {
  if (s.cam == "rotational") validate(s.event);
  if (!(std::isfinite(s.grid_step_deg) && s.grid_step_deg >= 0.01 && s.grid_step_deg <= 5.0))
    throw InputError("set.grid_step_deg = " + num(s.grid_step_deg) + " cam deg: must be in [0.01, 5]");
  if (!(std::isfinite(s.rpm) && s.rpm >= 0.0)) throw InputError("set.rpm = " + num(s.rpm) + ": must be finite and >= 0");
  if (!(std::isfinite(s.coefficient_bound) && s.coefficient_bound >= 0.0))
    throw InputError("set.coefficient_bound_mm_per_deg2 = " + num(s.coefficient_bound) + ": must be finite and >= 0");
  if (!(crank_per_cam > 0)) throw InputError("the design's driver.crank_per_cam must be > 0");
  const LimitSpec& l = s.limits;
  require_positive(l.acc_max_mm_per_deg2, "limits.acc_max_mm_per_deg2", "mm/deg^2");
  if (l.acc_min_mm_per_deg2 && !(std::isfinite(*l.acc_min_mm_per_deg2) && *l.acc_min_mm_per_deg2 < 0.0))
    throw InputError("limits.acc_min_mm_per_deg2 = " + num(*l.acc_min_mm_per_deg2) +
                     " mm/deg^2: must be finite and < 0 (the largest deceleration, a negative acceleration)");
  require_positive(l.jerk_max_mm_per_deg3, "limits.jerk_max_mm_per_deg3", "mm/deg^3");
  require_positive(l.min_radius_of_curvature_mm, "limits.min_radius_of_curvature_mm", "mm");
  require_positive(l.grinding_wheel_radius_mm, "limits.grinding_wheel_radius_mm", "mm");
  require_positive(l.max_pressure_angle_deg, "limits.max_pressure_angle_deg", "deg");
  if (l.max_pressure_angle_deg && *l.max_pressure_angle_deg >= 90.0)
    throw InputError("limits.max_pressure_angle_deg = " + num(*l.max_pressure_angle_deg) + " deg: must be below 90");
  require_positive(l.max_roller_speed_rpm, "limits.max_roller_speed_rpm", "rpm");
  require_positive(l.max_sliding_speed_m_per_s, "limits.max_sliding_speed_m_per_s", "m/s");
  require_positive(l.max_hertz_stress_MPa, "limits.max_hertz_stress_MPa", "MPa");
  require_positive(l.max_lift_mm, "limits.max_lift_mm", "mm");
  require_positive(l.min_max_lift_mm, "limits.min_max_lift_mm", "mm");
  require_positive(l.duration_check_height_mm, "limits.duration_check_height_mm", "mm");
  require_positive(l.min_duration_deg, "limits.min_duration_deg", "cam deg");
  require_positive(l.max_duration_deg, "limits.max_duration_deg", "cam deg");
  require_positive(l.max_seating_velocity_m_per_s, "limits.max_seating_velocity_m_per_s", "m/s");
  require_positive(l.max_opening_ramp_velocity_m_per_s, "limits.max_opening_ramp_velocity_m_per_s", "m/s");
  // contradictions
  if (l.max_lift_mm && l.min_max_lift_mm && *l.min_max_lift_mm > *l.max_lift_mm)
    throw InputError("limits.min_max_lift_mm = " + num(*l.min_max_lift_mm) + " mm is above limits.max_lift_mm = " +
                     num(*l.max_lift_mm) + " mm: contradictory constraints");
  if (l.min_duration_deg && l.max_duration_deg && *l.min_duration_deg > *l.max_duration_deg)
    throw InputError("limits.min_duration_deg = " + num(*l.min_duration_deg) + " cam deg is above limits.max_duration_deg = " +
                     num(*l.max_duration_deg) + " cam deg: contradictory constraints");
  if ((l.min_duration_deg || l.max_duration_deg) && !l.duration_check_height_mm)
    throw InputError("limits.min_duration_deg / max_duration_deg need limits.duration_check_height_mm");
  if (s.cam != "rotational" && s.cam != "swing")
    throw InputError("cam = '" + s.cam + "': must be rotational or swing");
  if (s.cam == "swing") validate(s.swing);
  if (s.cam == "rotational" && l.min_duration_deg && *l.min_duration_deg >= s.event.duration_deg)
    throw InputError("limits.min_duration_deg = " + num(*l.min_duration_deg) + " cam deg: must be below event.duration_deg = " +
                     num(s.event.duration_deg) + " cam deg (the lift is zero outside the event): contradictory constraints");
  if (l.duration_check_height_mm && l.max_lift_mm && *l.duration_check_height_mm >= *l.max_lift_mm)
    throw InputError("limits.duration_check_height_mm = " + num(*l.duration_check_height_mm) +
                     " mm is not below limits.max_lift_mm = " + num(*l.max_lift_mm) + " mm: contradictory constraints");
  require_positive(l.min_separation_speed_rpm, "limits.min_separation_speed_rpm", "rpm");
  if (l.min_contact_force_N && !(std::isfinite(*l.min_contact_force_N) && *l.min_contact_force_N >= 0.0))
    throw InputError("limits.min_contact_force_N = " + num(*l.min_contact_force_N) + " N: must be finite and >= 0");
  if (l.min_spring_margin && !(*l.min_spring_margin >= 0.0 && *l.min_spring_margin < 1.0))
    throw InputError("limits.min_spring_margin = " + num(*l.min_spring_margin) +
                     ": must be in [0, 1) (the fraction of a spring's load that could be lost before a contact opens)");
  require_positive(l.max_cam_torque_Nm, "limits.max_cam_torque_Nm", "N m");
  require_positive(l.min_film_thickness_um, "limits.min_film_thickness_um", "um");
  require_positive(l.min_lambda, "limits.min_lambda", "-");
  const bool speed_limits = l.max_roller_speed_rpm || l.max_sliding_speed_m_per_s || l.max_hertz_stress_MPa ||
                            l.max_seating_velocity_m_per_s || l.max_opening_ramp_velocity_m_per_s ||
                            l.min_contact_force_N || l.min_spring_margin || l.max_cam_torque_Nm ||
                            l.min_film_thickness_um || l.min_lambda;
  if (speed_limits && !(s.rpm > 0))
    throw InputError("set.rpm = " + num(s.rpm) + ": the speed-dependent limits (roller speed, sliding speed, Hertz stress, "
                     "ramp velocities, contact force, spring margin, cam torque, film thickness) need an engine speed > 0");
  if (s.cam == "swing" && (l.max_cam_torque_Nm || l.min_film_thickness_um || l.min_lambda))
    throw InputError(std::string(l.max_cam_torque_Nm ? "limits.max_cam_torque_Nm" : l.min_film_thickness_um ? "limits.min_film_thickness_um" : "limits.min_lambda") +
                     ": not available for a swing cam (its drive torque and entrainment come from the upstream mechanism)");
  if (s.load) {
    const LoadSpec& ld = *s.load;
    if (!(std::isfinite(ld.spring_preload_N) && ld.spring_preload_N >= 0.0))
      throw InputError("load.spring_preload_N = " + num(ld.spring_preload_N) + " N: must be finite and >= 0");
    if (!(std::isfinite(ld.spring_rate_N_per_mm) && ld.spring_rate_N_per_mm >= 0.0))
      throw InputError("load.spring_rate_N_per_mm = " + num(ld.spring_rate_N_per_mm) + " N/mm: must be finite and >= 0");
    if (!(std::isfinite(ld.moving_mass_kg) && ld.moving_mass_kg >= 0.0))
      throw InputError("load.moving_mass_kg = " + num(ld.moving_mass_kg) + " kg: must be finite and >= 0");
    require_positive(ld.width_mm, "load.width_mm", "mm");
    require_positive(ld.youngs_modulus_cam_GPa, "load.youngs_modulus_cam_GPa", "GPa");
    require_positive(ld.youngs_modulus_follower_GPa, "load.youngs_modulus_follower_GPa", "GPa");
    for (auto [v, f] : {std::pair{ld.poisson_cam, "load.poisson_cam"}, std::pair{ld.poisson_follower, "load.poisson_follower"}})
      if (v && !(*v >= 0.0 && *v < 0.5)) throw InputError(std::string(f) + " = " + num(*v) + ": must be in [0, 0.5)");
  }
  const ObjectiveSpec& o = s.objective;
  for (auto [w, f] : {std::pair{o.target_weight, "objective.target_weight"}, std::pair{o.area_weight, "objective.area_weight"},
                      std::pair{o.peak_weight, "objective.peak_weight"}})
    if (!(std::isfinite(w) && w >= 0.0)) throw InputError(std::string(f) + " = " + num(w) + ": must be finite and >= 0");
  if (o.target_weight + o.area_weight + o.peak_weight <= 0.0)
    throw InputError("objective: give at least one of target_weight, area_weight, peak_weight > 0");
  if (o.target_weight > 0.0 && o.target_file.empty())
    throw InputError("objective.target_weight = " + num(o.target_weight) + " needs objective.target (a lift csv)");
  if (s.cam == "rotational" && o.target_file.empty() && !(s.initial_max_lift_mm > 0.0))
    throw InputError("set.initial_max_lift_mm = " + num(s.initial_max_lift_mm) +
                     " mm: without an objective.target the initial design needs a lift > 0");
}

}  // namespace

InputError located_error(const OptimizationSpec& spec, const std::string& message) {
  const std::string key = message.substr(0, message.find_first_of(" :="));
  for (const auto& [path, where] : spec.locations)
    if (path == key) return InputError(SourceRef{where.file, where.line, where.column, ""}, message);
  if (spec.file.empty()) return InputError(message);
  const bool key_path = key.find('.') != std::string::npos && key.find('\'') == std::string::npos;
  return InputError(spec.file + ": " + message +
                    (key_path ? " (" + key + " is not in the file: it takes its default)" : std::string()));
}

void validate(const OptimizationSpec& s, double crank_per_cam) {
  try {
    validate_fields(s, crank_per_cam);
  } catch (const InputError& e) {
    throw located_error(s, e.what());
  }
}

}  // namespace camopt::opt
