// the kinematics job: the sweep of a design over the cam cycle and control range, as the
// columns of kinematics.csv (long format) and summary.json.
#include "camopt/jobs/kinematics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "camopt/core/parallel.hpp"
#include "camopt/core/units.hpp"
#include "camopt/jobs/kinematics_summary.hpp"
#include "camopt/kinematics/sweep.hpp"

namespace camopt::jobs {

namespace {

struct OutputSelection {
  bool lift = false, nodes = false, contacts = false;
  int order = 0;  // highest derivative requested
  // contact:NAME and node:NAME items: only these (none: every one, with contacts / nodes)
  std::vector<std::string> contact_names, node_names;
};

const char* const kOutputsAllowed =
    "allowed: lift, velocity, acceleration, jerk, nodes, contacts, all, node:NAME, contact:NAME";

OutputSelection parse_outputs(const std::string& list) {
  OutputSelection s;
  if (list.empty()) throw InputError(std::string("--outputs: empty (") + kOutputsAllowed + ")");
  std::stringstream ss(list);
  std::string item;
  bool all_contacts = false, all_nodes = false;
  while (std::getline(ss, item, ',')) {
    if (item == "lift") s.lift = true;
    else if (item == "velocity") s.order = std::max(s.order, 1);
    else if (item == "acceleration") s.order = std::max(s.order, 2);
    else if (item == "jerk") s.order = std::max(s.order, 3);
    else if (item == "nodes") all_nodes = true;
    else if (item == "contacts") all_contacts = true;
    else if (item == "all") all_nodes = all_contacts = true, s.order = 3;
    else if (item.rfind("contact:", 0) == 0 && item.size() > 8) s.contact_names.push_back(item.substr(8));
    else if (item.rfind("node:", 0) == 0 && item.size() > 5) s.node_names.push_back(item.substr(5));
    else throw InputError("--outputs: unknown output '" + item + "' (" + kOutputsAllowed + ")");
  }
  if (all_contacts) s.contact_names.clear();
  if (all_nodes) s.node_names.clear();
  s.contacts = all_contacts || !s.contact_names.empty();
  s.nodes = all_nodes || !s.node_names.empty();
  s.lift = true;  // the valve lift is always written
  return s;
}

// the names of contact:NAME and node:NAME are the design's: InputError naming the value and
// listing the valid names
void check_output_names(const kin::Mechanism& mech, const OutputSelection& s, const std::string& design_file) {
  std::vector<std::string> contacts, nodes;
  for (const auto& c : mech.connections)
    if (c.kind == ConnectionKind::contact) contacts.push_back(c.name);
  for (std::size_t n = 0; n < mech.nodes.size(); ++n)
    if (static_cast<int>(n) != mech.driver_node && mech.nodes[n].first_variable >= 0) nodes.push_back(mech.nodes[n].name);
  const auto check = [&design_file](const std::vector<std::string>& asked, const std::vector<std::string>& valid,
                                    const std::string& what) {
    for (const auto& name : asked)
      if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
        std::string list;
        for (const auto& v : valid) list += (list.empty() ? "" : ", ") + v;
        throw InputError("--outputs: " + what + ":" + name + ": " + design_file + " has no " + what + " '" + name +
                         "' (" + what + "s: " + (list.empty() ? "none" : list) + ")");
      }
  };
  check(s.contact_names, contacts, "contact");
  check(s.node_names, nodes, "node");
}

bool selected(const std::vector<std::string>& names, const std::string& name) {
  return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
}

// column suffixes for a quantity with the given base unit, per driver unit
struct Units {
  std::string base;    // "mm" or "deg"
  std::string driver;  // "deg" or "mm"
  std::string derivative(int k) const {
    if (k == 0) return base;
    return base + "_per_" + driver + (k > 1 ? std::to_string(k) : "");
  }
  // SI at an engine speed: mm -> m, deg -> rad, per second^k
  std::string si(int k) const {
    const std::string b = base == "mm" ? "m" : "rad";
    return b + "_per_s" + (k > 1 ? std::to_string(k) : "");
  }
};

const char* derivative_name(int k) {
  static const char* names[] = {"", "vel", "acc", "jerk"};
  return names[k];
}

double radius_of(double curvature) { return std::abs(curvature) > 1e-12 ? 1.0 / curvature : 0.0; }

// the summary of every control position, with durations at the chosen heights, on up to
// `threads` threads
std::vector<kin::PositionSummary> summaries(const kin::Mechanism& mech, const kin::SweepResult& result,
                                            const std::vector<DurationHeight>& heights, int threads) {
  kin::SummaryOptions options;
  options.duration_heights.clear();
  for (const auto& h : heights) options.duration_heights.push_back(h.value);
  std::vector<kin::PositionSummary> out(result.positions.size());
  parallel_for(out.size(), threads, [&](std::size_t p) { out[p] = kin::summarize(mech, result, p, options); });
  return out;
}

// what the run writes, and the units of its columns and keys
struct Run {
  const KinematicsOptions& options;
  Observer& observer;
  const DesignSpec& spec;  // as parsed: the lash-free recompile edits a copy
  const kin::Mechanism& mech;
  OutputSelection sel;
  ControlPositions controls;
  std::vector<DurationHeight> heights;
  bool output_is_angle = false;
  std::string driver_unit;     // "deg" or "mm"
  double cam_deg_per_s = 0.0;  // at --rpm [deg/s]
  bool has_lash = false;
};

// the sweep over the driver range at every control position, to the asked derivative order
kin::SweepSpec make_sweep(const Run& run) {
  const DriverRange range = driver_range(run.mech, run.options.step_deg);
  kin::SweepSpec sweep;
  sweep.start = range.start;
  sweep.stop = range.stop;
  sweep.step = range.step;
  sweep.request.derivative_order = run.sel.contacts ? std::max(run.sel.order, 1) : run.sel.order;
  sweep.request.contacts = run.sel.contacts;
  sweep.threads = run.options.threads;
  sweep.control_positions = run.controls.positions;
  sweep_points(run.options.step_deg > 0 ? "--step" : "driver.step_deg", sweep.start, sweep.stop, sweep.step,
               static_cast<double>(sweep.control_positions.size()));
  return sweep;
}

// the sweep, one observer step per control position (a cancel stops it there); seconds: its
// wall time
kin::SweepResult run_sweep(const kin::Mechanism& mech, kin::SweepSpec sweep, Observer& observer, double& seconds) {
  observer.begin("kinematics", static_cast<long>(sweep.control_positions.size()));
  StepCounter steps(observer);
  sweep.on_position_done = [&steps] { steps.step_done(); };
  const auto t0 = std::chrono::steady_clock::now();
  kin::SweepResult result = kin::sweep(mech, sweep);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  observer.end();
  return result;
}

// lash: the same sweep without lash, for the lift loss and the lift-area loss
std::vector<kin::PositionSummary> no_lash_summaries(const Run& run, const kin::SweepSpec& sweep) {
  std::vector<kin::PositionSummary> out;
  if (!run.has_lash) return out;
  DesignSpec zero = run.spec;
  for (auto& c : zero.connections) c.lash_mm = 0.0;
  const kin::Mechanism mech0 = kin::compile(zero);
  kin::SweepSpec s0 = sweep;
  s0.request = {sweep.request.derivative_order, false};  // refined as the summary below
  s0.on_position_done = nullptr;
  const kin::SweepResult r0 = kin::sweep(mech0, s0);
  for (std::size_t p = 0; p < r0.positions.size(); ++p)
    if (!r0.positions[p].status.ok()) throw NumericalError(r0.positions[p].status);
  out.resize(r0.positions.size());
  parallel_for(out.size(), sweep.threads, [&](std::size_t p) { out[p] = kin::summarize(mech0, r0, p); });
  return out;
}

// kinematics.csv in long format: one row per (control position, driver point)
class CsvColumns {
 public:
  CsvColumns(const Run& run, const kin::SweepResult& result) : run_(run), result_(result) {}
  // the table, moved out
  io::Columns table();

