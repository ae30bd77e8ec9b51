// camopt dynamics: rigid and flexible valvetrain dynamics.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/atomic_file.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/drawing_check.hpp"
#include "cli_common.hpp"
#include "validators.hpp"
#include "dynamics_setup.hpp"
#include "flexible_summary.hpp"
#include "modes_command.hpp"
#include "range_option.hpp"
#include "rigid_outputs.hpp"

namespace camopt::cli {

namespace {

struct DynamicsOptions {
  std::string design, model = "rigid", contacts = "rigid", rpm, out_dir, control, start = "static";
  double step_deg = 0.0;  // 0: the design's step
  dynamics::FlexibleOptions flexible;
};

std::string shortest_number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// the design, the mechanism, the dynamics model, the speeds and the control positions
DynamicsSetup make_setup(const DynamicsOptions& o) {
  DynamicsSetup su;
  su.spec = io::load_design(o.design);
  su.mech = kin::compile(su.spec);
  for (const auto& note : kin::check_drawing(su.mech)) info(o.design + ": warning: " + note);
  su.model = dynamics::compile_dynamics(su.mech);
  su.rpms = parse_range("--rpm", o.rpm);
  for (double r : su.rpms)
    if (!(r > 0 && r <= 1e6)) throw InputError("--rpm: value " + format_value(r, 6) + " must be in (0, 1e6]");
  su.start = su.spec.driver.start_deg;
  su.stop = su.spec.driver.stop_deg;
  su.step = o.step_deg > 0 ? o.step_deg : su.spec.driver.step_deg;
  if (su.step > su.stop - su.start)
    throw InputError("--step: value " + std::to_string(su.step) + " exceeds the driver range " +
                     std::to_string(su.stop - su.start));
  // control positions: the first control swept, the others at their defaults
  const kin::Mechanism& mech = su.mech;
  const std::vector<double> defaults = mech.default_controls();
  if (!o.control.empty()) {
    if (mech.controls.empty()) throw InputError("--control: design '" + o.design + "' has no [[control]]");
    const auto& c0 = mech.controls[0];
    su.control_values = parse_range("--control", o.control);
    for (double v : su.control_values)
      if (v < c0.min - 1e-12 || v > c0.max + 1e-12)
        throw InputError("--control: value " + std::to_string(v) + " is outside control '" + c0.name + "' range [" +
                         std::to_string(c0.min) + ", " + std::to_string(c0.max) + "]");
  } else {
    su.control_values.push_back(mech.controls.empty() ? 0.0 : mech.controls[0].default_value);
  }
  for (double v : su.control_values) {
    auto pos = defaults;
    if (!pos.empty()) pos[0] = v;
    su.positions.push_back(pos);
  }
  sweep_points(o.step_deg > 0 ? "--step" : "driver.step_deg", su.start, su.stop, su.step,
               static_cast<double>(su.positions.size() * su.rpms.size()), "--control x --rpm");
  su.control_unit = mech.controls.empty() || mech.controls[0].is_angle ? "deg" : "mm";
  return su;
}

// a numerical failure at one control position, named
[[noreturn]] void fail_at(const DynamicsSetup& su, Status st, std::size_t position) {
  if (!su.mech.controls.empty())
    st.where += ", control " + su.mech.controls[0].name + " = " + std::to_string(su.control_values[position]);
  throw NumericalError(st);
}

// mode (a): the kinematically constrained inverse dynamics, one sweep per control position,
// every speed from its split load cases
void run_rigid(const DynamicsOptions& o) {
  const DynamicsSetup su = make_setup(o);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<dynamics::RigidSweep> sweeps(su.control_values.size());
  Progress progress("dynamics", static_cast<long>(su.control_values.size()));
  for (std::size_t p = 0; p < su.control_values.size(); ++p) {
    const Status st = dynamics::rigid_sweep(su.mech, su.model, su.positions[p], su.start, su.stop, su.step, sweeps[p]);
    if (!st.ok()) fail_at(su, st, p);
    progress.advance();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const nlohmann::json summary = rigid_summary(su, o.design, sweeps, seconds);
  io::OutputTransaction out = open_outputs(o.out_dir, kDynamicsOutputs);
  out.stage("dynamics.csv", rigid_csv(su, sweeps));
  out.stage("summary.json", summary.dump(2) + "\n");
  out.commit();
  info("dynamics (rigid): " + std::to_string(su.control_values.size()) + " position(s) x " +
       std::to_string(sweeps[0].points()) + " points in " + std::to_string(seconds * 1e3) + " ms, " +
       std::to_string(su.rpms.size()) + " speed(s) -> " + o.out_dir + "/dynamics.csv, summary.json");
}


// one time-integrated run per (rpm, control position) of the setup, in that nesting order
template <class Result>
struct GridRun {
  double rpm;
  std::size_t position;
  Result result;
};

// runs `integrate(rpm, controls, result)` over the grid; a failure stops with its position
template <class Result, class Integrate>
std::vector<GridRun<Result>> run_grid(const DynamicsSetup& su, Integrate&& integrate) {
  std::vector<GridRun<Result>> runs;
  Progress progress("dynamics", static_cast<long>(su.rpms.size() * su.positions.size()));
  for (double rpm : su.rpms)
    for (std::size_t p = 0; p < su.positions.size(); ++p) {
      GridRun<Result> r{rpm, p, {}};
      const Status st = integrate(rpm, su.positions[p], r.result);
      if (!st.ok()) fail_at(su, st, p);
      runs.push_back(std::move(r));
      progress.advance();
    }
  return runs;
}

// mode (b): stiff separable contacts integrated in time, one run per (rpm, control)
void run_compliant_contacts(const DynamicsOptions& o) {
  const DynamicsSetup su = make_setup(o);
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t nc = mech.connections.size();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<dynamics::RigidSweep> rigid(su.positions.size());
  for (std::size_t p = 0; p < su.positions.size(); ++p) {
    const Status st = dynamics::rigid_sweep(mech, model, su.positions[p], su.start, su.stop, su.step, rigid[p]);
    if (!st.ok()) fail_at(su, st, p);
  }
  using Run = GridRun<dynamics::CompliantResult>;
  const std::vector<Run> runs =
      run_grid<dynamics::CompliantResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_compliant(mech, model, controls, rpm, su.start, su.stop, su.step,
                                       dynamics::CompliantOptions{}, result);
      });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // ---- dynamics.csv ----
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
  add_column("control_" + su.control_unit,
             [&](const Run& r, const Sweep&, std::size_t, double) { return su.control_values[r.position]; });
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
    const double scale = var.is_angle ? 180.0 / M_PI : 1.0;
    add_column("node_" + name + "_deviation_" + (var.is_angle ? "deg" : "mm"),
               [r, scale](const Run& run, const Sweep&, std::size_t i, double) {
                 return run.result.deviation[i * run.result.rows + r] * scale;
               });
  }

