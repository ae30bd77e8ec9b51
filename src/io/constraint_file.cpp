// constraint-set files (TOML) -> opt::OptimizationSpec (docs/optimisation.md)
#include "camopt/io/constraint_file.hpp"

#include "toml_edit.hpp"
#include "toml_table.hpp"

namespace camopt::io {

namespace {

using namespace toml_detail;
using toml_detail::EditableToml;

opt::RampSpec parse_ramp(const Table& t) {
  t.allow({"height_mm", "length_deg"});
  return {t.number("height_mm", ge(0.0)), t.number("length_deg", ge(0.0))};
}

// every key of the file (tables, inline tables and values) with where it was written
void record_locations(const toml::table& table, const std::string& prefix, const Context& context,
                      std::vector<std::pair<std::string, SourceRef>>& out) {
  for (const auto& [key, node] : table) {
    const std::string path = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    out.emplace_back(path, context.ref(key.source(), path));
    if (const toml::table* sub = node.as_table()) record_locations(*sub, path, context, out);
  }
}

opt::OptimizationSpec parse(const toml::table& document, const Context& context) {
  const Table root(context, document, "");
  root.allow({"schema", "set", "event", "swing_profile", "limits", "load", "oil", "verify", "objective"});
  if (const long long schema = root.integer("schema"); schema != 1)
    root.fail("schema", "value " + std::to_string(schema) + " is not a supported schema version (must be 1)");
  opt::OptimizationSpec s;
  s.file = context.file;
  s.directory = context.directory;
  record_locations(document, "", context, s.locations);

  const Table set = root.table("set");
  set.allow({"name", "description", "rpm", "grid_step_deg", "initial_max_lift_mm", "coefficient_bound_mm_per_deg2",
             "controls"});
  s.name = set.string("name");
  s.description = set.text_or("description", "");
  s.rpm = set.number_or("rpm", 0.0, ge(0.0));
  s.grid_step_deg = set.number_or("grid_step_deg", 0.5, ge(0.01) & le(5.0));
  s.initial_max_lift_mm = set.number_or("initial_max_lift_mm", 0.0, ge(0.0));
  s.coefficient_bound = set.number_or("coefficient_bound_mm_per_deg2", 0.0, ge(0.0));
  if (set.has("controls")) {
    const Column c = set.numbers("controls");
    s.controls = c.values;
  }

  // [event]: the conventional cam's lift model; [swing_profile]: the swing cam's pitch curve
  // (optimize --cam swing). at least one of them.
  if (!root.has("event") && !root.has("swing_profile")) root.table("event");  // names the missing table
  if (auto ev_ = root.optional_table("event")) {
    const Table& ev = *ev_;
    ev.allow({"start_deg", "duration_deg", "opening_ramp", "closing_ramp", "ramp_blend", "coefficients", "degree"});
    s.event.start_deg = ev.number("start_deg");
    s.event.duration_deg = ev.number("duration_deg", gt(0.0) & lt(360.0));
    if (auto t = ev.optional_table("opening_ramp")) s.event.opening_ramp = parse_ramp(*t);
    if (auto t = ev.optional_table("closing_ramp")) s.event.closing_ramp = parse_ramp(*t);
    s.event.ramp_blend = ev.number_or("ramp_blend", 0.5, gt(0.0) & le(1.0));
    s.event.coefficients = static_cast<int>(ev.integer_or("coefficients", 24, ge(6) & le(200)));
    s.event.degree = static_cast<int>(ev.integer_or("degree", 3, ge(2) & le(5)));
  }
  if (auto sw_ = root.optional_table("swing_profile")) {
    const Table& sw = *sw_;
    sw.allow({"start_deg", "end_deg", "coefficients", "degree", "positions"});
    s.swing.start_deg = sw.number_or("start_deg", 1.0, ge(0.0) & lt(90.0));
    s.swing.end_deg = sw.number_or("end_deg", 0.0, ge(0.0) & le(170.0));
    s.swing.coefficients = static_cast<int>(sw.integer_or("coefficients", 20, ge(9) & le(200)));
    s.swing.degree = static_cast<int>(sw.integer_or("degree", 5, ge(4) & le(7)));
    if (sw.has("positions")) s.swing.positions = sw.numbers("positions").values;
  }

  if (auto lt_ = root.optional_table("limits")) {
    const Table& l = *lt_;
    l.allow({"acc_max_mm_per_deg2", "acc_min_mm_per_deg2", "jerk_max_mm_per_deg3", "min_radius_of_curvature_mm",
             "grinding_wheel_radius_mm", "max_pressure_angle_deg", "max_roller_speed_rpm", "max_sliding_speed_m_per_s",
             "max_hertz_stress_MPa", "max_lift_mm", "min_max_lift_mm", "duration_check_height_mm", "min_duration_deg",
             "max_duration_deg", "max_seating_velocity_m_per_s", "max_opening_ramp_velocity_m_per_s",
             "min_separation_speed_rpm", "min_contact_force_N", "min_spring_margin", "max_cam_torque_Nm",
             "min_film_thickness_um", "min_lambda"});
    auto& m = s.limits;
    m.acc_max_mm_per_deg2 = l.optional_number("acc_max_mm_per_deg2", gt(0.0));
    m.acc_min_mm_per_deg2 = l.optional_number("acc_min_mm_per_deg2", lt(0.0));
    m.jerk_max_mm_per_deg3 = l.optional_number("jerk_max_mm_per_deg3", gt(0.0));
    m.min_radius_of_curvature_mm = l.optional_number("min_radius_of_curvature_mm", gt(0.0));
    m.grinding_wheel_radius_mm = l.optional_number("grinding_wheel_radius_mm", gt(0.0));
    m.max_pressure_angle_deg = l.optional_number("max_pressure_angle_deg", gt(0.0) & lt(90.0));
    m.max_roller_speed_rpm = l.optional_number("max_roller_speed_rpm", gt(0.0));
    m.max_sliding_speed_m_per_s = l.optional_number("max_sliding_speed_m_per_s", gt(0.0));
    m.max_hertz_stress_MPa = l.optional_number("max_hertz_stress_MPa", gt(0.0));
    m.max_lift_mm = l.optional_number("max_lift_mm", gt(0.0));
    m.min_max_lift_mm = l.optional_number("min_max_lift_mm", gt(0.0));
    m.duration_check_height_mm = l.optional_number("duration_check_height_mm", gt(0.0));
    m.min_duration_deg = l.optional_number("min_duration_deg", gt(0.0));
    m.max_duration_deg = l.optional_number("max_duration_deg", gt(0.0));
    m.max_seating_velocity_m_per_s = l.optional_number("max_seating_velocity_m_per_s", gt(0.0));
    m.max_opening_ramp_velocity_m_per_s = l.optional_number("max_opening_ramp_velocity_m_per_s", gt(0.0));
    m.min_separation_speed_rpm = l.optional_number("min_separation_speed_rpm", gt(0.0));
    m.min_contact_force_N = l.optional_number("min_contact_force_N", ge(0.0));
    m.min_spring_margin = l.optional_number("min_spring_margin", ge(0.0) & lt(1.0));
    m.max_cam_torque_Nm = l.optional_number("max_cam_torque_Nm", gt(0.0));
    m.min_film_thickness_um = l.optional_number("min_film_thickness_um", gt(0.0));
    m.min_lambda = l.optional_number("min_lambda", gt(0.0));
  }

  if (auto oil_ = root.optional_table("oil")) {
    const Table& o = *oil_;
    o.allow({"viscosity_mPa_s", "pressure_viscosity_per_GPa", "composite_roughness_um"});
    opt::OilSetSpec oil;
    oil.viscosity_mPa_s = o.number("viscosity_mPa_s", gt(0.0));
    oil.pressure_viscosity_per_GPa = o.number("pressure_viscosity_per_GPa", gt(0.0));
    oil.composite_roughness_um = o.optional_number("composite_roughness_um", gt(0.0));
    oil.where = o.where();
    s.oil = oil;
  }

  if (auto ld_ = root.optional_table("load")) {
    const Table& l = *ld_;
    l.allow({"override_design", "spring_preload_N", "spring_rate_N_per_mm", "moving_mass_kg", "width_mm",
             "youngs_modulus_cam_GPa", "poisson_cam", "youngs_modulus_follower_GPa", "poisson_follower"});
    opt::LoadSpec load;
    load.override_design = l.boolean_or("override_design", false);
    load.where = l.where();
    for (const char* key : {"spring_preload_N", "spring_rate_N_per_mm", "moving_mass_kg", "width_mm", "youngs_modulus_cam_GPa",
                            "poisson_cam", "youngs_modulus_follower_GPa", "poisson_follower"})
      if (l.has(key)) load.given.emplace_back(key, l.where(key));
    load.spring_preload_N = l.number_or("spring_preload_N", 0.0, ge(0.0));
    load.spring_rate_N_per_mm = l.number_or("spring_rate_N_per_mm", 0.0, ge(0.0));
    load.moving_mass_kg = l.number_or("moving_mass_kg", 0.0, ge(0.0));
    load.width_mm = l.optional_number("width_mm", gt(0.0));
    load.youngs_modulus_cam_GPa = l.optional_number("youngs_modulus_cam_GPa", gt(0.0));
    load.poisson_cam = l.optional_number("poisson_cam", ge(0.0) & lt(0.5));
    load.youngs_modulus_follower_GPa = l.optional_number("youngs_modulus_follower_GPa", gt(0.0));
    load.poisson_follower = l.optional_number("poisson_follower", ge(0.0) & lt(0.5));
    s.load = load;
  }

  if (auto v_ = root.optional_table("verify")) {
    const Table& v = *v_;
    v.allow({"relative_tolerance", "max_lift_error_mm", "max_lift_loss_mm", "max_bounce_height_mm", "flexible"});
    s.verify.relative_tolerance = v.number_or("relative_tolerance", 0.005, ge(0.0) & lt(0.5));
    s.verify.max_lift_error_mm = v.number_or("max_lift_error_mm", 0.01, gt(0.0));
    s.verify.max_lift_loss_mm = v.optional_number("max_lift_loss_mm", gt(0.0));
    s.verify.max_bounce_height_mm = v.number_or("max_bounce_height_mm", 0.001, ge(0.0));
    s.verify.flexible = v.boolean_or("flexible", true);
  }

  const Table ob = root.table("objective");
  ob.allow({"target", "target_weight", "area_weight", "peak_weight", "peak"});
  s.objective.target_weight = ob.number_or("target_weight", 0.0, ge(0.0));
  s.objective.area_weight = ob.number_or("area_weight", 0.0, ge(0.0));
  s.objective.peak_weight = ob.number_or("peak_weight", 0.0, ge(0.0));
  if (ob.has("target")) s.objective.target_file = context.resolve(ob.string("target")).string();
  if (ob.has("peak")) {
    try {
      s.objective.peak = opt::parse_quantity(ob.string("peak"), "peak");
    } catch (const InputError& e) {
      throw InputError(ob.where("peak"), e.what());
    }
  }
  return s;
}

}  // namespace

opt::OptimizationSpec parse_constraints(std::string_view text, const std::string& file_name,
                                        const std::string& directory) {
  const Context context{file_name, directory, {}};
  return parse(parse_document(text, context), context);
}

opt::OptimizationSpec load_constraints(const std::string& path) {
  std::string directory;
  const std::string text = read_text_file(path, "constraint file", directory);
  return parse_constraints(text, path, directory);
}

opt::OptimizationSpec load_constraints(const std::string& path, const std::vector<Override>& overrides) {
  if (overrides.empty()) return load_constraints(path);
  std::string directory;
  EditableToml edited(read_text_file(path, "constraint file", directory), path, "--set-constraint");
  for (const Override& o : overrides) edited.set(o);
  const Context context{path, directory, edited.spans()};
  return parse(edited.document(), context);
}

}  // namespace camopt::io
