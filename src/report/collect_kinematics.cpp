// the report of camopt kinematics: the valve's lift and derivatives, every node's, every
// contact's quantities (each one series per control position), the summary's extremes.
#include <algorithm>

#include "camopt/core/error.hpp"
#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

// the contacts of the table: every "<name>_pressure_angle_deg" column
std::vector<std::string> contact_names(const CsvData& csv) {
  std::vector<std::string> names;
  const std::string suffix = "_pressure_angle_deg";
  for (const auto& c : csv.columns)
    if (c.ends_with(suffix)) names.push_back(c.substr(0, c.size() - suffix.size()));
  return names;
}

// the node coordinates' columns: "finger_angle_deg", "valve_disp_mm", "lever_x_mm" (those
// with a velocity column "<prefix>vel_..." beside them, outside the valve and the contacts)
std::vector<std::string> node_columns(const CsvData& csv, const std::vector<std::string>& contacts) {
  std::vector<std::string> out;
  for (const auto& c : csv.columns) {
    if (c.starts_with("lift_") || c.starts_with("control_") || c == "cam_deg" || c == "driver_mm") continue;
    if (std::any_of(contacts.begin(), contacts.end(), [&](const std::string& k) { return c.starts_with(k + "_"); }))
      continue;
    const std::size_t cut = c.rfind('_');
    if (cut == std::string::npos) continue;
    const std::string prefix = c.substr(0, cut + 1);
    if (std::any_of(csv.columns.begin(), csv.columns.end(),
                    [&](const std::string& k) { return k.starts_with(prefix + "vel_"); }) &&
        c.find("_vel_") == std::string::npos && c.find("_acc_") == std::string::npos &&
        c.find("_jerk_") == std::string::npos)
      out.push_back(c);
  }
  return out;
}

// the first column among `names` that the table has ("" when none)
std::string first_of(const CsvData& csv, std::initializer_list<std::string> names) {
  for (const auto& n : names)
    if (csv.find(n)) return n;
  return "";
}

// a node coordinate whose velocity is the valve's, column for column (the output node: its
// plots would repeat the valve's lift plots)
bool repeats_valve(const CsvData& csv, const std::string& base) {
  const std::string prefix = base.substr(0, base.rfind('_') + 1);
  const std::vector<double>* valve = nullptr;
  for (const auto& c : csv.columns)
    if (c.starts_with("vel_") && c.find("_per_s") == std::string::npos) valve = csv.find(c);
  for (const auto& c : csv.columns)
    if (valve && c.starts_with(prefix + "vel_") && c.find("_per_s") == std::string::npos) return *csv.find(c) == *valve;
  return false;
}

struct Sweep {
  const CsvData& csv;
  std::vector<Group> groups;
  std::vector<std::string> labels;
  std::string angle;
};

// a plot of one column, added when the column is there and not zero everywhere
void add_column_plot(ReportData& data, const Sweep& sw, const std::string& id, const std::string& title,
                     const std::string& section, const std::string& column, const std::string& name) {
  if (column.empty() || !sw.csv.find(column)) return;
  Plot p = line_plot(id, title, section, sw.angle, column, "svaj");
  if (add_group_series(p, sw.csv, sw.groups, sw.labels, sw.angle, column, name)) data.plots.push_back(std::move(p));
}

// a node coordinate and its derivatives, one plot each
void add_node_plots(ReportData& data, const Sweep& sw, const std::string& base) {
  const std::string prefix = base.substr(0, base.rfind('_') + 1);  // "finger_angle_"
  const std::string name = prefix.substr(0, prefix.size() - 1);     // "finger_angle"
  const std::string readable = axis_of(base).label;                 // "finger angle"
  add_column_plot(data, sw, "node-" + name, readable, "nodes", base, readable);
  for (const char* d : {"vel_", "acc_", "jerk_"}) {
    std::string column;
    for (const auto& c : sw.csv.columns)
      if (c.starts_with(prefix + d) && c.find("_per_s") == std::string::npos) column = c;
    const std::string what = d == std::string("vel_") ? "velocity" : d == std::string("acc_") ? "acceleration" : "jerk";
    add_column_plot(data, sw, "node-" + name + "-" + what, readable + " " + what, "nodes", column, readable);
  }
}

