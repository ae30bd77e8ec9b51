// the reports of the runs that make a lift or a cam: a lift table (camopt lift), synthesize
// (profile.csv, grinding.csv, report.json) and optimize (lift.csv and the same files, the
// constraint margins and the verification).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <system_error>

#include "camopt/core/error.hpp"
#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

// the first column named `prefix`<unit> that is not per second (the SI copies at --rpm)
std::string column_with_prefix(const CsvData& csv, const std::string& prefix) {
  for (const auto& c : csv.columns)
    if (c.rfind(prefix, 0) == 0 && c.find("_per_s") == std::string::npos && c != prefix + "loss_mm") return c;
  return "";
}

// the angle column of a lift table: cam_deg or crank_deg
std::string angle_column(const CsvData& csv) {
  for (const char* name : {"cam_deg", "crank_deg", "cam_angle_deg", "crank_angle_deg"})
    if (csv.find(name)) return name;
  throw InputError(csv.file + ": no angle column (cam_deg or crank_deg)");
}

// windows of consecutive rows where `inside` holds, as bands over x
std::vector<Band> windows(const std::vector<double>& x, const std::vector<bool>& inside, const std::string& label) {
  std::vector<Band> bands;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!inside[i]) continue;
    if (i == 0 || !inside[i - 1]) bands.push_back({x[i], x[i], label});
    bands.back().to = x[i];
  }
  return bands;
}

// the cam to scale, coloured by its radius of curvature, with the base circle dashed; the
// radius of curvature against profile angle with the concave windows as bands
void add_profile_plots(ReportData& data, const Folder& dir, const nlohmann::json& report) {
  if (!dir.has("profile.csv")) {
    data.notes.push_back("no profile.csv in the folder: the cam is not drawn");
    return;
  }
  const CsvData csv = dir.csv("profile.csv");
  add_section(data, "profile", "Cam profile");
  Plot p;
  p.id = "profile";
  p.title = "Cam profile (to scale), coloured by radius of curvature";
  p.section = "profile";
  p.kind = PlotKind::profile;
  p.x = axis_of("x_mm");
  p.y = axis_of("y_mm");
  p.color = {"radius of curvature", axis_of("radius_of_curvature_mm").unit};
  p.main = true;
  Series profile{"profile", csv.at("x_mm"), csv.at("y_mm"), csv.at("radius_of_curvature_mm"), -1, false};
  p.series.push_back(std::move(profile));
  // the base circle
  const nlohmann::json& prof = member(report, "profile", (dir / "report.json").string());
  const double base = number(prof, "base_circle_radius_mm", (dir / "report.json").string(), "profile");
  Series circle{"base circle", {}, {}, {}, -1, true};
  for (int i = 0; i <= 360; ++i) {
    circle.x.push_back(base * std::cos(i * kPi / 180.0));
    circle.y.push_back(base * std::sin(i * kPi / 180.0));
  }
  p.series.push_back(std::move(circle));
  data.plots.push_back(std::move(p));
  // radius of curvature against profile angle, concave windows shaded
  Plot r = line_plot("profile-curvature", "Radius of curvature of the profile", "profile", "angle_deg",
                     "radius_of_curvature_mm", "profile-angle");
  r.x.label = "profile angle";
  add_group_series(r, csv, group_rows(csv, {}), {""}, "angle_deg", "radius_of_curvature_mm", "radius of curvature");
  const auto& rho = csv.at("radius_of_curvature_mm");
  std::vector<bool> concave(rho.size());
  for (std::size_t i = 0; i < rho.size(); ++i) concave[i] = rho[i] < 0;
  r.bands = windows(csv.at("angle_deg"), concave, "concave");
  data.plots.push_back(std::move(r));
}

// the grinding table: master lift against cam angle
void add_grinding_plot(ReportData& data, const Folder& dir) {
  if (!dir.has("grinding.csv")) return;
  const CsvData csv = dir.csv("grinding.csv");
  Plot g = line_plot("grinding", "Grinding table: master lift", "profile", "cam_deg", "master_lift_mm", "");
  add_group_series(g, csv, group_rows(csv, {}), {""}, "cam_deg", "master_lift_mm", "master lift");
  data.plots.push_back(std::move(g));
}

// the linked plot of `unit`'s quantity among the SVAJ plots ("" when none)
Plot* svaj_plot_of_unit(ReportData& data, const std::string& unit) {
  for (Plot& p : data.plots)
    if (p.link_group == "svaj" && p.y.unit == unit) return &p;
  return nullptr;
}

