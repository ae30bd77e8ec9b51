// the outputs of `camopt dynamics --contacts compliant` (compliant_outputs.hpp)
#include "compliant_outputs.hpp"

#include <algorithm>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/io/csv.hpp"

namespace camopt::jobs {

io::Columns compliant_columns(const DynamicsSetup& su, const std::vector<CompliantRun>& runs,
                                const std::vector<dynamics::RigidSweep>& rigid) {
  using Run = CompliantRun;
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t nc = mech.connections.size();
  std::vector<std::string> header;
  std::vector<std::vector<double>> cols;
  auto add_column = [&](std::string name, auto&& value) {
    header.push_back(std::move(name));
    std::vector<double> col;
    for (const Run& r : runs) {
      const double w = dynamics::cam_speed_rad_per_s(r.rpm, model.crank_per_cam);
      for (std::size_t i = 0; i < r.result.cam_deg.size(); ++i) col.push_back(value(r, rigid[r.position], i, w));
    }
    cols.push_back(std::move(col));
  };
  using Sweep = dynamics::RigidSweep;
  add_column("rpm", [](const Run& r, const Sweep&, std::size_t, double) { return r.rpm; });
  add_column("control_" + su.controls.unit,
             [&](const Run& r, const Sweep&, std::size_t, double) { return su.controls.values[r.position]; });
  add_column("cam_deg", [](const Run& r, const Sweep&, std::size_t i, double) { return r.result.cam_deg[i]; });
  add_column("crank_deg", [&](const Run& r, const Sweep&, std::size_t i, double) {
    return r.result.cam_deg[i] * model.crank_per_cam;
  });
  add_column(mech.nodes[mech.output_node].kind == NodeKind::translational ? "lift_mm" : "lift_deg",
             [](const Run&, const Sweep& a, std::size_t i, double) { return a.output[i]; });
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& conn = mech.connections[c];
    const int ci = static_cast<int>(c);
    const bool contact = conn.kind == ConnectionKind::contact;
    const std::string n = (contact ? "contact_" : "link_") + conn.name + "_";
    add_column(n + "force_N", [nc, c](const Run& r, const Sweep&, std::size_t i, double) {
      return r.result.force[i * nc + c];
    });
    add_column(n + "rigid_force_N", [ci](const Run&, const Sweep& a, std::size_t i, double w) {
      return a.force_at(i, ci, w);
    });
    if (contact && model.contacts[c].has_hertz)
      add_column(n + "hertz_MPa", [&, nc, c](const Run& r, const Sweep& a, std::size_t i, double) {
        const auto& cs = a.contact[i * nc + c];
        return dynamics::hertz_line(r.result.force[i * nc + c], model.contacts[c].width, model.contacts[c].e_star,
                                    cs.curvature_a + cs.curvature_b)
            .max_pressure;
      });
  }
  for (std::size_t r = 0; r < model.free_variables.size(); ++r) {
    const auto& var = mech.variables[model.free_variables[r]];
    std::string name = var.name;
    std::replace(name.begin(), name.end(), '.', '_');
    const double scale = var.is_angle ? deg_per_rad : 1.0;
    add_column("node_" + name + "_deviation_" + (var.is_angle ? "deg" : "mm"),
               [r, scale](const Run& run, const Sweep&, std::size_t i, double) {
                 return run.result.deviation[i * run.result.rows + r] * scale;
               });
  }
  return {std::move(header), std::move(cols), {}};
}

nlohmann::json compliant_summary(const DynamicsSetup& su, const std::string& design_file,
                                 const std::vector<CompliantRun>& runs, double seconds) {
  using Run = CompliantRun;
  const kin::Mechanism& mech = su.mech;
  const std::size_t nc = mech.connections.size();
  nlohmann::json summary = rigid_summary_head(su, design_file, "dynamics (rigid, compliant contacts)",
                                              "stiff separable contacts, CVODE (b)");
  summary["run_time_s"] = seconds;
  nlohmann::json results = nlohmann::json::array();
  for (const Run& r : runs) {
    nlohmann::json j;
    j["rpm"] = r.rpm;
    j["control_" + su.controls.unit] = su.controls.values[r.position];
    j["integrator_steps"] = r.result.steps;
    j["rhs_evaluations"] = r.result.rhs_evaluations;
    for (std::size_t c = 0; c < nc; ++c) {
      Extremes f;
      for (std::size_t i = 0; i < r.result.cam_deg.size(); ++i) f.add(r.result.force[i * nc + c], r.result.cam_deg[i]);
      j["connections"][mech.connections[c].name] = {{"max_force_N", f.max},
                                                    {"max_force_at_cam_deg", f.max_at},
                                                    {"min_force_N", f.min},
                                                    {"min_force_at_cam_deg", f.min_at},
                                                    {"stiffness_N_per_mm", r.result.stiffness[c]}};
    }
    nlohmann::json events = nlohmann::json::array();
    for (const auto& e : r.result.events)
      events.push_back({{"contact", e.contact}, {"cam_deg", e.cam_deg}, {"event", e.opens ? "opens" : "closes"}});
    j["events"] = events;
    results.push_back(j);
  }
  summary["results"] = results;
  return summary;
}

}  // namespace camopt::jobs
