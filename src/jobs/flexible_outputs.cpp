// the outputs of `camopt dynamics --model flexible` (flexible_outputs.hpp)
#include "flexible_outputs.hpp"

#include <charconv>

#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/flexible_summary.hpp"

namespace camopt::jobs {

namespace {

std::string shortest_number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

io::Columns flexible_columns(const DynamicsSetup& su, const std::vector<FlexibleRun>& runs, bool coil_displacements) {
  using Run = FlexibleRun;
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t nc = mech.connections.size();
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";
  std::vector<std::string> header;
  std::vector<std::vector<double>> cols;
  auto add_column = [&](std::string name, auto&& value) {
    header.push_back(std::move(name));
    std::vector<double> col;
    for (const Run& r : runs)
      for (std::size_t i = 0; i < r.result.cam_deg.size(); ++i) col.push_back(value(r.result, i));
    cols.push_back(std::move(col));
  };
  using Res = dynamics::FlexibleResult;
  {
    header.push_back("rpm");
    header.push_back("control_" + su.controls.unit);
    std::vector<double> a, b;
    for (const Run& r : runs)
      for (std::size_t i = 0; i < r.result.cam_deg.size(); ++i) a.push_back(r.rpm), b.push_back(su.controls.values[r.position]);
    cols.push_back(std::move(a));
    cols.push_back(std::move(b));
  }
  add_column("cam_deg", [](const Res& r, std::size_t i) { return r.cam_deg[i]; });
  add_column("crank_deg", [&](const Res& r, std::size_t i) { return r.cam_deg[i] * model.crank_per_cam; });
  add_column("lift_kinematic_" + lift_unit, [](const Res& r, std::size_t i) { return r.lift_kinematic[i]; });
  add_column("lift_" + lift_unit, [](const Res& r, std::size_t i) { return r.lift[i]; });
  add_column("lift_loss_" + lift_unit, [](const Res& r, std::size_t i) { return r.lift_kinematic[i] - r.lift[i]; });
  // the valve's dynamic velocity and acceleration (mm -> m; an angle output stays in deg)
  const double si = angle_out ? 1.0 : 1e-3;
  add_column(angle_out ? "vel_deg_per_s" : "vel_m_per_s", [si](const Res& r, std::size_t i) { return r.velocity[i] * si; });
  add_column(angle_out ? "acc_deg_per_s2" : "acc_m_per_s2",
             [si](const Res& r, std::size_t i) { return r.acceleration[i] * si; });
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& conn = mech.connections[c];
    const bool contact = conn.kind == ConnectionKind::contact;
    const std::string n = (contact ? "contact_" : "link_") + conn.name + "_";
    add_column(n + "force_N", [nc, c](const Res& r, std::size_t i) { return r.force[i * nc + c]; });
    if (contact && model.contacts[c].friction > 0 && !model.contacts[c].rolling)
      add_column(n + "friction_W", [nc, c](const Res& r, std::size_t i) { return r.friction_power[i * nc + c]; });
  }
  const Res& first = runs.front().result;
  const bool has_seat = !first.seat_names.empty();
  if (has_seat) add_column("seat_force_N", [](const Res& r, std::size_t i) { return r.seat_force[i]; });
  const std::size_t nseat = first.seat_names.size();
  if (nseat > 1)
    for (std::size_t k = 0; k < nseat; ++k)
      add_column("seat_" + first.seat_names[k] + "_force_N",
                 [k, nseat](const Res& r, std::size_t i) { return r.seat_forces[i * nseat + k]; });
  add_column("cam_torque_Nm", [](const Res& r, std::size_t i) { return r.cam_torque[i] * 1e-3; });
  for (std::size_t e = 0; e < first.element_names.size(); ++e) {
    const int node = mech.node_index(first.element_names[e]);
    const bool angle = mech.nodes[node].kind != NodeKind::translational;
    const std::size_t ne = first.element_names.size();
    add_column("node_" + first.element_names[e] + "_deformation_" + (angle ? "deg" : "mm"),
               [e, ne, angle](const Res& r, std::size_t i) { return r.deformation[i * ne + e] * (angle ? deg_per_rad : 1.0); });
  }
  const std::size_t nch = first.chain_names.size();
  for (std::size_t s = 0; s < nch; ++s) {
    add_column("spring_" + first.chain_names[s] + "_retainer_N",
               [s, nch](const Res& r, std::size_t i) { return r.coil_force_top[i * nch + s]; });
    add_column("spring_" + first.chain_names[s] + "_seat_N",
               [s, nch](const Res& r, std::size_t i) { return r.coil_force_base[i * nch + s]; });
    add_column("spring_" + first.chain_names[s] + "_static_N",
               [s, nch](const Res& r, std::size_t i) { return r.spring_static_load[i * nch + s]; });
  }
  // hydraulic lash adjusters, named by the node they support
  const std::size_t nh = first.hla_names.size();
  for (std::size_t k = 0; k < nh; ++k) {
    const std::string n = "hla_" + first.hla_names[k] + "_";
    auto per_hla = [k, nh](const std::vector<double> Res::*v) {
      return [k, nh, v](const Res& r, std::size_t i) { return (r.*v)[i * nh + k]; };
    };
    add_column(n + "plunger_mm", per_hla(&Res::hla_plunger));
    add_column(n + "force_N", per_hla(&Res::hla_force));
    add_column(n + "pressure_MPa", per_hla(&Res::hla_pressure));
    add_column(n + "leak_mm3_per_s", per_hla(&Res::hla_leak_flow));
    add_column(n + "refill_mm3_per_s", per_hla(&Res::hla_refill_flow));
    add_column(n + "ball_lift_mm", per_hla(&Res::hla_ball_lift));
  }
  if (coil_displacements) {
    const int masses = first.layout.spring_masses;
    int k = 0;
    for (std::size_t s = 0; s < nch; ++s)
      for (int j = 1; j < first.chain_segments[s]; ++j, ++k)
        add_column("spring_" + first.chain_names[s] + "_coil" + std::to_string(j) + "_mm",
                   [k, masses](const Res& r, std::size_t i) { return r.coil_displacement[i * masses + k]; });
  }
  return {std::move(header), std::move(cols), {}};
}

nlohmann::json flexible_summary(const DynamicsSetup& su, const std::string& design_file,
                                const dynamics::FlexibleOptions& options, const std::vector<FlexibleRun>& runs,
                                double seconds) {
  using Run = FlexibleRun;
  using Res = dynamics::FlexibleResult;
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";
  const Res& first = runs.front().result;
  const bool has_seat = !first.seat_names.empty();
  nlohmann::json summary;
  summary["design"] = su.mech.name;
  summary["design_file"] = design_file;
  summary["model"] = "flexible";
  summary["step_cam_deg"] = su.range.step;
  summary["revolutions"] = options.revolutions;
  summary["relative_tolerance"] = options.relative_tolerance;
  summary["absolute_tolerance"] = options.absolute_tolerance;
  summary["run_time_s"] = seconds;
  summary["start"] = options.start_at_rest ? "rest" : "static";
  nlohmann::json parameters = nlohmann::json::array();
  for (const auto& p : first.parameters)
    parameters.push_back({{"key", p.key}, {"value", p.value}, {"unit", p.unit}, {"from_design", p.from_design}});
  summary["model_parameters"] = parameters;
  nlohmann::json results = nlohmann::json::array(), map = nlohmann::json::array();
  for (const Run& run : runs) {
    const Res& r = run.result;
    nlohmann::json j;
    j["rpm"] = run.rpm;
    j["control_" + su.controls.unit] = su.controls.values[run.position];
    j.update(flexible_run_summary(mech, model, r));
    if (r.gap_error_mm > 0.01)
      su.observer.note("dynamics (flexible): warning: at " + shortest_number(run.rpm) + " rpm contact '" +
                       r.gap_error_contact + "' carries force " + shortest_number(r.gap_error_mm) +
                       " mm off its linearised gap (cam " + shortest_number(r.gap_error_at_cam_deg) +
                       " deg): the bodies have left their kinematic path far");
    if (!r.periodic && !options.start_at_rest)
      su.observer.note("dynamics (flexible): warning: no periodic steady state at " + shortest_number(run.rpm) +
                       " rpm after " + std::to_string(r.revolutions_integrated) +
                       " revolutions (start-state difference " + shortest_number(r.periodic_difference) +
                       " tolerances); the last revolution is reported: raise --revolutions");
    const bool separates = j["any_contact_separates"].get<bool>();
    nlohmann::json point = {{"rpm", run.rpm},
                            {"control_" + su.controls.unit, su.controls.values[run.position]},
                            {"any_contact_separates", separates},
                            {"bounce_count", has_seat ? j["bounce_count"] : nlohmann::json(nullptr)},
                            {"bounce_height_" + lift_unit, has_seat ? j["bounce_height_" + lift_unit] : nlohmann::json(nullptr)},
                            {"max_lift_loss_" + lift_unit, j["max_lift_loss_" + lift_unit]}};
    // pump-up (> 0) or collapse (< 0) of every HLA over the reported revolution
    if (j.contains("hla"))
      for (const auto& h : j["hla"]) point["hla_" + h["node"].get<std::string>() + "_drift_mm"] = h["plunger_drift_mm"];
    map.push_back(point);
    results.push_back(j);
  }
  summary["results"] = results;
  summary["speed_map"] = map;
  return summary;
}

}  // namespace camopt::jobs