  // ---- summary.json ----
  nlohmann::json summary;
  summary["design"] = su.spec.name;
  summary["design_file"] = o.design;
  summary["model"] = "rigid";
  summary["mode"] = "stiff separable contacts, CVODE (b)";
  summary["step_cam_deg"] = su.step;
  summary["run_time_s"] = seconds;
  nlohmann::json results = nlohmann::json::array();
  for (const Run& r : runs) {
    nlohmann::json j;
    j["rpm"] = r.rpm;
    j["control_" + su.control_unit] = su.control_values[r.position];
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
  io::OutputTransaction out = open_outputs(o.out_dir, kDynamicsOutputs);
  out.stage("dynamics.csv", io::format_csv(header, cols));
  out.stage("summary.json", summary.dump(2) + "\n");
  out.commit();
  info("dynamics (rigid, compliant contacts): " + std::to_string(runs.size()) + " run(s) in " +
       std::to_string(seconds * 1e3) + " ms -> " + o.out_dir + "/dynamics.csv, summary.json");
}

// the flexible model: one CVODE run per (rpm, control), the last revolution reported
void run_flexible_model(const DynamicsOptions& o) {
  const DynamicsSetup su = make_setup(o);
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t nc = mech.connections.size();
  const auto t0 = std::chrono::steady_clock::now();
  using Run = GridRun<dynamics::FlexibleResult>;
  const std::vector<Run> runs =
      run_grid<dynamics::FlexibleResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_flexible(mech, model, controls, rpm, su.start, su.stop, su.step, o.flexible, result);
      });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";

  // ---- dynamics.csv ----
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
    header.push_back("control_" + su.control_unit);
    std::vector<double> a, b;
    for (const Run& r : runs)
      for (std::size_t i = 0; i < r.result.cam_deg.size(); ++i) a.push_back(r.rpm), b.push_back(su.control_values[r.position]);
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
               [e, ne, angle](const Res& r, std::size_t i) { return r.deformation[i * ne + e] * (angle ? 180.0 / M_PI : 1.0); });
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
  if (o.flexible.coil_displacements) {
    const int masses = first.layout.spring_masses;
    int k = 0;
    for (std::size_t s = 0; s < nch; ++s)
      for (int j = 1; j < first.chain_segments[s]; ++j, ++k)
        add_column("spring_" + first.chain_names[s] + "_coil" + std::to_string(j) + "_mm",
                   [k, masses](const Res& r, std::size_t i) { return r.coil_displacement[i * masses + k]; });
  }

  // ---- summary.json ----
  nlohmann::json summary;
  summary["design"] = su.spec.name;
  summary["design_file"] = o.design;
  summary["model"] = "flexible";
  summary["step_cam_deg"] = su.step;
  summary["revolutions"] = o.flexible.revolutions;
  summary["relative_tolerance"] = o.flexible.relative_tolerance;
  summary["absolute_tolerance"] = o.flexible.absolute_tolerance;
  summary["run_time_s"] = seconds;
  summary["start"] = o.flexible.start_at_rest ? "rest" : "static";
  nlohmann::json parameters = nlohmann::json::array();
  for (const auto& p : first.parameters)
    parameters.push_back({{"key", p.key}, {"value", p.value}, {"unit", p.unit}, {"from_design", p.from_design}});
  summary["model_parameters"] = parameters;
  nlohmann::json results = nlohmann::json::array(), map = nlohmann::json::array();
  for (const Run& run : runs) {
    const Res& r = run.result;
    nlohmann::json j;
    j["rpm"] = run.rpm;
    j["control_" + su.control_unit] = su.control_values[run.position];
    j.update(flexible_run_summary(mech, model, r));
    if (r.gap_error_mm > 0.01)
      info("dynamics (flexible): warning: at " + shortest_number(run.rpm) + " rpm contact '" + r.gap_error_contact +
           "' carries force " + shortest_number(r.gap_error_mm) + " mm off its linearised gap (cam " +
           shortest_number(r.gap_error_at_cam_deg) + " deg): the bodies have left their kinematic path far");
    if (!r.periodic && !o.flexible.start_at_rest)
      info("dynamics (flexible): warning: no periodic steady state at " + shortest_number(run.rpm) + " rpm after " +
           std::to_string(r.revolutions_integrated) + " revolutions (start-state difference " +
           shortest_number(r.periodic_difference) + " tolerances); the last revolution is reported: raise --revolutions");
    const bool separates = j["any_contact_separates"].get<bool>();
    map.push_back({{"rpm", run.rpm},
                   {"control_" + su.control_unit, su.control_values[run.position]},
                   {"any_contact_separates", separates},
                   {"bounce_count", has_seat ? j["bounce_count"] : nlohmann::json(nullptr)},
                   {"bounce_height_" + lift_unit, has_seat ? j["bounce_height_" + lift_unit] : nlohmann::json(nullptr)},
                   {"max_lift_loss_" + lift_unit, j["max_lift_loss_" + lift_unit]}});
    results.push_back(j);
  }
  summary["results"] = results;
  summary["speed_map"] = map;
  io::OutputTransaction out = open_outputs(o.out_dir, kDynamicsOutputs);
  out.stage("dynamics.csv", io::format_csv(header, cols));
  out.stage("summary.json", summary.dump(2) + "\n");
  out.commit();
  info("dynamics (flexible): " + std::to_string(runs.size()) + " run(s) in " + std::to_string(seconds * 1e3) +
       " ms -> " + o.out_dir + "/dynamics.csv, summary.json");
}

}  // namespace

