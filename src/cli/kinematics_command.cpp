// camopt kinematics: kinematic sweep of a design over the cam cycle and control range.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <mutex>
#include <sstream>

#include "camopt/io/atomic_file.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/drawing_check.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "cli_common.hpp"
#include "kinematics_summary.hpp"
#include "validators.hpp"
#include "range_option.hpp"

namespace camopt::cli {

namespace {

struct KinematicsOptions {
  std::string design, out_dir, control, outputs = "lift,velocity,acceleration,jerk";
  double step_deg = 0.0;  // 0: the design's step
  double rpm = 0.0;       // 0: no SI columns
  std::string duration_at;  // --duration-at heights ("" : 1 and 0.1 in the output's unit)
};

struct OutputSelection {
  bool lift = false, nodes = false, contacts = false;
  int order = 0;  // highest derivative requested
};

OutputSelection parse_outputs(const std::string& list) {
  OutputSelection s;
  if (list.empty())
    throw InputError("--outputs: empty (allowed: lift, velocity, acceleration, jerk, nodes, contacts, all)");
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item == "lift") s.lift = true;
    else if (item == "velocity") s.order = std::max(s.order, 1);
    else if (item == "acceleration") s.order = std::max(s.order, 2);
    else if (item == "jerk") s.order = std::max(s.order, 3);
    else if (item == "nodes") s.nodes = true;
    else if (item == "contacts") s.contacts = true;
    else if (item == "all") s = {true, true, true, 3};
    else
      throw InputError("--outputs: unknown output '" + item +
                       "' (allowed: lift, velocity, acceleration, jerk, nodes, contacts, all)");
  }
  s.lift = true;  // the valve lift is always written
  return s;
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

// the summary of every control position, with durations at the chosen heights
std::vector<kin::PositionSummary> summaries(const kin::Mechanism& mech, const kin::SweepResult& result,
                                            const std::vector<DurationHeight>& heights) {
  kin::SummaryOptions options;
  options.duration_heights.clear();
  for (const auto& h : heights) options.duration_heights.push_back(h.value);
  std::vector<kin::PositionSummary> out;
  for (std::size_t p = 0; p < result.positions.size(); ++p) out.push_back(kin::summarize(mech, result, p, options));
  return out;
}

}  // namespace