// a contact's pressure angle, radii, entrainment, sliding, roller speed and gap (the SI
// columns when the run had --rpm)
void add_contact_plots(ReportData& data, const Sweep& sw, const std::string& c) {
  const std::string n = c + "_";
  add_column_plot(data, sw, "contact-" + c + "-pressure-angle", c + ": pressure angle", "contacts",
                  n + "pressure_angle_deg", "pressure angle");
  add_column_plot(data, sw, "contact-" + c + "-radius-a", c + ": radius of curvature of body a", "contacts",
                  n + "radius_a_mm", "radius a");
  add_column_plot(data, sw, "contact-" + c + "-radius-b", c + ": radius of curvature of body b", "contacts",
                  n + "radius_b_mm", "radius b");
  add_column_plot(data, sw, "contact-" + c + "-entrainment", c + ": entrainment speed", "contacts",
                  first_of(sw.csv, {n + "entrainment_m_per_s", n + "entrainment_mm_per_deg", n + "entrainment_mm_per_mm"}),
                  "entrainment");
  add_column_plot(data, sw, "contact-" + c + "-sliding", c + ": sliding speed", "contacts",
                  first_of(sw.csv, {n + "sliding_m_per_s", n + "sliding_mm_per_deg", n + "sliding_mm_per_mm"}), "sliding");
  add_column_plot(data, sw, "contact-" + c + "-roller-speed", c + ": roller speed", "contacts",
                  first_of(sw.csv, {n + "roller_rpm", n + "roller_speed_rad_per_deg", n + "roller_speed_rad_per_mm"}),
                  "roller speed");
  add_column_plot(data, sw, "contact-" + c + "-gap", c + ": lash gap", "contacts", n + "gap_mm", "gap");
}

}  // namespace

void collect_kinematics(ReportData& data, const Folder& dir, const nlohmann::json& summary) {
  const std::string file = (dir / "summary.json").string();
  data.title = "camopt kinematics: " + format_scalar(member(summary, "design", file));
  add_facts(data, summary, {"design", "design_file", "driver", "step_deg", "step_mm", "points_per_position",
                            "engine_speed_rpm"});
  // the sweep: one group of rows per control position
  const CsvData csv = dir.csv("kinematics.csv");
  Sweep sw{csv, {}, {}, first_of(csv, {"cam_deg", "driver_mm"})};
  if (sw.angle.empty()) throw InputError(csv.file + ": no driver column (cam_deg or driver_mm)");
  const std::string control = first_of(csv, {"control_deg", "control_mm"});
  sw.groups = group_rows(csv, {control});
  sw.labels = family_labels({control}, sw.groups);
  if (sw.groups.size() > 1) data.family = sw.labels;
  // the valve, the mechanism moving, the nodes, the contacts
  add_svaj_plots(data, csv, sw.groups, sw.labels, sw.angle, "valve");
  const std::vector<double>& driver = csv.at(sw.angle);
  if (!driver.empty()) {
    const double step = summary.contains("step_deg") ? number(summary, "step_deg", file) : number(summary, "step_mm", file);
    add_scene(data, scene_source_of_summary(summary, member(summary, "positions", file), step, driver.front(),
                                            driver[sw.groups.front().end - 1]));
  }
  const std::vector<std::string> contacts = contact_names(csv);
  const std::vector<std::string> nodes = node_columns(csv, contacts);
  if (!nodes.empty()) add_section(data, "nodes", "Every node: position, velocity, acceleration and jerk");
  for (const auto& base : nodes)
    if (!repeats_valve(csv, base)) add_node_plots(data, sw, base);
  if (!contacts.empty()) add_section(data, "contacts", "Contacts");
  for (const auto& c : contacts) add_contact_plots(data, sw, c);
  if (nodes.empty())
    data.notes.push_back("no node columns: run camopt kinematics with --outputs all (or add nodes) for every node's motion");
  if (contacts.empty())
    data.notes.push_back("no contact columns: run camopt kinematics with --outputs all (or add contacts) for the "
                         "pressure angle, radii of curvature, entrainment, sliding and roller speed of every contact");
  // the extremes per control position, the profiles
  add_section(data, "summary", "Summary");
  data.tables.push_back(rows_table("extremes", "Extremes per control position (summary.json)", "summary",
                                   member(summary, "positions", file), {"control_deg", "control_mm"}));
  if (summary.contains("profiles"))
    data.tables.push_back(rows_table("profiles", "Cam profiles", "summary", summary["profiles"], {"name"}));
}

}  // namespace camopt::report::detail