// bands over the angles a constraint is active at, each half a grid step wide on either side
// (the grid step: the smallest spacing of the angles, 0.5 deg for a single one); angles one
// step apart merged
std::vector<Band> active_bands(const nlohmann::json& angles, const std::string& label) {
  std::vector<double> at;
  for (const auto& a : angles) at.push_back(a.is_string() ? std::strtod(a.get<std::string>().c_str(), nullptr) : a.get<double>());
  std::sort(at.begin(), at.end());
  double step = 0.5;
  for (std::size_t i = 1; i < at.size(); ++i)
    if (at[i] > at[i - 1]) step = std::min(step, at[i] - at[i - 1]);
  std::vector<Band> bands;
  for (double a : at) {
    if (!bands.empty() && a - bands.back().to <= 1.5 * step) {
      bands.back().to = a + 0.5 * step;
      continue;
    }
    bands.push_back({a - 0.5 * step, a + 0.5 * step, label});
  }
  return bands;
}

// the constraint margins: a table (failed rows marked), limit lines and active bands on the
// SVAJ plot of the constraint's unit (the lift plot for the others)
void add_constraints(ReportData& data, const nlohmann::json& constraints, const std::string& file) {
  add_section(data, "constraints", "Constraints");
  Table t{"constraints", "Constraint margins at the optimum", "constraints",
          {"constraint", "unit", "limit", "limit is", "worst", "margin", "where [cam deg]", "satisfied"}, {}, {}};
  for (const auto& [name, c] : constraints.items()) {
    const std::string unit = c.value("unit", "");
    const std::string where = c.contains("worst_at_cam_deg") ? format_scalar(c["worst_at_cam_deg"]) +
                                                                   (c.contains("worst_at") ? " (" + format_scalar(c["worst_at"]) + ")" : "")
                                                             : "";
    const bool satisfied = c.value("satisfied", false);
    if (!satisfied) t.failed_rows.push_back(static_cast<int>(t.rows.size()));
    t.rows.push_back({name, unit, format_scalar(member(c, "limit", file, "constraints." + name)),
                      c.value("limit_is", ""), format_scalar(member(c, "worst", file, "constraints." + name)),
                      format_scalar(member(c, "margin", file, "constraints." + name)), where,
                      satisfied ? "yes" : "no"});
    // its limit line and active angles on its plot
    const std::string plot_unit = unit == "mm" && name.rfind("lift", 0) != 0 ? "" : unit;
    Plot* plot = plot_unit.empty() ? nullptr : svaj_plot_of_unit(data, plot_unit);
    if (plot) plot->limits.push_back({number(c, "limit", file, "constraints." + name), name});
    if (!plot) plot = svaj_plot_of_unit(data, "mm");
    if (plot && c.contains("active_at_cam_deg")) {
      const auto bands = active_bands(c["active_at_cam_deg"], name + " active");
      plot->bands.insert(plot->bands.end(), bands.begin(), bands.end());
    }
  }
  data.tables.push_back(std::move(t));
}

// optimize --verify: every check, failed rows marked, and the verdict
void add_verification(ReportData& data, const nlohmann::json& report) {
  const auto it = report.find("verification");
  if (it == report.end()) return;
  Table t{"verification", "Verification of the made design (--verify)", "constraints",
          {"model", "check", "value", "limit", "limit is", "unit", "where", "passed"}, {}, {}};
  for (const auto& c : *it) {
    const bool passed = c.value("passed", false);
    if (!passed) t.failed_rows.push_back(static_cast<int>(t.rows.size()));
    const std::string value = c.contains("failure") ? format_scalar(c["failure"])
                              : c.contains("count") ? format_scalar(c["count"])
                                                    : format_scalar(c.value("value", nlohmann::json()));
    t.rows.push_back({c.value("model", ""), c.value("check", ""), value,
                      c.contains("limit") ? format_scalar(c["limit"]) : "", c.value("limit_is", ""),
                      c.value("unit", ""), c.value("at", ""), passed ? "yes" : "no"});
  }
  data.tables.push_back(std::move(t));
  if (report.contains("verified")) data.passed = report["verified"].get<bool>();
}

// report.json's "convergence" (every progress report of the solvers: each ipopt iteration,
// nlopt evaluations at most every 0.05 s, each phase's end): the objective and the worst
// normalised violation against the run's time, one series per phase
void add_convergence_plots(ReportData& data, const nlohmann::json& report) {
  const auto it = report.find("convergence");
  if (it == report.end() || !it->is_array() || it->empty()) {
    data.notes.push_back("no convergence history in report.json");
    return;
  }
  Plot objective = line_plot("convergence-objective", "Objective during the solve", "convergence", "time_s",
                             "objective", "convergence");
  Plot violation = line_plot("convergence-violation", "Worst normalised violation during the solve", "convergence",
                             "time_s", "violation_normalised", "convergence");
  objective.x.label = violation.x.label = "solver time";
  for (const auto& row : *it) {
    const std::string phase = row.value("phase", std::string());
    if (objective.series.empty() || objective.series.back().name != phase) {
      objective.series.push_back({phase, {}, {}, {}, -1, false});
      violation.series.push_back({phase, {}, {}, {}, -1, false});
    }
    const auto value = [&](const char* key) {
      const auto v = row.find(key);
      return v != row.end() && v->is_number() ? v->get<double>() : std::numeric_limits<double>::quiet_NaN();
    };
    for (Plot* p : {&objective, &violation}) p->series.back().x.push_back(value("elapsed_s"));
    objective.series.back().y.push_back(value("objective"));
    violation.series.back().y.push_back(value("violation_normalised"));
  }
  add_section(data, "convergence", "Convergence");
  data.plots.push_back(std::move(objective));
  data.plots.push_back(std::move(violation));
}

}  // namespace

