// camopt optimize: constrained cam optimisation with Ipopt / NLopt (the optimize job), written as
// lift.csv (swing_pitch.csv), profile.csv, report.json, design.toml, profile.dxf and grinding.csv.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/jobs/optimize.hpp"
#include "cli_common.hpp"
#include "optimize_progress.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct OptimizeOptions {
  jobs::OptimizeOptions job;  // the design, the constraint set, --out and the solver's options
  std::vector<std::string> set_constraint;  // --set-constraint KEY=VALUE
  ReportOptions report;       // --no-report, --figures
};

// the job's notes on stderr; the solver's phases are drawn by the progress printer
class OptimizeObserver : public TerminalObserver {
 public:
  void begin(const std::string&, long) override {}
  void end() override {}
};

void run_optimize(OptimizeOptions& o) {
  // the design and the constraint set (inputs outside the output folder)
  check_inputs_outside(o.job.out_dir, {o.job.design_file, o.job.constraints_file}, kOptimizeOutputs);
  const DesignSpec spec = load_design_spec(o.job.design_file);
  std::vector<io::Override> constraint_overrides;
  for (const std::string& a : o.set_constraint) constraint_overrides.push_back(io::parse_override(a, "--set-constraint"));
  opt::OptimizationSpec set = io::load_constraints(o.job.constraints_file, constraint_overrides);
  // the solve, its profile and its checks, the progress on stderr
  o.job.progress = make_progress_printer();
  o.job.overrides = design_overrides();
  OptimizeObserver terminal;
  const jobs::OptimizeResult result = jobs::run_optimize(spec, std::move(set), o.job, terminal);
  // the tables, the profile's files and report.json, committed together (an infeasible set:
  // report.json alone)
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, table] : result.tables) files.emplace_back(name, io::format_csv(table));
  if (result.exports) {
    const auto exports = jobs::export_files(*result.exports);
    files.insert(files.end(), exports.begin(), exports.end());
  }
  files.emplace_back("report.json", result.report.dump(2) + "\n");
  write_outputs(o.job.out_dir, kOptimizeOutputs, files);
  if (result.exports) {
    std::string names;
    for (const auto& file : files) names += (names.empty() ? "/" : ", ") + file.first;
    info(result.summary + " -> " + o.job.out_dir + names);
  }
  // the page of the results, before a solver failure or a failed verification is raised
  write_run_report(o.job.out_dir, o.report);
  if (!result.status.ok()) throw NumericalError(result.status);
  if (!result.verified) {
    std::fprintf(stderr, "camopt: optimize --verify: the optimised design fails its checks:\n%s",
                 result.verification_failures.c_str());
    throw VerificationFailed("the optimised design fails verification (report.json \"verification\")");
  }
}

}  // namespace

void setup_optimize(CLI::App& app) {
  auto opts = std::make_shared<OptimizeOptions>();
  auto* cmd = app.add_subcommand("optimize", "optimise a cam's lift under acceleration, curvature, pressure-angle, "
                                             "rolling-speed and Hertz-stress limits, and synthesize its profile");
  cmd->add_option("design", opts->job.design_file, "design file (TOML)")->required();
  cmd->add_option("--constraints", opts->job.constraints_file, "constraint set (TOML, see constraints/ and docs/optimisation.md)")
      ->required();
  cmd->add_option("--set-constraint", opts->set_constraint,
                  "KEY=VALUE: change a value of the constraint set before it is read, e.g. --set-constraint "
                  "limits.max_pressure_angle_deg=28 (repeatable; key paths as --set's)")
      ->allow_extra_args(false)
      ->type_name("KEY=VALUE");
  cmd->add_option("--cam", opts->job.cam,
                  "which cam to optimise: rotational (the driver's; [event] lift model) or swing (a VVA swing cam's "
                  "profile over every control position; [swing_profile])")
      ->check(CLI::IsMember({"rotational", "swing"}))
      ->capture_default_str();
  cmd->add_option("--solver", opts->job.solver, "ipopt, slsqp, mma, cobyla or global (multi-start slsqp)")
      ->capture_default_str();
  cmd->add_option("--out", opts->job.out_dir, "output directory")->required();
  cmd->add_option("--points", opts->job.points, "profile resolution [count per revolution] (see synthesize --points)")
      ->check(CLI::Range(36, 100000))
      ->capture_default_str();
  cmd->add_option("--max-iterations", opts->job.max_iterations, "iteration (ipopt) or evaluation (nlopt) limit")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--starts", opts->job.starts, "global: number of starts")->check(CLI::Range(1, 1000))->capture_default_str();
  add_report_options(*cmd, opts->report);
  cmd->add_flag("--verify", opts->job.verify, "run the optimised design through kinematics, rigid and flexible dynamics and report them");
  cmd->callback([opts, cmd] {
    if (opts->job.solver != "global") reject_unused(*cmd, {"--starts"}, "with --solver " + opts->job.solver + " (global only)");
    run_optimize(*opts);
  });
}

}  // namespace camopt::cli
