// the reports of camopt dynamics: rigid (contact forces, cam torque, Hertz stress, spring
// margins, the speed map), flexible (dynamic against kinematic lift, forces, bounce, spring
// coil forces, the speed map) and modes (natural frequencies, mode shapes).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

// the table's rows per (engine speed, control position), family labels when there are several
struct Runs {
  CsvData csv;
  std::vector<Group> groups;
  std::vector<std::string> labels;
};

Runs read_runs(ReportData& data, const Folder& dir) {
  Runs r{dir.csv("dynamics.csv"), {}, {}};
  const std::string control = r.csv.find("control_mm") ? "control_mm" : "control_deg";
  r.groups = group_rows(r.csv, {"rpm", control});
  r.labels = family_labels({"rpm", control}, r.groups);
  if (r.groups.size() > 1) data.family = r.labels;
  return r;
}

// the columns named <prefix>...<suffix>, with the middle part (a contact's or spring's name)
std::vector<std::pair<std::string, std::string>> columns_between(const CsvData& csv, const std::string& prefix,
                                                                 const std::string& suffix) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& c : csv.columns)
    if (c.starts_with(prefix) && c.ends_with(suffix) && c.size() > prefix.size() + suffix.size())
      out.emplace_back(c, c.substr(prefix.size(), c.size() - prefix.size() - suffix.size()));
  return out;
}

// a plot of a column against cam angle, one series per run; returns it (nullptr: not added)
Plot* add_runs_plot(ReportData& data, const Runs& r, const std::string& id, const std::string& title,
                    const std::string& section, const std::string& column, const std::string& name, bool main = false) {
  if (!r.csv.find(column)) return nullptr;
  Plot p = line_plot(id, title, section, "cam_deg", column, "dynamics");
  p.main = main;
  if (!add_group_series(p, r.csv, r.groups, r.labels, "cam_deg", column, name)) return nullptr;
  data.plots.push_back(std::move(p));
  return &data.plots.back();
}

// the distinct values of a key of the results' entries, sorted
std::vector<double> distinct(const nlohmann::json& entries, const std::string& key) {
  std::vector<double> v;
  for (const auto& e : entries)
    if (e.contains(key) && e[key].is_number()) v.push_back(e[key].get<double>());
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// a quantity over engine speed x control position: a heatmap when the run swept both, a
// line plot over engine speed when it swept the speed alone, nothing otherwise
void add_speed_map(ReportData& data, const nlohmann::json& entries, const std::string& title, const Axis& z,
                   const std::function<double(const nlohmann::json&)>& value, const std::string& id = "speed-map") {
  const std::string control = !entries.empty() && entries.front().contains("control_mm") ? "control_mm" : "control_deg";
  const std::vector<double> rpm = distinct(entries, "rpm"), controls = distinct(entries, control);
  if (rpm.size() < 2) return;
  add_section(data, "speed-map", "Speed map");
  Plot p;
  p.id = id;
  p.title = title;
  p.section = "speed-map";
  p.x = axis_of("rpm");
  p.main = id == "speed-map";
  if (controls.size() < 2) {
    p.kind = PlotKind::line;
    p.y = z;
    Series s{z.label, {}, {}, {}, -1, false};
    for (const auto& e : entries) s.x.push_back(e["rpm"].get<double>()), s.y.push_back(value(e));
    p.series.push_back(std::move(s));
  } else {
    p.kind = PlotKind::heatmap;
    p.y = axis_of(control);
    p.color = z;
    p.x_values = rpm;
    p.y_values = controls;
    p.z.assign(rpm.size() * controls.size(), std::numeric_limits<double>::quiet_NaN());
    for (const auto& e : entries) {
      const auto col = std::lower_bound(rpm.begin(), rpm.end(), e["rpm"].get<double>()) - rpm.begin();
      const auto row = std::lower_bound(controls.begin(), controls.end(), e[control].get<double>()) - controls.begin();
      p.z[static_cast<std::size_t>(row) * rpm.size() + static_cast<std::size_t>(col)] = value(e);
    }
  }
  data.plots.push_back(std::move(p));
}

// the smallest contact force of a rigid result over its contacts [N]
double smallest_force(const nlohmann::json& result) {
  double f = std::numeric_limits<double>::infinity();
  if (result.contains("connections"))
    for (const auto& [name, c] : result["connections"].items())
      if (c.contains("min_force_N") && c["min_force_N"].is_number()) f = std::min(f, c["min_force_N"].get<double>());
  return std::isfinite(f) ? f : std::numeric_limits<double>::quiet_NaN();
}

// rigid: the separation speed of every contact per control position
Table separation_table(const nlohmann::json& summary) {
  Table t{"separation", "Separation speed of every contact", "speed-map",
          {"control", "contact", "separation speed [rpm]", "at cam angle [deg]"}, {}, {}};
  if (!summary.contains("separation")) return t;
  for (const auto& s : summary["separation"]) {
    const std::string control = s.contains("control_mm") ? format_scalar(s["control_mm"]) + " mm"
                                                         : format_scalar(s.value("control_deg", nlohmann::json(0))) + " deg";
    if (!s.contains("contacts")) continue;
    for (const auto& [name, c] : s["contacts"].items())
      t.rows.push_back({control, name, c.contains("separation_rpm") ? format_scalar(c["separation_rpm"]) : "",
                        c.contains("at_cam_deg") ? format_scalar(c["at_cam_deg"]) : ""});
  }
  return t;
}

// per result row of the summary: rpm, control and the scalar extremes
void add_results_table(ReportData& data, const nlohmann::json& summary, const std::string& file) {
  add_section(data, "summary", "Summary");
  data.tables.push_back(rows_table("summary", "Results per engine speed and control position (summary.json)", "summary",
                                   member(summary, "results", file), {"rpm", "control_deg", "control_mm"}));
}

}  // namespace

