// camopt dynamics: rigid (mode (a), or mode (b) with compliant contacts), flexible and modal
// valvetrain dynamics of a design over engine speeds and control positions.
#include <CLI/CLI.hpp>
#include <chrono>
#include <nlohmann/json.hpp>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cli_common.hpp"
#include "compliant_outputs.hpp"
#include "dynamics_setup.hpp"
#include "flexible_outputs.hpp"
#include "modes_command.hpp"
#include "range_option.hpp"
#include "rigid_outputs.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct DynamicsOptions {
  std::string design, model = "rigid", contacts = "rigid", rpm, out_dir, control, start = "static";
  double step_deg = 0.0;  // 0: the design's step
  dynamics::FlexibleOptions flexible;
  ReportOptions report;  // --no-report, --figures
};

// --rpm: a value, a list or a range, each in (0, 1e6]
std::vector<double> parse_rpms(const std::string& option_value) {
  const std::vector<double> rpms = parse_range("--rpm", option_value);
  for (double r : rpms)
    if (!(r > 0 && r <= 1e6)) throw InputError("--rpm: value " + format_value(r, 6) + " must be in (0, 1e6]");
  return rpms;
}

// the design, the mechanism, the dynamics model, the speeds, the cam angles and the control positions
DynamicsSetup make_setup(const DynamicsOptions& o) {
  DynamicsSetup su;
  LoadedDesign design = load_mechanism(o.design);
  su.spec = std::move(design.spec);
  su.mech = std::move(design.mech);
  su.model = dynamics::compile_dynamics(su.spec, su.mech);
  su.rpms = parse_rpms(o.rpm);
  su.range = driver_range(su.mech, o.step_deg);
  su.controls = resolve_controls(su.mech, o.design, o.control);
  sweep_points(o.step_deg > 0 ? "--step" : "driver.step_deg", su.range.start, su.range.stop, su.range.step,
               static_cast<double>(su.controls.positions.size() * su.rpms.size()), "--control x --rpm");
  return su;
}

// mode (a) at every control position: one sweep each, split by load case
std::vector<dynamics::RigidSweep> rigid_sweeps(const DynamicsSetup& su, bool progress_bar) {
  std::vector<dynamics::RigidSweep> sweeps(su.controls.positions.size());
  Progress progress("dynamics", progress_bar ? static_cast<long>(sweeps.size()) : 0);
  for (std::size_t p = 0; p < sweeps.size(); ++p) {
    const Status st = dynamics::rigid_sweep(su.mech, su.model, su.controls.positions[p], su.range.start,
                                            su.range.stop, su.range.step, sweeps[p]);
    if (!st.ok()) fail_at_position(su.mech, su.controls, st, p);
    progress.advance();
  }
  return sweeps;
}

// mode (a): the kinematically constrained inverse dynamics, one sweep per control position,
// every speed from its split load cases
report::WrittenTables run_rigid(const DynamicsOptions& o) {
  // the design, its dynamics model, speeds and control positions
  const DynamicsSetup su = make_setup(o);
  // one sweep per control position
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<dynamics::RigidSweep> sweeps = rigid_sweeps(su, true);
  const double seconds = seconds_since(t0);
  // dynamics.csv and summary.json
  const nlohmann::json summary = rigid_summary(su, o.design, sweeps, seconds);
  io::Columns table = rigid_columns(su, sweeps);
  const auto committed = write_outputs(o.out_dir, kDynamicsOutputs,
                                       {{"dynamics.csv", io::format_csv(table)}, {"summary.json", with_overrides(summary).dump(2) + "\n"}});
  info("dynamics (rigid): " + std::to_string(su.controls.values.size()) + " position(s) x " +
       std::to_string(sweeps[0].points()) + " points in " + std::to_string(seconds * 1e3) + " ms, " +
       std::to_string(su.rpms.size()) + " speed(s) -> " + o.out_dir + "/dynamics.csv, summary.json");
  return hand_over(committed, "dynamics.csv", std::move(table));
}

// mode (b): stiff separable contacts integrated in time, one run per (rpm, control)
report::WrittenTables run_compliant_contacts(const DynamicsOptions& o) {
  // the design, its dynamics model, speeds and control positions
  const DynamicsSetup su = make_setup(o);
  const auto t0 = std::chrono::steady_clock::now();
  // mode (a) at every control position, for its forces beside the integrated ones
  const std::vector<dynamics::RigidSweep> rigid = rigid_sweeps(su, false);
  // one CVODE run per (rpm, control position)
  const std::vector<CompliantRun> runs =
      run_grid<dynamics::CompliantResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_compliant(su.mech, su.model, controls, rpm, su.range.start, su.range.stop,
                                       su.range.step, dynamics::CompliantOptions{}, result);
      });
  const double seconds = seconds_since(t0);
  // dynamics.csv and summary.json
  const nlohmann::json summary = compliant_summary(su, o.design, runs, seconds);
  io::Columns table = compliant_columns(su, runs, rigid);
  const auto committed = write_outputs(o.out_dir, kDynamicsOutputs,
                                       {{"dynamics.csv", io::format_csv(table)}, {"summary.json", with_overrides(summary).dump(2) + "\n"}});
  info("dynamics (rigid, compliant contacts): " + std::to_string(runs.size()) + " run(s) in " +
       std::to_string(seconds * 1e3) + " ms -> " + o.out_dir + "/dynamics.csv, summary.json");
  return hand_over(committed, "dynamics.csv", std::move(table));
}

// the flexible model: one CVODE run per (rpm, control), the last revolution reported
report::WrittenTables run_flexible_model(const DynamicsOptions& o) {
  // the design, its dynamics model, speeds and control positions
  const DynamicsSetup su = make_setup(o);
  // one CVODE run per (rpm, control position)
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<FlexibleRun> runs =
      run_grid<dynamics::FlexibleResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_flexible(su.mech, su.model, controls, rpm, su.range.start, su.range.stop, su.range.step,
                                      o.flexible, result);
      });
  const double seconds = seconds_since(t0);
  // dynamics.csv and summary.json (with the runs' warnings on stderr)
  io::Columns table = flexible_columns(su, runs, o.flexible.coil_displacements);
  const nlohmann::json summary = flexible_summary(su, o.design, o.flexible, runs, seconds);
  const auto committed = write_outputs(o.out_dir, kDynamicsOutputs,
                                       {{"dynamics.csv", io::format_csv(table)}, {"summary.json", with_overrides(summary).dump(2) + "\n"}});
  info("dynamics (flexible): " + std::to_string(runs.size()) + " run(s) in " + std::to_string(seconds * 1e3) +
       " ms -> " + o.out_dir + "/dynamics.csv, summary.json");
  return hand_over(committed, "dynamics.csv", std::move(table));
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
  cmd->add_option("--out", opts->out_dir, "output directory (dynamics.csv or modes.csv, summary.json, report.html)")
      ->required();
  add_report_options(*cmd, opts->report);
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
    // the run, then its report (from the run's table in memory)
    report::WrittenTables written;
    if (opts->model == "modes") {
      run_modes({opts->design, opts->out_dir, opts->control, opts->rpm, opts->flexible, *modes});
    } else {
      if (opts->rpm.empty()) throw CLI::RequiredError("--rpm");
      opts->flexible.start_at_rest = opts->start == "rest";
      if (opts->model == "flexible")
        written = run_flexible_model(*opts);
      else if (opts->contacts == "compliant")
        written = run_compliant_contacts(*opts);
      else
        written = run_rigid(*opts);
    }
    write_run_report(opts->out_dir, opts->report, written);
  });
}

}  // namespace camopt::cli