void setup_dynamics(CLI::App& app) {
  auto opts = std::make_shared<DynamicsOptions>();
  auto* cmd = app.add_subcommand("dynamics", "valvetrain dynamics: contact forces, cam torque, Hertz stress, spring "
                                             "margin and separation speed (rigid), valve motion, bounce and surge (flexible), "
                                             "natural frequencies and mode shapes (modes)");
  cmd->add_option("design", opts->design, "design file (TOML)")->required();
  cmd->add_option("--model", opts->model,
                  "rigid, flexible, or modes (natural frequencies and mode shapes of the flexible model, no speed)")
      ->check(CLI::IsMember({"rigid", "flexible", "modes"}));
  cmd->add_option("--rpm", opts->rpm,
                  "engine speed [rpm, crankshaft]: a value, a list a,b,c or START:STOP:COUNT (required, except "
                  "with --model modes)");
  cmd->add_option("--out", opts->out_dir, "output directory (dynamics.csv or modes.csv, summary.json)")->required();
  cmd->add_option("--control", opts->control,
                  "control positions of the design's first control [deg or mm]: a value, a list or START:STOP:COUNT");
  cmd->add_option("--step", opts->step_deg, "cam angle step [cam deg] (default: the design's driver.step_deg)")
      ->check(positive_number());
  cmd->add_option("--contacts", opts->contacts,
                  "rigid: kinematically constrained inverse dynamics (mode a, exact rpm^2 scaling); compliant: "
                  "stiff separable Hertz contacts integrated in time (mode b)")
      ->check(CLI::IsMember({"rigid", "compliant"}));
  cmd->add_option("--revolutions", opts->flexible.revolutions,
                  "flexible: cam revolutions integrated at most, the last reported; stops earlier at a periodic steady state (default 3)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--start", opts->start, "flexible: static (default: start in the static balance moving with the "
                                         "kinematic path, report the last revolution) or rest (every body at rest, "
                                         "the valve on its seat; report every revolution: start-up transients)")
      ->check(CLI::IsMember({"static", "rest"}));
  cmd->add_flag("--coil-displacements", opts->flexible.coil_displacements,
                "flexible: write the displacement of every coil mass of the multi-mass springs [mm]");
  cmd->add_option("--rtol", opts->flexible.relative_tolerance, "flexible: CVODE relative tolerance (default 1e-6)")
      ->check(CLI::Range(1e-14, 1e-1));
  cmd->add_option("--atol", opts->flexible.absolute_tolerance,
                  "flexible: CVODE absolute tolerance on deviations [mm or rad] (default 1e-7)")
      ->check(CLI::Range(1e-16, 1.0));
  auto modes = std::make_shared<ModesOptions>();
  add_modes_options(*cmd, *modes);
  cmd->callback([opts, modes, cmd] {
    // options the chosen model does not use
    if (opts->model != "flexible")
      reject_unused(*cmd, {"--revolutions", "--start", "--coil-displacements", "--rtol", "--atol"},
                    "with --model " + opts->model + " (flexible model only)");
    if (opts->model != "rigid") reject_unused(*cmd, {"--contacts"}, "with --model " + opts->model + " (rigid model only)");
    if (opts->model != "modes")
      reject_unused(*cmd, {"--cam-deg", "--release-cam"}, "with --model " + opts->model + " (--model modes only)");
    if (opts->model == "modes") {
      run_modes({opts->design, opts->out_dir, opts->control, opts->rpm, opts->flexible, *modes});
      return;
    }
    if (opts->rpm.empty()) throw CLI::RequiredError("--rpm");
    opts->flexible.start_at_rest = opts->start == "rest";
    if (opts->model == "flexible") {
      run_flexible_model(*opts);
      return;
    }
    if (opts->contacts == "compliant")
      run_compliant_contacts(*opts);
    else
      run_rigid(*opts);
  });
}

}  // namespace camopt::cli