void setup_kinematics(CLI::App& app) {
  auto opts = std::make_shared<KinematicsOptions>();
  auto* cmd = app.add_subcommand("kinematics", "kinematic sweep: lift, velocity, acceleration, jerk of every node and "
                                               "contact quantities, over the cam cycle and control range");
  cmd->add_option("design", opts->design, "design file (TOML)")->required();
  cmd->add_option("--out", opts->out_dir, "output directory (kinematics.csv, summary.json)")->required();
  cmd->add_option("--control", opts->control,
                  "control positions of the design's first control [deg or mm]: a value, or START:STOP:COUNT "
                  "(e.g. 0:16:17)");
  cmd->add_option("--step", opts->step_deg, "driver step [cam deg] (default: the design's driver.step_deg)")
      ->check(positive_number());
  cmd->add_option("--rpm", opts->rpm, "engine speed [rpm, crankshaft], up to 1e6: adds SI columns (m/s, m/s^2, m/s^3, rpm)")
      ->check(positive_number() & CLI::Range(0.0, 1e6));
  cmd->add_option("--outputs", opts->outputs,
                  "comma list of lift, velocity, acceleration, jerk, nodes, contacts, all "
                  "(default lift,velocity,acceleration,jerk)");
  cmd->add_option("--duration-at", opts->duration_at,
                  "lift heights for the durations in summary.json [mm, or in when written 0.040in; deg for a "
                  "rotating output node]: a comma list, e.g. 1,0.1 (the default) or 0.040in,0.004in");
  cmd->callback([opts] {
    const auto& o = *opts;
    const OutputSelection sel = parse_outputs(o.outputs);
    const DesignSpec spec = io::load_design(o.design);
    const kin::Mechanism mech = kin::compile(spec);
    for (const auto& note : kin::check_drawing(mech)) info(o.design + ": warning: " + note);
    const bool output_is_angle = mech.variables[mech.nodes[mech.output_node].first_variable].is_angle;
    const std::vector<DurationHeight> heights =
        parse_duration_heights(o.duration_at.empty() ? "1,0.1" : o.duration_at, output_is_angle);

    kin::SweepSpec sweep;
    sweep.start = spec.driver.start_deg;
    sweep.stop = spec.driver.stop_deg;
    sweep.step = o.step_deg > 0 ? o.step_deg : spec.driver.step_deg;
    if (sweep.step > sweep.stop - sweep.start)
      throw InputError("--step: value " + std::to_string(sweep.step) + " exceeds the driver range " +
                       std::to_string(sweep.stop - sweep.start));
    sweep.request.derivative_order = sel.contacts ? std::max(sel.order, 1) : sel.order;
    sweep.request.contacts = sel.contacts;
    sweep.threads = thread_count();
    const std::vector<double> defaults = mech.default_controls();
    std::vector<double> control_values;
    if (!o.control.empty()) {
      if (mech.controls.empty()) throw InputError("--control: design '" + o.design + "' has no [[control]]");
      const auto& c0 = mech.controls[0];
      control_values = parse_range("--control", o.control);
      for (double v : control_values)
        if (v < c0.min - 1e-12 || v > c0.max + 1e-12)
          throw InputError("--control: value " + std::to_string(v) + " is outside control '" + c0.name + "' range [" +
                           std::to_string(c0.min) + ", " + std::to_string(c0.max) + "]");
    } else {
      control_values.push_back(mech.controls.empty() ? 0.0 : mech.controls[0].default_value);
    }
    for (double v : control_values) {
      auto pos = defaults;
      if (!pos.empty()) pos[0] = v;
      sweep.control_positions.push_back(pos);
    }
    sweep_points(o.step_deg > 0 ? "--step" : "driver.step_deg", sweep.start, sweep.stop, sweep.step,
                 static_cast<double>(sweep.control_positions.size()));
    Progress progress("kinematics", static_cast<long>(sweep.control_positions.size()));
    std::mutex progress_mutex;
    sweep.on_position_done = [&] {
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress.advance();
    };
    const auto t0 = std::chrono::steady_clock::now();
    const kin::SweepResult result = kin::sweep(mech, sweep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t p = 0; p < result.positions.size(); ++p) {
      const auto& st = result.positions[p].status;
      if (!st.ok()) {
        Status s = st;
        if (!mech.controls.empty())
          s.where += ", control " + mech.controls[0].name + " = " + std::to_string(control_values[p]);
        throw NumericalError(s);
      }
    }

    // lash: the same sweep without lash gives lift loss and lift-area loss
    bool has_lash = false;
    for (const auto& c : mech.connections) has_lash |= c.one_sided;
    std::vector<kin::PositionSummary> no_lash_summary;
    if (has_lash) {
      DesignSpec zero = spec;
      for (auto& c : zero.connections) c.lash_mm = 0.0;
      const kin::Mechanism mech0 = kin::compile(zero);
      kin::SweepSpec s0 = sweep;
      s0.request = {sweep.request.derivative_order, false};  // refined as the summary below
      s0.on_position_done = nullptr;
      const kin::SweepResult r0 = kin::sweep(mech0, s0);
      for (std::size_t p = 0; p < r0.positions.size(); ++p) {
        if (!r0.positions[p].status.ok()) throw NumericalError(r0.positions[p].status);
        no_lash_summary.push_back(kin::summarize(mech0, r0, p));
      }
    }

    // ---- kinematics.csv (long format) ----
    const std::string driver_unit = mech.driver_is_angle() ? "deg" : "mm";
    const std::string control_unit = mech.controls.empty() || mech.controls[0].is_angle ? "deg" : "mm";
    const double cam_deg_per_s = o.rpm / spec.driver.crank_per_cam * 6.0;  // [deg/s]
    std::vector<std::string> header{"control_" + control_unit, mech.driver_is_angle() ? "cam_deg" : "driver_mm"};
    std::vector<std::vector<double>> cols(2);
    const std::size_t nv = mech.variables.size(), nc = mech.connections.size(), np = result.driver.size();
    auto add_column = [&](std::string name, auto&& value_at) {
      header.push_back(std::move(name));
      std::vector<double> col;
      col.reserve(np * result.positions.size());
      for (std::size_t p = 0; p < result.positions.size(); ++p)
        for (std::size_t i = 0; i < np; ++i) col.push_back(value_at(result.positions[p], i));
      cols.push_back(std::move(col));
    };
    for (std::size_t p = 0; p < result.positions.size(); ++p)
      for (std::size_t i = 0; i < np; ++i) {
        cols[0].push_back(control_values[p]);
        cols[1].push_back(result.driver[i]);
      }
    auto add_variable = [&](int v, const std::string& prefix, bool relative_to_rest) {
      const Units u{mech.variables[v].is_angle ? "deg" : "mm", driver_unit};
      const int node = mech.variables[v].node;
      double rest = 0.0;
      if (relative_to_rest && node >= 0)
        rest = mech.variables[v].is_angle ? mech.nodes[node].rest * 180.0 / M_PI : mech.nodes[node].rest;
      add_column(prefix + u.derivative(0), [&, v, rest](const kin::PositionResult& r, std::size_t i) {
        return r.at(i, nv, v, 0) - rest;
      });
      for (int k = 1; k <= sel.order; ++k)
        add_column(prefix + derivative_name(k) + "_" + u.derivative(k),
                   [&, v, k](const kin::PositionResult& r, std::size_t i) { return r.at(i, nv, v, k); });
      if (o.rpm > 0 && mech.driver_is_angle())
        for (int k = 1; k <= sel.order; ++k) {
          const double scale = std::pow(cam_deg_per_s, k) * (u.base == "mm" ? 1e-3 : M_PI / 180.0);
          add_column(prefix + derivative_name(k) + "_" + u.si(k),
                     [&, v, k, scale](const kin::PositionResult& r, std::size_t i) { return r.at(i, nv, v, k) * scale; });
        }
    };
    const int out_var = mech.nodes[mech.output_node].first_variable;
    add_variable(out_var, "lift_", true);
    // the valve-lift derivative names: vel_, acc_, jerk_ without the lift prefix
    for (std::size_t h = 2; h < header.size(); ++h)
      if (header[h].rfind("lift_", 0) == 0 && header[h] != "lift_mm" && header[h] != "lift_deg")
        header[h] = header[h].substr(5);
    if (sel.nodes)
      for (std::size_t v = 0; v < nv; ++v) {
        // the driver is the cam_deg column already
        if (mech.variables[v].node < 0 || mech.variables[v].node == mech.driver_node) continue;
        std::string name = mech.variables[v].name;
        std::replace(name.begin(), name.end(), '.', '_');
        const auto kind = mech.nodes[mech.variables[v].node].kind;
        add_variable(static_cast<int>(v), name + (kind == NodeKind::rotational ? "_angle_" : kind == NodeKind::translational ? "_disp_" : "_"), false);
      }
    if (sel.contacts) {
      const double rate = mech.driver_is_angle() ? M_PI / 180.0 : 1.0;  // per rad -> per deg
      for (std::size_t c = 0; c < nc; ++c) {
        const auto& conn = mech.connections[c];
        if (conn.kind != ConnectionKind::contact) continue;
        const std::string n = conn.name + "_";
        auto cs = [&, c](auto member) {
          return [&, c, member](const kin::PositionResult& r, std::size_t i) { return member(r.contacts[i * nc + c]); };
        };
        add_column(n + "x_mm", cs([](const kin::ContactState& s) { return s.x; }));
        add_column(n + "y_mm", cs([](const kin::ContactState& s) { return s.y; }));
        add_column(n + "a_local_x_mm", cs([](const kin::ContactState& s) { return s.local_a_x; }));
        add_column(n + "a_local_y_mm", cs([](const kin::ContactState& s) { return s.local_a_y; }));
        add_column(n + "b_local_x_mm", cs([](const kin::ContactState& s) { return s.local_b_x; }));
        add_column(n + "b_local_y_mm", cs([](const kin::ContactState& s) { return s.local_b_y; }));
        add_column(n + "pressure_angle_deg", cs([](const kin::ContactState& s) { return s.pressure_angle * 180.0 / M_PI; }));
        add_column(n + "radius_a_mm", cs([](const kin::ContactState& s) { return radius_of(s.curvature_a); }));
        add_column(n + "radius_b_mm", cs([](const kin::ContactState& s) { return radius_of(s.curvature_b); }));
        add_column(n + "entrainment_mm_per_" + driver_unit, cs([rate](const kin::ContactState& s) { return s.entrainment * rate; }));
        add_column(n + "sliding_mm_per_" + driver_unit, cs([rate](const kin::ContactState& s) { return s.sliding * rate; }));
        add_column(n + "roller_speed_rad_per_" + driver_unit, cs([rate](const kin::ContactState& s) { return s.roller_speed * rate; }));
        if (o.rpm > 0 && mech.driver_is_angle()) {
          const double w = cam_deg_per_s;
          add_column(n + "entrainment_m_per_s", cs([rate, w](const kin::ContactState& s) { return s.entrainment * rate * w * 1e-3; }));
          add_column(n + "sliding_m_per_s", cs([rate, w](const kin::ContactState& s) { return s.sliding * rate * w * 1e-3; }));
          add_column(n + "roller_rpm", cs([rate, w](const kin::ContactState& s) { return s.roller_speed * rate * w * 60.0 / (2 * M_PI); }));
        }
        add_column(n + "gap_mm", cs([](const kin::ContactState& s) { return s.gap; }));
      }
    }

    // ---- summary.json ----
    nlohmann::json summary;
    summary["design"] = spec.name;
    summary["design_file"] = o.design;
    summary["driver"] = mech.nodes[mech.driver_node].name;
    summary["step_" + driver_unit] = sweep.step;
    summary["points_per_position"] = np;
    if (o.rpm > 0) summary["engine_speed_rpm"] = o.rpm;
    summary["run_time_s"] = seconds;
    nlohmann::json positions = nlohmann::json::array();
    const std::vector<kin::PositionSummary> position_summaries = summaries(mech, result, heights);
    if (!o.duration_at.empty()) check_duration_heights(heights, position_summaries, output_is_angle ? "deg" : "mm");
    const SummaryUnits summary_units{output_is_angle ? "deg" : "mm", driver_unit, sel.order,
                                     o.rpm > 0 && mech.driver_is_angle() ? cam_deg_per_s : 0.0};
    for (std::size_t p = 0; p < result.positions.size(); ++p) {
      const kin::PositionSummary& s = position_summaries[p];
      const Units u{mech.variables[out_var].is_angle ? "deg" : "mm", driver_unit};
      nlohmann::json j;
      j["control_" + control_unit] = control_values[p];
      j["status"] = "ok";
      j.update(position_summary_json(s, heights, summary_units));
      if (sel.order >= 1 || sel.contacts) {
        j["max_condition_number"] = s.max_condition;
        j["grid_values"].push_back("max_condition_number");
      }
      // the closest approach to a singular configuration, whatever the outputs (taken at the
      // solved points)
      j["near_toggle"] = s.near_toggle;
      j["min_toggle_margin"] = s.min_toggle_margin;
      j["min_toggle_margin_at_" + driver_unit] = s.min_toggle_margin_at;
      j["grid_values"].push_back("min_toggle_margin");
      if (has_lash) {
        j["lift_loss_from_lash_" + u.base] = no_lash_summary[p].max_lift - s.max_lift;
        j["lift_area_loss_from_lash_" + u.base + "_" + driver_unit] = no_lash_summary[p].lift_area - s.lift_area;
      }
      info("kinematics: " + (mech.controls.empty() ? std::string() : "control " + format_value(control_values[p], 6) +
                                                                      " " + control_unit + ": ") +
           position_summary_line(s, heights, summary_units));
      if (s.near_toggle)
        info("warning: near a singular configuration (a linkage at toggle or a pressure angle near 90 deg): toggle "
             "margin " + format_value(s.min_toggle_margin, 3) + " < " + format_value(kin::near_singular_margin, 3) +
             " at " + format_value(s.min_toggle_margin_at, 6) + " " + driver_unit +
             (mech.controls.empty() ? "" : ", control " + mech.controls[0].name + " = " + format_value(control_values[p], 6)) +
             "; the motion there is sensitive to the link lengths");
      positions.push_back(j);
    }
    summary["positions"] = positions;
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& prof : mech.profiles)
      profiles.push_back({{"name", prof.name()},
                          {"base_circle_radius_mm", prof.base_radius_mm()},
                          {"max_radius_mm", prof.max_radius_mm()},
                          {"max_excess_radius_mm", prof.max_radius_mm() - prof.base_radius_mm()}});
    summary["profiles"] = profiles;

    io::OutputTransaction out = open_outputs(o.out_dir, kKinematicsOutputs);
    out.stage("kinematics.csv", io::format_csv(header, cols));
    out.stage("summary.json", summary.dump(2) + "\n");
    out.commit();
    info("kinematics: " + std::to_string(result.positions.size()) + " position(s) x " + std::to_string(np) +
         " points in " + std::to_string(seconds * 1e3) + " ms -> " + o.out_dir + "/kinematics.csv, summary.json");
  });
}

}  // namespace camopt::cli