void collect_rigid(ReportData& data, const Folder& dir, const nlohmann::json& summary) {
  const std::string file = (dir / "summary.json").string();
  data.title = "camopt dynamics rigid: " + format_scalar(member(summary, "design", file));
  add_facts(data, summary, {"design", "design_file", "model", "mode", "step_cam_deg", "points_per_position"});
  const Runs r = read_runs(data, dir);
  // the mechanism at the run's control positions
  add_scene(data, scene_source_of_summary(summary, member(summary, "results", file), number(summary, "step_cam_deg", file),
                                          0.0, 360.0));
  // contact forces and stresses, cam torque, spring margins
  add_section(data, "forces", "Forces");
  bool first = true;
  for (const auto& [column, name] : columns_between(r.csv, "contact_", "_force_N")) {
    if (name.ends_with("_rigid")) continue;
    Plot* p = add_runs_plot(data, r, "force-" + name, name + ": contact force", "forces", column, "force", first);
    if (p && r.csv.find("contact_" + name + "_rigid_force_N"))
      add_group_series(*p, r.csv, r.groups, r.labels, "cam_deg", "contact_" + name + "_rigid_force_N", "rigid", true);
    first = first && !p;
  }
  add_runs_plot(data, r, "cam-torque", "Cam torque", "forces", "cam_torque_Nm", "cam torque", true);
  for (const auto& [column, name] : columns_between(r.csv, "contact_", "_hertz_MPa"))
    add_runs_plot(data, r, "hertz-" + name, name + ": Hertz stress", "forces", column, "Hertz stress");
  for (const auto suffix : {"_margin_N", "_margin_Nm"})
    for (const auto& [column, name] : columns_between(r.csv, "spring_", suffix))
      add_runs_plot(data, r, "spring-margin-" + name, name + ": spring margin", "forces", column, "margin");
  // the speed map, the separation speeds, the results
  const nlohmann::json& results = member(summary, "results", file);
  add_speed_map(data, results, "Smallest contact force over engine speed and control position (at or below 0: separation)",
                {"smallest contact force", "N"}, smallest_force);
  Table sep = separation_table(summary);
  if (!sep.rows.empty()) {
    add_section(data, "speed-map", "Speed map");
    data.tables.push_back(std::move(sep));
  }
  add_results_table(data, summary, file);
}