void add_svaj_plots(ReportData& data, const CsvData& csv, const std::vector<Group>& groups,
                    const std::vector<std::string>& labels, const std::string& angle, const std::string& subject) {
  add_section(data, "svaj", "Lift, velocity, acceleration and jerk");
  struct Quantity {
    const char* prefix;
    const char* id;
    const char* name;
    bool main;
  };
  for (const Quantity q : {Quantity{"lift_", "svaj-lift", "lift", true}, Quantity{"vel_", "svaj-velocity", "velocity", false},
                           Quantity{"acc_", "svaj-acceleration", "acceleration", true},
                           Quantity{"jerk_", "svaj-jerk", "jerk", false}}) {
    const std::string column = column_with_prefix(csv, q.prefix);
    if (column.empty()) continue;
    std::string title = subject + " " + q.name;
    title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
    Plot p = line_plot(q.id, title, "svaj", angle, column, "svaj");
    p.y.label = subject + " " + q.name;
    p.main = q.main;
    if (add_group_series(p, csv, groups, labels, angle, column, q.name)) data.plots.push_back(std::move(p));
  }
}

void collect_lift_table(ReportData& data, const fs::path& csv_path) {
  const CsvData csv = read_csv(csv_path);
  const std::string angle = angle_column(csv);
  if (column_with_prefix(csv, "lift_").empty())
    throw InputError(csv.file + ": no lift column (lift_mm): not a lift table of camopt lift");
  data.title = "camopt lift: " + csv_path.filename().string();
  data.facts.push_back({"lift table", csv_path.filename().string()});
  data.facts.push_back({"points", std::to_string(csv.rows())});
  add_svaj_plots(data, csv, group_rows(csv, {}), {""}, angle, "valve");
}

void collect_synthesize(ReportData& data, const Folder& dir, const nlohmann::json& report) {
  const std::string file = (dir / "report.json").string();
  data.title = "camopt synthesize: " + format_scalar(member(report, "design", file));
  add_facts(data, report, {"design", "design_file", "target_file", "cam", "connection", "follower_shape"});
  // the cam to scale and its curvature, the grinding table
  add_profile_plots(data, dir, report);
  add_grinding_plot(data, dir);
  // the design it wrote, read once for the animation and the check of the cam
  SceneSource scene{dir / "design.toml"};
  scene.compiled = compile_design_file(scene.design);
  add_scene(data, scene);
  if (scene.compiled) add_made_cam_plots(data, *scene.compiled, report);
  // every key of report.json
  add_section(data, "summary", "Summary");
  data.tables.push_back(key_value_table("summary", "report.json", "summary", report));
}

void collect_optimize(ReportData& data, const Folder& dir, const nlohmann::json& report) {
  const std::string file = (dir / "report.json").string();
  data.title = "camopt optimize: " + format_scalar(member(report, "design", file));
  add_facts(data, report, {"design", "design_file", "constraints_file", "constraint_set", "solver", "status",
                           "iterations", "time_s"});
  // the lift and its derivatives, one series per control position of a swing cam
  if (dir.has("lift.csv")) {
    const CsvData csv = dir.csv("lift.csv");
    const std::vector<Group> groups = group_rows(csv, {"control"});
    data.family = family_labels({"control"}, groups);
    if (groups.size() < 2) data.family.clear();
    add_svaj_plots(data, csv, groups, data.family, "cam_deg", "valve");
    SceneSource scene{dir / "design.toml"};
    if (groups.size() > 1)
      for (const Group& g : groups) scene.request.controls.push_back(g.keys.front());
    add_scene(data, scene);
  } else {
    data.notes.push_back("no lift.csv: the run wrote report.json alone (an infeasible constraint set)");
  }
  // the constraints at the optimum (limits, active angles), the verification
  if (const auto it = report.find("constraints"); it != report.end()) add_constraints(data, *it, file);
  add_verification(data, report);
  add_convergence_plots(data, report);
  // the cam it made
  add_profile_plots(data, dir, report);
  add_grinding_plot(data, dir);
  add_section(data, "summary", "Summary");
  nlohmann::json rest = report;
  for (const char* big : {"constraints", "verification", "conflicting_constraints", "convergence"}) rest.erase(big);
  data.tables.push_back(key_value_table("summary", "report.json", "summary", rest));
  if (const auto it = report.find("conflicting_constraints"); it != report.end())
    data.tables.push_back(rows_table("conflicts", "Conflicting constraints (infeasible set)", "constraints", *it, {"name"}));
}

}  // namespace camopt::report::detail
