#pragma once
// what the collectors of every run share: reading a result folder's CSV and JSON files
// (errors naming the file, line or key), axes from CSV header units, row groups of a long
// table, and plot and table builders.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "camopt/report/report.hpp"
#include "camopt/report/report_data.hpp"
#include "camopt/report/scene.hpp"

namespace camopt::report::detail {

namespace fs = std::filesystem;

// a result CSV: every column read; an empty cell (a quantity that does not exist at that
// row, such as the film of an open contact) is NaN
struct CsvData {
  std::string file;  // the path, for messages
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;  // values[column][row]
  std::size_t rows() const { return values.empty() ? 0 : values.front().size(); }
  const std::vector<double>* find(std::string_view column) const;
  // the column, or InputError "file: no column 'name' (columns: ...)"
  const std::vector<double>& at(std::string_view column) const;
};

// the file parsed; InputError "file:line: ..." for a row that is not numbers or has the
// wrong number of cells, "file: ..." for a missing or empty file
CsvData read_csv(const fs::path& path);
// InputError naming the file and the parse error
nlohmann::json read_json(const fs::path& path);

// the result folder collected, with the tables its run handed over in memory (collect())
struct Folder {
  fs::path path;
  const WrittenTables* written = nullptr;
  fs::path operator/(std::string_view name) const { return path / name; }
  // the folder holds the file
  bool has(const std::string& name) const;
  // the run's table in memory while the folder holds the file the run committed (as read
  // back from that file: -0 as 0), read_csv of the file otherwise
  CsvData csv(const std::string& name) const;
};

// the member `key` of the object `j` (read from `file`), or InputError "file: no key 'path.key'"
const nlohmann::json& member(const nlohmann::json& j, const std::string& key, const std::string& file,
                             const std::string& path = "");
// a number member as a double (null: NaN); InputError when absent or not a number
double number(const nlohmann::json& j, const std::string& key, const std::string& file, const std::string& path = "");

// the quantity and unit of a CSV column or JSON key: "acc_mm_per_deg2" -> {"acc", "mm/deg^2"},
// "roller_rpm" -> {"roller", "rpm"}, "mode" -> {"mode", "-"}; underscores in the quantity
// read as spaces
Axis axis_of(std::string_view name);
// "label [unit]"
std::string heading(const Axis& axis);

// shortest text that reads back to the same double; "nan" / "inf" for a non-finite value
std::string format_number(double value);
// a JSON scalar as table text (a number in shortest form, a string as it is)
std::string format_scalar(const nlohmann::json& value);

// consecutive rows sharing the values of the key columns (a long table's control positions,
// engine speeds)
struct Group {
  std::size_t begin = 0, end = 0;  // rows [begin, end)
  std::vector<double> keys;        // the key columns' values
};
std::vector<Group> group_rows(const CsvData& csv, const std::vector<std::string>& key_columns);
std::vector<double> slice(const std::vector<double>& column, const Group& group);

// the family of a long table's groups: one label per group ("control 4 deg", "3000 rpm,
// control 4 deg") in `family`, empty labels when there is one group
std::vector<std::string> family_labels(const std::vector<std::string>& key_columns, const std::vector<Group>& groups);

// a line plot of y against x with axes from the column names
Plot line_plot(std::string id, std::string title, std::string section, const std::string& x_column,
               const std::string& y_column, std::string link_group);
// one series per group of the csv column `y_column` against `x_column`; with several groups
// each series is a family member named by its label (", name" added on a plot that already
// has series), else named `name`; the series read the plot's x_values when every group has
// the same x. A column that is zero (or empty) everywhere adds nothing (returns false).
bool add_group_series(Plot& plot, const CsvData& csv, const std::vector<Group>& groups,
                      const std::vector<std::string>& labels, const std::string& x_column,
                      const std::string& y_column, const std::string& name, bool dashed = false);

// a two-column table (quantity [unit], value) of the scalar members of `object`, nested
// objects flattened to "a.b"; arrays of scalars joined by ", "
Table key_value_table(std::string id, std::string title, std::string section, const nlohmann::json& object);
// a table with one row per element of `array` (objects), one column per scalar member of the
// first element that has a unit or is in `always`, headings from the keys
Table rows_table(std::string id, std::string title, std::string section, const nlohmann::json& array,
                 const std::vector<std::string>& first_columns = {});

// what every run's report starts with: command, title, source, facts from the JSON's
// top-level strings and numbers listed in `fact_keys`
void add_facts(ReportData& data, const nlohmann::json& j, const std::vector<std::string>& fact_keys);
void add_section(ReportData& data, std::string id, std::string title);

// the collectors, one per kind of run (collect_*.cpp)
void collect_lift_table(ReportData& data, const fs::path& csv_path);

// ---- the mechanism animation (collect_scene.cpp) ---------------------------------------------
// the design a run used and the frames to draw: its control positions, its driver sweep (NaN
// ends: the design's own) at the run's step, of which every stride-th point is drawn
// a design file read and compiled once for the collectors that use it
struct CompiledDesign {
  DesignSpec spec;
  kin::Mechanism mech;
};
// the design at `path`, or nothing when there is no such file
std::shared_ptr<const CompiledDesign> compile_design_file(const fs::path& path);

struct SceneSource {
  fs::path design;
  std::shared_ptr<const CompiledDesign> compiled = nullptr;  // `design` already compiled (else read here)
  SceneRequest request{{}, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(), 1.0};
  std::size_t stride = 1;
};
// a summary.json's design_file, the control values of its `rows` (control_deg or control_mm)
SceneSource scene_source_of_summary(const nlohmann::json& summary, const nlohmann::json& rows, double run_step,
                                    double start, double stop);
// data.scene from build_scene() and a "mechanism" section after the first; a design file that
// is not there leaves a note instead
void add_scene(ReportData& data, const SceneSource& source);
// synthesize: the kinematic solver on the folder's design.toml: the pressure angle and the
// cam's radius of curvature at the contact against cam angle, and the made lift minus the
// target (report.json's target_file, when readable from here)
void add_made_cam_plots(ReportData& data, const CompiledDesign& design, const nlohmann::json& report);
void collect_synthesize(ReportData& data, const Folder& dir, const nlohmann::json& report);
void collect_optimize(ReportData& data, const Folder& dir, const nlohmann::json& report);
void collect_kinematics(ReportData& data, const Folder& dir, const nlohmann::json& summary);
void collect_rigid(ReportData& data, const Folder& dir, const nlohmann::json& summary);
void collect_flexible(ReportData& data, const Folder& dir, const nlohmann::json& summary);
void collect_modes(ReportData& data, const Folder& dir, const nlohmann::json& summary);

// the lift, velocity, acceleration and jerk plots of a lift table (lift.csv, a target, a
// kinematic sweep's valve): one plot each in section "svaj", linked; `angle` the x column
void add_svaj_plots(ReportData& data, const CsvData& csv, const std::vector<Group>& groups,
                    const std::vector<std::string>& labels, const std::string& angle, const std::string& subject);

}  // namespace camopt::report::detail
