// camopt kinematics: kinematic sweep of a design over the cam cycle and control range,
// written as kinematics.csv (long format) and summary.json (the jobs layer computes them).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "camopt/io/csv.hpp"
#include "camopt/jobs/kinematics.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct KinematicsOptions {
  jobs::KinematicsOptions job;  // the design file, --control, --step, --rpm, --outputs, --duration-at
  std::string out_dir;
  std::string format = "long";  // --format
  ReportOptions report;  // --no-report, --figures
};

void run_kinematics(KinematicsOptions& o) {
  // the options, the design, the sweep and its summaries
  o.job.threads = thread_count();
  jobs::validate(o.job);
  const LoadedDesign design = load_mechanism(o.job.design_file);
  TerminalObserver terminal;
  jobs::KinematicsResult result = jobs::run_kinematics(design, o.job, terminal);
  // kinematics.csv (or .npz) and summary.json, committed together; the wide layout folds the
  // control position into the column names
  const TableFormat format{o.format, 1};
  const std::string table = table_file_name("kinematics.csv", format);
  const auto committed =
      write_table_and_summary(o.out_dir, kKinematicsOutputs, "kinematics.csv", result.columns, result.summary, format);
  info("kinematics: " + std::to_string(result.positions) + " position(s) x " + std::to_string(result.points) +
       " points in " + std::to_string(result.seconds * 1e3) + " ms -> " + o.out_dir + "/" + table + ", summary.json");
  // the page of the results, from the table in memory
  write_run_report(o.out_dir, o.report, hand_over(committed, table, std::move(result.columns)));
}

}  // namespace

void setup_kinematics(CLI::App& app) {
  auto opts = std::make_shared<KinematicsOptions>();
  auto* cmd = app.add_subcommand("kinematics", "kinematic sweep: lift, velocity, acceleration, jerk of every node and "
                                               "contact quantities, over the cam cycle and control range");
  cmd->add_option("design", opts->job.design_file, "design file (TOML)")->required();
  cmd->add_option("--out", opts->out_dir, "output directory (kinematics.csv, summary.json, report.html)")->required();
  add_report_options(*cmd, opts->report);
  cmd->add_option("--control", opts->job.control,
                  "control positions of the design's first control [deg or mm]: a value, or START:STOP:COUNT "
                  "(e.g. 0:16:17)");
  cmd->add_option("--step", opts->job.step_deg, "driver step [cam deg] (default: the design's driver.step_deg)")
      ->check(positive_number());
  cmd->add_option("--rpm", opts->job.rpm,
                  "engine speed [rpm, crankshaft], up to 1e6: adds SI columns (m/s, m/s^2, m/s^3, rpm)")
      ->check(positive_number() & CLI::Range(0.0, 1e6));
  cmd->add_option("--outputs", opts->job.outputs,
                  "comma list of lift, velocity, acceleration, jerk, nodes, contacts, all, node:NAME (one node), "
                  "contact:NAME (one contact) (default lift,velocity,acceleration,jerk)");
  add_format_option(*cmd, opts->format, "control position");
  cmd->add_option("--duration-at", opts->job.duration_at,
                  "lift heights for the durations in summary.json [mm, or in when written 0.040in; deg for a "
                  "rotating output node]: a comma list, e.g. 1,0.1 (the default) or 0.040in,0.004in");
  cmd->callback([opts] { run_kinematics(*opts); });
}

}  // namespace camopt::cli
