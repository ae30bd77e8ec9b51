// camopt dynamics: rigid (mode (a), or mode (b) with compliant contacts), flexible and modal
// valvetrain dynamics of a design over engine speeds and control positions.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "camopt/jobs/dynamics.hpp"
#include "camopt/jobs/modes.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct DynamicsOptions {
  jobs::DynamicsOptions job;  // the design file, --model, --contacts, --rpm, --control, --step, the flexible options
  std::string out_dir, start = "static";
  std::string format = "long";  // --format
  ReportOptions report;  // --no-report, --figures
};

// the rigid or flexible model: the job, its dynamics.csv and summary.json
report::WrittenTables run_dynamics(const DynamicsOptions& o) {
  // the design, then the job
  const LoadedDesign design = load_mechanism(o.job.design_file);
  TerminalObserver terminal;
  jobs::DynamicsResult result = jobs::run_dynamics(design, o.job, terminal);
  // dynamics.csv (or .npz) and summary.json, committed together; the wide layout (the rigid
  // model) folds the engine speed and the control position into the column names and keeps
  // the cam and crank angles once
  const TableFormat format{o.format, 2, 2};  // rpm, control; cam_deg, crank_deg
  const std::string table = table_file_name("dynamics.csv", format);
  const auto committed =
      write_table_and_summary(o.out_dir, kDynamicsOutputs, "dynamics.csv", result.columns, result.summary, format);
  const std::string ms = std::to_string(result.seconds * 1e3);
  const std::string files = " -> " + o.out_dir + "/" + table + ", summary.json";
  if (o.job.model == "flexible")
    info("dynamics (flexible): " + std::to_string(result.runs) + " run(s) in " + ms + " ms" + files);
  else if (o.job.contacts == "compliant")
    info("dynamics (rigid, compliant contacts): " + std::to_string(result.runs) + " run(s) in " + ms + " ms" + files);
  else
    info("dynamics (rigid): " + std::to_string(result.positions) + " position(s) x " + std::to_string(result.points) +
         " points in " + ms + " ms, " + std::to_string(result.speeds) + " speed(s)" + files);
  return hand_over(committed, table, std::move(result.columns));
}

// --model modes: the job, its modes.csv and summary.json
report::WrittenTables run_modes(const DynamicsOptions& o, jobs::ModesOptions modes) {
  // the design, then the job
  modes.design_file = o.job.design_file;
  modes.control = o.job.control;
  modes.flexible = o.job.flexible;
  modes.threads = thread_count();
  const LoadedDesign design = load_mechanism(o.job.design_file);
  if (!o.job.rpm.empty()) info("dynamics (modes): note: --rpm is not used (the modes are at no speed)");
  TerminalObserver terminal;
  jobs::ModesResult result = jobs::run_modes(design, modes, terminal);
  // modes.csv and summary.json, committed together
  write_table_and_summary(o.out_dir, kDynamicsOutputs, "modes.csv", result.columns, result.summary);
  info("dynamics (modes): " + std::to_string(result.linearisations) + " linearisation(s), " +
       std::to_string(result.coordinates) + " coordinates -> " + o.out_dir + "/modes.csv, summary.json");
  return {};
}

// the options only --model modes reads
void add_modes_options(CLI::App& cmd, jobs::ModesOptions& options) {
  cmd.add_option("--cam-deg", options.cam_deg,
                 "modes: cam angles [cam deg] at which to linearise: a value, a list a,b,c or START:STOP:COUNT "
                 "(default: the driver's start angle and the angle of peak kinematic lift)");
  cmd.add_flag("--release-cam", options.release_cam,
               "modes: the contacts on the driver carry no stiffness (the cam force is the input)");
}

}  // namespace

