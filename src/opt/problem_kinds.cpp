// the constraint kinds of CamProblem: report names, constraint-set keys, units, limits, and
// the contact or spring a load row is about
#include <string>

#include "camopt/opt/problem.hpp"
#include "load_rows.hpp"

namespace camopt::opt {

const char* to_string(ConstraintKind kind) {
  switch (kind) {
    case ConstraintKind::acc_max: return "acc_max";
    case ConstraintKind::acc_min: return "acc_min";
    case ConstraintKind::jerk_max: return "jerk_max";
    case ConstraintKind::lift_max: return "lift_max";
    case ConstraintKind::lift_nonnegative: return "lift_nonnegative";
    case ConstraintKind::peak_lift_min: return "peak_lift_min";
    case ConstraintKind::duration_min: return "duration_min";
    case ConstraintKind::duration_max: return "duration_max";
    case ConstraintKind::radius_min: return "radius_of_curvature_min";
    case ConstraintKind::concave_radius: return "concave_radius_min";
    case ConstraintKind::pressure_angle: return "pressure_angle_max";
    case ConstraintKind::roller_speed: return "roller_speed_max";
    case ConstraintKind::sliding_speed: return "sliding_speed_max";
    case ConstraintKind::hertz_stress: return "hertz_stress_max";
    case ConstraintKind::face_width: return "face_width";
    case ConstraintKind::separation: return "separation_speed_min";
    case ConstraintKind::contact_force: return "contact_force_min";
    case ConstraintKind::spring_margin: return "spring_margin_min";
    case ConstraintKind::cam_torque: return "cam_torque_max";
    case ConstraintKind::film_thickness: return "film_thickness_min";
    case ConstraintKind::lambda: return "lambda_min";
    case ConstraintKind::peak_bound: return "peak_bound";
  }
  return "?";
}

const char* limit_key(ConstraintKind kind) {
  switch (kind) {
    case ConstraintKind::acc_max: return "limits.acc_max_mm_per_deg2";
    case ConstraintKind::acc_min: return "limits.acc_min_mm_per_deg2";
    case ConstraintKind::jerk_max: return "limits.jerk_max_mm_per_deg3";
    case ConstraintKind::lift_max: return "limits.max_lift_mm";
    case ConstraintKind::lift_nonnegative: return nullptr;
    case ConstraintKind::peak_lift_min: return "limits.min_max_lift_mm";
    case ConstraintKind::duration_min: return "limits.min_duration_deg";
    case ConstraintKind::duration_max: return "limits.max_duration_deg";
    case ConstraintKind::radius_min: return "limits.min_radius_of_curvature_mm";
    case ConstraintKind::concave_radius: return "limits.grinding_wheel_radius_mm";
    case ConstraintKind::pressure_angle: return "limits.max_pressure_angle_deg";
    case ConstraintKind::roller_speed: return "limits.max_roller_speed_rpm";
    case ConstraintKind::sliding_speed: return "limits.max_sliding_speed_m_per_s";
    case ConstraintKind::hertz_stress: return "limits.max_hertz_stress_MPa";
    case ConstraintKind::face_width: return "design: the flat face's half_width_mm";
    case ConstraintKind::separation: return "limits.min_separation_speed_rpm";
    case ConstraintKind::contact_force: return "limits.min_contact_force_N";
    case ConstraintKind::spring_margin: return "limits.min_spring_margin";
    case ConstraintKind::cam_torque: return "limits.max_cam_torque_Nm";
    case ConstraintKind::film_thickness: return "limits.min_film_thickness_um";
    case ConstraintKind::lambda: return "limits.min_lambda";
    case ConstraintKind::peak_bound: return nullptr;
  }
  return nullptr;
}

const char* CamProblem::unit_of(ConstraintKind kind) const {
  switch (kind) {
    case ConstraintKind::acc_max:
    case ConstraintKind::acc_min: return "mm/deg^2";
    case ConstraintKind::jerk_max: return "mm/deg^3";
    case ConstraintKind::lift_max:
    case ConstraintKind::lift_nonnegative:
    case ConstraintKind::peak_lift_min: return "mm";
    case ConstraintKind::duration_min:
    case ConstraintKind::duration_max: return "cam deg";
    case ConstraintKind::radius_min:
    case ConstraintKind::concave_radius:
    case ConstraintKind::face_width: return "mm";
    case ConstraintKind::pressure_angle: return "deg";
    case ConstraintKind::roller_speed: return "rpm";
    case ConstraintKind::sliding_speed: return "m/s";
    case ConstraintKind::hertz_stress: return "MPa";
    case ConstraintKind::separation: return "rpm";
    case ConstraintKind::contact_force: return "N";
    case ConstraintKind::spring_margin: return "-";
    case ConstraintKind::cam_torque: return "N m";
    case ConstraintKind::film_thickness: return "um";
    case ConstraintKind::lambda: return "-";
    case ConstraintKind::peak_bound: return "-";
  }
  return "";
}

double CamProblem::limit_of(ConstraintKind kind) const {
  const auto& l = spec_.limits;
  switch (kind) {
    case ConstraintKind::acc_max: return *l.acc_max_mm_per_deg2;
    case ConstraintKind::acc_min: return *l.acc_min_mm_per_deg2;
    case ConstraintKind::jerk_max: return *l.jerk_max_mm_per_deg3;
    case ConstraintKind::lift_max: return *l.max_lift_mm;
    case ConstraintKind::lift_nonnegative: return 0.0;
    case ConstraintKind::peak_lift_min: return *l.min_max_lift_mm;
    case ConstraintKind::duration_min: return *l.min_duration_deg;
    case ConstraintKind::duration_max: return *l.max_duration_deg;
    case ConstraintKind::radius_min: return *l.min_radius_of_curvature_mm;
    case ConstraintKind::concave_radius: return -*l.grinding_wheel_radius_mm;
    case ConstraintKind::pressure_angle: return *l.max_pressure_angle_deg;
    case ConstraintKind::roller_speed: return *l.max_roller_speed_rpm;
    case ConstraintKind::sliding_speed: return *l.max_sliding_speed_m_per_s;
    case ConstraintKind::hertz_stress: return *l.max_hertz_stress_MPa;
    case ConstraintKind::face_width: return contact_->face_half_width_mm();
    case ConstraintKind::separation: return *l.min_separation_speed_rpm;
    case ConstraintKind::contact_force: return *l.min_contact_force_N;
    case ConstraintKind::spring_margin: return *l.min_spring_margin;
    case ConstraintKind::cam_torque: return *l.max_cam_torque_Nm;
    case ConstraintKind::film_thickness: return *l.min_film_thickness_um;
    case ConstraintKind::lambda: return *l.min_lambda;
    case ConstraintKind::peak_bound: return 0.0;
  }
  return 0.0;
}

bool CamProblem::is_upper_limit(ConstraintKind kind) const {
  switch (kind) {
    case ConstraintKind::acc_min:
    case ConstraintKind::lift_nonnegative:
    case ConstraintKind::peak_lift_min:
    case ConstraintKind::duration_min:
    case ConstraintKind::radius_min:
    case ConstraintKind::separation:
    case ConstraintKind::contact_force:
    case ConstraintKind::spring_margin:
    case ConstraintKind::film_thickness:
    case ConstraintKind::lambda: return false;
    case ConstraintKind::concave_radius: return true;  // the concave radius as a negative number: <= -wheel
    default: return true;
  }
}

std::string CamProblem::load_source() const { return load_rows_ ? load_rows_->source() : std::string(); }

std::vector<LoadOverride> CamProblem::load_overrides() const {
  return load_rows_ ? load_rows_->overrides() : std::vector<LoadOverride>{};
}

std::string CamProblem::item_name(const ConstraintRow& row) const {
  if (!load_rows_ || row.item < 0) return "";
  const auto& contacts = load_rows_->contact_names();
  if (row.kind == ConstraintKind::spring_margin) {
    const std::size_t ns = load_rows_->spring_names().size(), item = static_cast<std::size_t>(row.item);
    return contacts[item / ns] + " / " + load_rows_->spring_names()[item % ns];
  }
  if (row.kind == ConstraintKind::separation) return contacts[static_cast<std::size_t>(row.item)];
  return contacts.front();
}

}  // namespace camopt::opt