 private:
  template <class ValueAt>
  void add(std::string name, ValueAt&& value_at) {
    header_.push_back(std::move(name));
    std::vector<double> col;
    col.reserve(result_.driver.size() * result_.positions.size());
    for (std::size_t p = 0; p < result_.positions.size(); ++p)
      for (std::size_t i = 0; i < result_.driver.size(); ++i) col.push_back(value_at(result_.positions[p], i));
    cols_.push_back(std::move(col));
  }
  void add_control_and_driver();
  void add_variable(int v, const std::string& prefix, bool relative_to_rest);
  void add_contact(std::size_t c);

  const Run& run_;
  const kin::SweepResult& result_;
  std::vector<std::string> header_;
  std::vector<std::vector<double>> cols_;
};

void CsvColumns::add_control_and_driver() {
  const kin::Mechanism& mech = run_.mech;
  header_ = {"control_" + run_.controls.unit, mech.driver_is_angle() ? "cam_deg" : "driver_mm"};
  cols_.resize(2);
  for (std::size_t p = 0; p < result_.positions.size(); ++p)
    for (std::size_t i = 0; i < result_.driver.size(); ++i) {
      cols_[0].push_back(run_.controls.values[p]);
      cols_[1].push_back(result_.driver[i]);
    }
}

// a node variable and its derivatives per driver unit, and per second at --rpm
void CsvColumns::add_variable(int v, const std::string& prefix, bool relative_to_rest) {
  const kin::Mechanism& mech = run_.mech;
  const Units u{mech.variables[v].is_angle ? "deg" : "mm", run_.driver_unit};
  const int node = mech.variables[v].node;
  double rest = 0.0;
  if (relative_to_rest && node >= 0)
    rest = mech.variables[v].is_angle ? mech.nodes[node].rest * 180.0 / pi : mech.nodes[node].rest;
  add(prefix + u.derivative(0),
      [v, rest](const kin::PositionResult& r, std::size_t i) { return r.value(i, v, 0) - rest; });
  for (int k = 1; k <= run_.sel.order; ++k)
    add(prefix + derivative_name(k) + "_" + u.derivative(k),
        [v, k](const kin::PositionResult& r, std::size_t i) { return r.value(i, v, k); });
  if (run_.options.rpm > 0 && mech.driver_is_angle())
    for (int k = 1; k <= run_.sel.order; ++k) {
      const double scale = std::pow(run_.cam_deg_per_s, k) * (u.base == "mm" ? 1e-3 : rad_per_deg);
      add(prefix + derivative_name(k) + "_" + u.si(k),
          [v, k, scale](const kin::PositionResult& r, std::size_t i) { return r.value(i, v, k) * scale; });
    }
}

// a contact's point, local coordinates, pressure angle, radii, speeds and gap
void CsvColumns::add_contact(std::size_t c) {
  const kin::Mechanism& mech = run_.mech;
  const std::size_t nc = mech.connections.size();
  const double rate = mech.driver_is_angle() ? rad_per_deg : 1.0;  // per rad -> per deg
  const std::string n = mech.connections[c].name + "_";
  const std::string& driver_unit = run_.driver_unit;
  auto cs = [nc, c](auto member) {
    return [nc, c, member](const kin::PositionResult& r, std::size_t i) { return member(r.contacts[i * nc + c]); };
  };
  add(n + "x_mm", cs([](const kin::ContactState& s) { return s.x; }));
  add(n + "y_mm", cs([](const kin::ContactState& s) { return s.y; }));
  add(n + "a_local_x_mm", cs([](const kin::ContactState& s) { return s.local_a_x; }));
  add(n + "a_local_y_mm", cs([](const kin::ContactState& s) { return s.local_a_y; }));
  add(n + "b_local_x_mm", cs([](const kin::ContactState& s) { return s.local_b_x; }));
  add(n + "b_local_y_mm", cs([](const kin::ContactState& s) { return s.local_b_y; }));
  add(n + "pressure_angle_deg", cs([](const kin::ContactState& s) { return s.pressure_angle * 180.0 / pi; }));
  add(n + "radius_a_mm", cs([](const kin::ContactState& s) { return radius_of(s.curvature_a); }));
  add(n + "radius_b_mm", cs([](const kin::ContactState& s) { return radius_of(s.curvature_b); }));
  add(n + "entrainment_mm_per_" + driver_unit, cs([rate](const kin::ContactState& s) { return s.entrainment * rate; }));
  add(n + "sliding_mm_per_" + driver_unit, cs([rate](const kin::ContactState& s) { return s.sliding * rate; }));
  add(n + "roller_speed_rad_per_" + driver_unit,
      cs([rate](const kin::ContactState& s) { return s.roller_speed * rate; }));
  if (run_.options.rpm > 0 && mech.driver_is_angle()) {
    const double w = run_.cam_deg_per_s;
    add(n + "entrainment_m_per_s", cs([rate, w](const kin::ContactState& s) { return s.entrainment * rate * w * 1e-3; }));
    add(n + "sliding_m_per_s", cs([rate, w](const kin::ContactState& s) { return s.sliding * rate * w * 1e-3; }));
    add(n + "roller_rpm",
        cs([rate, w](const kin::ContactState& s) { return s.roller_speed * rate * w * 60.0 / (2 * pi); }));
  }
  add(n + "gap_mm", cs([](const kin::ContactState& s) { return s.gap; }));
}

io::Columns CsvColumns::table() {
  const kin::Mechanism& mech = run_.mech;
  add_control_and_driver();
  // the valve lift, its derivative columns named vel_, acc_, jerk_ without the lift prefix
  add_variable(mech.nodes[mech.output_node].first_variable, "lift_", true);
  for (std::size_t h = 2; h < header_.size(); ++h)
    if (header_[h].rfind("lift_", 0) == 0 && header_[h] != "lift_mm" && header_[h] != "lift_deg")
      header_[h] = header_[h].substr(5);
  // every node variable but the driver's (the cam_deg column already)
  if (run_.sel.nodes)
    for (std::size_t v = 0; v < mech.variables.size(); ++v) {
      if (mech.variables[v].node < 0 || mech.variables[v].node == mech.driver_node) continue;
      if (!selected(run_.sel.node_names, mech.nodes[mech.variables[v].node].name)) continue;
      std::string name = mech.variables[v].name;
      std::replace(name.begin(), name.end(), '.', '_');
      const auto kind = mech.nodes[mech.variables[v].node].kind;
      add_variable(static_cast<int>(v),
                   name + (kind == NodeKind::rotational      ? "_angle_"
                           : kind == NodeKind::translational ? "_disp_"
                                                             : "_"),
                   false);
    }
  if (run_.sel.contacts)
    for (std::size_t c = 0; c < mech.connections.size(); ++c)
      if (mech.connections[c].kind == ConnectionKind::contact && selected(run_.sel.contact_names, mech.connections[c].name))
        add_contact(c);
  return {std::move(header_), std::move(cols_), {}};
}

// one control position's entry of summary.json, and its line (and a toggle warning) on stderr
nlohmann::json position_entry(const Run& run, const kin::PositionSummary& s, const kin::PositionSummary* no_lash,
                              std::size_t p, const SummaryUnits& summary_units) {
  const kin::Mechanism& mech = run.mech;
  const std::string& driver_unit = run.driver_unit;
  const double control = run.controls.values[p];
  const int out_var = mech.nodes[mech.output_node].first_variable;
  const Units u{mech.variables[out_var].is_angle ? "deg" : "mm", driver_unit};
  nlohmann::json j;
  j["control_" + run.controls.unit] = control;
  j["status"] = "ok";
  j.update(position_summary_json(s, run.heights, summary_units));
  if (run.sel.order >= 1 || run.sel.contacts) {
    j["max_condition_number"] = s.max_condition;
    j["grid_values"].push_back("max_condition_number");
  }
  // the closest approach to a singular configuration, whatever the outputs (taken at the
  // solved points)
  j["near_toggle"] = s.near_toggle;
  j["min_toggle_margin"] = s.min_toggle_margin;
  j["min_toggle_margin_at_" + driver_unit] = s.min_toggle_margin_at;
  j["grid_values"].push_back("min_toggle_margin");
  if (no_lash) {
    j["lift_loss_from_lash_" + u.base] = no_lash->max_lift - s.max_lift;
    j["lift_area_loss_from_lash_" + u.base + "_" + driver_unit] = no_lash->lift_area - s.lift_area;
  }
  run.observer.note("kinematics: " + (mech.controls.empty() ? std::string() : "control " + format_value(control, 6) + " " +
                                                                  run.controls.unit + ": ") +
       position_summary_line(s, run.heights, summary_units));
  if (s.near_toggle)
    run.observer.note("warning: near a singular configuration (a linkage at toggle or a pressure angle near 90 deg): toggle "
         "margin " + format_value(s.min_toggle_margin, 3) + " < " + format_value(kin::near_singular_margin, 3) +
         " at " + format_value(s.min_toggle_margin_at, 6) + " " + driver_unit +
         (mech.controls.empty() ? "" : ", control " + mech.controls[0].name + " = " + format_value(control, 6)) +
         "; the motion there is sensitive to the link lengths");
  return j;
}

// summary.json: the run, every control position's summary, the cam profiles' radii
nlohmann::json summary_json(const Run& run, const kin::SweepSpec& sweep, const kin::SweepResult& result,
                            const std::vector<kin::PositionSummary>& no_lash, double seconds) {
  const kin::Mechanism& mech = run.mech;
  nlohmann::json summary;
  summary["design"] = mech.name;
  if (const auto held = held_rigid_hlas(run.spec, "kinematics", run.observer); !held.empty()) summary["hla_held_rigid"] = held;
  summary["design_file"] = run.options.design_file;
  summary["driver"] = mech.nodes[mech.driver_node].name;
  summary["step_" + run.driver_unit] = sweep.step;
  summary["points_per_position"] = result.driver.size();
  if (run.options.rpm > 0) summary["engine_speed_rpm"] = run.options.rpm;
  summary["run_time_s"] = seconds;
  const std::vector<kin::PositionSummary> position_summaries = summaries(mech, result, run.heights, run.options.threads);
  const std::string lift_unit = run.output_is_angle ? "deg" : "mm";
  if (!run.options.duration_at.empty()) check_duration_heights(run.heights, position_summaries, lift_unit);
  const SummaryUnits summary_units{lift_unit, run.driver_unit, run.sel.order,
                                   run.options.rpm > 0 && mech.driver_is_angle() ? run.cam_deg_per_s : 0.0};
  nlohmann::json positions = nlohmann::json::array();
  for (std::size_t p = 0; p < result.positions.size(); ++p)
    positions.push_back(position_entry(run, position_summaries[p], run.has_lash ? &no_lash[p] : nullptr, p,
                                       summary_units));
  summary["positions"] = positions;
  nlohmann::json profiles = nlohmann::json::array();
  for (const auto& prof : mech.profiles)
    profiles.push_back({{"name", prof.name()},
                        {"base_circle_radius_mm", prof.base_radius_mm()},
                        {"max_radius_mm", prof.max_radius_mm()},
                        {"max_excess_radius_mm", prof.max_radius_mm() - prof.base_radius_mm()}});
  summary["profiles"] = profiles;
  return summary;
}

}  // namespace