void setup_dynamics(CLI::App& app) {
  auto opts = std::make_shared<DynamicsOptions>();
  auto* cmd = app.add_subcommand("dynamics", "valvetrain dynamics: contact forces, cam torque, Hertz stress, spring "
                                             "margin and separation speed (rigid), valve motion, bounce and surge (flexible), "
                                             "natural frequencies and mode shapes (modes)");
  cmd->add_option("design", opts->job.design_file, "design file (TOML)")->required();
  cmd->add_option("--model", opts->job.model,
                  "rigid, flexible, or modes (natural frequencies and mode shapes of the flexible model, no speed)")
      ->check(CLI::IsMember({"rigid", "flexible", "modes"}));
  cmd->add_option("--rpm", opts->job.rpm,
                  "engine speed [rpm, crankshaft]: a value, a list a,b,c or START:STOP:COUNT (required, except "
                  "with --model modes)");
  cmd->add_option("--out", opts->out_dir, "output directory (dynamics.csv or modes.csv, summary.json, report.html)")
      ->required();
  add_report_options(*cmd, opts->report);
  add_format_option(*cmd, opts->format, "engine speed and control position (wide: --model rigid only)");
  cmd->add_option("--control", opts->job.control,
                  "control positions of the design's first control [deg or mm]: a value, a list or START:STOP:COUNT");
  cmd->add_option("--step", opts->job.step_deg, "cam angle step [cam deg] (default: the design's driver.step_deg)")
      ->check(positive_number());
  cmd->add_option("--contacts", opts->job.contacts,
                  "rigid: kinematically constrained inverse dynamics (mode a, exact rpm^2 scaling); compliant: "
                  "stiff separable Hertz contacts integrated in time (mode b)")
      ->check(CLI::IsMember({"rigid", "compliant"}));
  cmd->add_option("--revolutions", opts->job.flexible.revolutions,
                  "flexible: cam revolutions integrated at most, the last reported; stops earlier at a periodic steady state (default 3)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--start", opts->start, "flexible: static (default: start in the static balance moving with the "
                                         "kinematic path, report the last revolution) or rest (every body at rest, "
                                         "the valve on its seat; report every revolution: start-up transients)")
      ->check(CLI::IsMember({"static", "rest"}));
  cmd->add_flag("--coil-displacements", opts->job.flexible.coil_displacements,
                "flexible: write the displacement of every coil mass of the multi-mass springs [mm]");
  cmd->add_option("--rtol", opts->job.flexible.relative_tolerance, "flexible: CVODE relative tolerance (default 1e-6)")
      ->check(CLI::Range(1e-14, 1e-1));
  cmd->add_option("--atol", opts->job.flexible.absolute_tolerance,
                  "flexible: CVODE absolute tolerance on deviations [mm or rad] (default 1e-7)")
      ->check(CLI::Range(1e-16, 1.0));
  auto modes = std::make_shared<jobs::ModesOptions>();
  add_modes_options(*cmd, *modes);
  cmd->callback([opts, modes, cmd] {
    // options the chosen model does not use
    if (opts->job.model != "flexible")
      reject_unused(*cmd, {"--revolutions", "--start", "--coil-displacements", "--rtol", "--atol"},
                    "with --model " + opts->job.model + " (flexible model only)");
    if (opts->job.model != "rigid")
      reject_unused(*cmd, {"--contacts"}, "with --model " + opts->job.model + " (rigid model only)");
    if (opts->job.model != "modes")
      reject_unused(*cmd, {"--cam-deg", "--release-cam"}, "with --model " + opts->job.model + " (--model modes only)");
    // the wide layout: one row per cam angle of the rigid model (mode a), the same at every
    // speed and control position; modes.csv is written long
    if (opts->format == "wide" && (opts->job.model != "rigid" || opts->job.contacts != "rigid"))
      throw InputError("--format wide: value 'wide' is for --model rigid with rigid contacts (one row per cam "
                       "angle); use long or npz with --model " + opts->job.model +
                       (opts->job.model == "rigid" ? " --contacts compliant" : ""));
    if (opts->format != "long" && opts->job.model == "modes")
      throw InputError("--format " + opts->format + ": value '" + opts->format +
                       "' is not used with --model modes (modes.csv is written long)");
    // the run, then its report (from the run's table in memory)
    report::WrittenTables written;
    if (opts->job.model == "modes") {
      written = run_modes(*opts, *modes);
    } else {
      if (opts->job.rpm.empty()) throw CLI::RequiredError("--rpm");
      opts->job.flexible.start_at_rest = opts->start == "rest";
      written = run_dynamics(*opts);
    }
    write_run_report(opts->out_dir, opts->report, written);
  });
}

}  // namespace camopt::cli