// the hydraulic lash adjusters (hla_<node>_* columns): chamber pressure, plunger, force, flows
// and ball lift against cam angle; the plunger's drift per revolution over the speed map
void add_hla_plots(ReportData& data, const Runs& r, const nlohmann::json& summary) {
  const auto hlas = columns_between(r.csv, "hla_", "_pressure_MPa");
  if (hlas.empty()) return;
  add_section(data, "hla", "Hydraulic lash adjusters");
  for (const auto& [pressure, node] : hlas) {
    const std::string n = "hla_" + node + "_", who = "HLA under " + node + ": ";
    add_runs_plot(data, r, "hla-pressure-" + node, who + "chamber pressure", "hla", pressure, "pressure");
    add_runs_plot(data, r, "hla-plunger-" + node, who + "plunger extension (pump-up > 0)", "hla", n + "plunger_mm",
                  "plunger");
    add_runs_plot(data, r, "hla-force-" + node, who + "force on the pivot", "hla", n + "force_N", "force");
    if (Plot* p = add_runs_plot(data, r, "hla-flow-" + node, who + "leak and refill", "hla", n + "leak_mm3_per_s", "leak"))
      add_group_series(*p, r.csv, r.groups, r.labels, "cam_deg", n + "refill_mm3_per_s", "refill");
    add_runs_plot(data, r, "hla-ball-" + node, who + "check-valve ball lift", "hla", n + "ball_lift_mm", "ball lift");
    const std::string key = n + "drift_mm";
    if (summary.contains("speed_map"))
      add_speed_map(
          data, summary["speed_map"], who + "plunger drift per revolution (pump-up > 0, collapse < 0)", axis_of(key),
          [key](const nlohmann::json& e) {
            return e.contains(key) && e[key].is_number() ? e[key].get<double>() : std::numeric_limits<double>::quiet_NaN();
          },
          "hla-drift-map-" + node);
  }
}

void collect_flexible(ReportData& data, const Folder& dir, const nlohmann::json& summary) {
  const std::string file = (dir / "summary.json").string();
  data.title = "camopt dynamics flexible: " + format_scalar(member(summary, "design", file));
  add_facts(data, summary, {"design", "design_file", "model", "step_cam_deg", "revolutions", "start",
                            "relative_tolerance", "absolute_tolerance"});
  const Runs r = read_runs(data, dir);
  // the dynamic lift over the kinematic one (dashed), the lift loss, the mechanism (its
  // kinematic poses)
  add_section(data, "lift", "Dynamic lift");
  if (Plot* p = add_runs_plot(data, r, "dynamic-lift", "Dynamic valve lift (kinematic dashed)", "lift", "lift_mm",
                              "dynamic lift", true)) {
    p->y.label = "valve lift";
    add_group_series(*p, r.csv, r.groups, r.labels, "cam_deg", "lift_kinematic_mm", "kinematic lift", true);
  }
  add_runs_plot(data, r, "lift-loss", "Lift loss (kinematic - dynamic)", "lift", "lift_loss_mm", "lift loss");
  add_scene(data, scene_source_of_summary(summary, member(summary, "results", file), number(summary, "step_cam_deg", file),
                                          0.0, 360.0));
  // contact and seat forces (bounce), cam torque, spring coil forces
  add_section(data, "forces", "Forces");
  bool first = true;
  for (const auto& [column, name] : columns_between(r.csv, "contact_", "_force_N")) {
    first = !add_runs_plot(data, r, "force-" + name, name + ": contact force", "forces", column, "force", first) && first;
  }
  for (const auto& c : r.csv.columns)
    if (c.starts_with("seat_") && c.ends_with("_force_N"))
      add_runs_plot(data, r, "seat-" + c, "Seat force (bounce where it drops to 0)", "forces", c, "seat force");
  add_runs_plot(data, r, "cam-torque", "Cam torque", "forces", "cam_torque_Nm", "cam torque");
  for (const auto& [column, name] : columns_between(r.csv, "spring_", "_retainer_N"))
    if (Plot* p = add_runs_plot(data, r, "spring-" + name, name + ": coil forces at retainer and seat", "forces", column,
                                "retainer"))
      add_group_series(*p, r.csv, r.groups, r.labels, "cam_deg", "spring_" + name + "_seat_N", "seat");
  // the speed map and the results
  if (summary.contains("speed_map"))
    add_speed_map(data, summary["speed_map"], "Largest lift loss over engine speed and control position",
                  axis_of("max_lift_loss_mm"), [](const nlohmann::json& e) {
                    return e.contains("max_lift_loss_mm") && e["max_lift_loss_mm"].is_number()
                               ? e["max_lift_loss_mm"].get<double>()
                               : std::numeric_limits<double>::quiet_NaN();
                  });
  add_hla_plots(data, r, summary);
  add_results_table(data, summary, file);
}

