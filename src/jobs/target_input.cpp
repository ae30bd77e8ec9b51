#include "target_input.hpp"


namespace camopt::jobs {

ValveTarget read_valve_target(const io::CsvTable& table, const std::string& path, const DesignSpec& spec,
                              const synthesis::TargetLiftOptions& options, Observer& observer) {
  ValveTarget t;
  t.rows = table.rows();
  const io::AngleTable at = io::read_angle_table(table, {"lift_mm", "valve_lift_mm", "tappet_lift_mm"});
  t.basis = at.basis;
  std::vector<double> cam_deg = at.angle_deg;
  if (at.basis == io::AngleBasis::crank)
    for (auto& a : cam_deg) a /= spec.driver.crank_per_cam;
  synthesis::TargetLiftOptions fit = options;
  fit.source = path;
  if (const Status st = synthesis::fit_target_lift(cam_deg, at.value, at.lines, fit, t.fit); !st.ok())
    throw NumericalError(st);
  if (t.fit.closed_on_base_circle) observer.note("target " + path + ": " + t.fit.closure_message);
  return t;
}

}  // namespace camopt::jobs