void validate(const KinematicsOptions& o) {
  check_positive("--step", o.step_deg, false);
  check_positive("--rpm", o.rpm, false);
  if (o.rpm > 1e6) throw InputError("--rpm: value " + format_value(o.rpm) + " must be <= 1e6");
  CAMOPT_THROW_UNLESS(o.threads >= 1, "threads = " + std::to_string(o.threads) + " must be >= 1");
  (void)parse_outputs(o.outputs);
}

KinematicsResult run_kinematics(const LoadedDesign& design, const KinematicsOptions& o, Observer& observer) {
  // the outputs asked for and the --duration-at heights
  validate(o);
  const OutputSelection sel = parse_outputs(o.outputs);
  const kin::Mechanism& mech = design.mech;
  check_output_names(mech, sel, o.design_file);
  Run run{o, observer, design.spec, mech, sel, {}, {}, false, "", 0.0, false};
  run.output_is_angle = mech.variables[mech.nodes[mech.output_node].first_variable].is_angle;
  run.heights = parse_duration_heights(o.duration_at.empty() ? "1,0.1" : o.duration_at, run.output_is_angle);
  // the sweep: driver range, derivative order, control positions
  run.controls = resolve_controls(mech, o.design_file, o.control);
  const kin::SweepSpec sweep = make_sweep(run);
  // run it; a failed position stops the run, named
  KinematicsResult out;
  const kin::SweepResult result = run_sweep(mech, sweep, observer, out.seconds);
  for (std::size_t p = 0; p < result.positions.size(); ++p)
    if (!result.positions[p].status.ok()) fail_at_position(mech, run.controls, result.positions[p].status, p);
  // lash: the same sweep without it
  for (const auto& c : mech.connections) run.has_lash |= c.one_sided;
  const std::vector<kin::PositionSummary> no_lash = no_lash_summaries(run, sweep);
  // the units of the columns and keys
  run.driver_unit = mech.driver_is_angle() ? "deg" : "mm";
  run.cam_deg_per_s = o.rpm / mech.driver.crank_per_cam * 6.0;  // [deg/s]
  // kinematics.csv and summary.json
  out.columns = CsvColumns(run, result).table();
  out.summary = summary_json(run, sweep, result, no_lash, out.seconds);
  record_overrides(out.summary, design.overrides);
  out.positions = result.positions.size();
  out.points = result.driver.size();
  return out;
}

}  // namespace camopt::jobs