void collect_modes(ReportData& data, const Folder& dir, const nlohmann::json& summary) {
  const std::string file = (dir / "summary.json").string();
  data.title = "camopt dynamics modes: " + format_scalar(member(summary, "design", file));
  add_facts(data, summary, {"design", "design_file", "model", "linearisation", "driver_contacts",
                            "mode_shape_normalisation"});
  const CsvData csv = dir.csv("modes.csv");
  const nlohmann::json& results = member(summary, "results", file);
  // the natural frequencies per linearisation point
  add_section(data, "modes", "Natural frequencies and mode shapes");
  Table t{"frequencies", "Natural frequencies", "modes", {"control", "cam angle [deg]", "kinematic lift [mm]"}, {}, {}};
  std::size_t modes = 0;
  for (const auto& res : results) modes = std::max(modes, member(res, "frequencies_Hz", file, "results").size());
  for (std::size_t k = 0; k < modes; ++k) t.columns.push_back("mode " + std::to_string(k + 1) + " [Hz]");
  for (const auto& res : results) {
    std::vector<std::string> row{format_scalar(res.contains("control_mm") ? res["control_mm"] : res.value("control_deg", nlohmann::json(0))),
                                 format_scalar(member(res, "cam_deg", file, "results")),
                                 format_scalar(res.value("lift_kinematic_mm", nlohmann::json()))};
    for (const auto& f : res["frequencies_Hz"]) row.push_back(format_scalar(f));
    row.resize(t.columns.size());
    t.rows.push_back(std::move(row));
  }
  data.tables.push_back(std::move(t));
  // the mode shapes: amplitude per coordinate (index), one series per mode, one plot per point
  std::vector<std::string> coords;
  for (const auto& c : csv.columns)
    if (c.ends_with("_per_sqrt_kg")) coords.push_back(c);
  const std::vector<Group> points = group_rows(csv, {"control_deg", "control_mm", "cam_deg"});
  for (std::size_t g = 0; g < points.size(); ++g) {
    Plot p;
    p.id = "mode-shapes-" + std::to_string(g + 1);
    p.title = "Mode shapes at cam " + format_number(points[g].keys.back()) + " deg";
    p.section = "modes";
    p.x = {"coordinate", "-"};
    p.y = {"amplitude", "mm/sqrt(kg) or rad/sqrt(kg)"};
    p.main = g == 0;
    for (std::size_t i = 0; i < coords.size(); ++i) p.x_values.push_back(static_cast<double>(i + 1));
    for (std::size_t row = points[g].begin; row < points[g].end; ++row) {
      Series s{"mode " + format_number(csv.at("mode")[row]) + " (" + format_number(std::round(csv.at("frequency_Hz")[row])) + " Hz)",
               {}, {}, {}, -1, false};
      for (const auto& c : coords) s.y.push_back(csv.at(c)[row]);
      p.series.push_back(std::move(s));
    }
    data.plots.push_back(std::move(p));
  }
  Table names{"coordinates", "Mode shape coordinates", "modes", {"coordinate", "name [unit of amplitude]"}, {}, {}};
  for (std::size_t i = 0; i < coords.size(); ++i) names.rows.push_back({std::to_string(i + 1), heading(axis_of(coords[i]))});
  data.tables.push_back(std::move(names));
  if (summary.contains("springs_alone"))
    data.tables.push_back(key_value_table("springs-alone", "Springs alone (surge)", "modes", summary["springs_alone"]));
}

}  // namespace camopt::report::detail
