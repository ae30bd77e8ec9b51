// camopt bench: the user's design timed stage by stage against tighter runs of itself (the
// jobs layer runs them): a work-precision table on stdout and, with --out, as bench.csv.
#include <CLI/CLI.hpp>
#include <iostream>

#include "camopt/jobs/bench.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

// the one file bench writes into --out (no report: the table is the result)
const std::vector<std::string> kBenchOutputs = {"bench.csv"};

struct BenchCommandOptions {
  jobs::BenchOptions job;  // the design file, --control, --rpm, --repeat
  std::string out_dir;     // "": stdout only
};

void run_bench(BenchCommandOptions& o) {
  // the options, the design and its stages
  jobs::validate(o.job);
  if (!o.out_dir.empty()) check_inputs_outside(o.out_dir, {o.job.design_file}, kBenchOutputs);
  const LoadedDesign design = load_mechanism(o.job.design_file);
  TerminalObserver terminal;
  const jobs::BenchResult result = jobs::run_bench(design, o.job, terminal);
  // the table on stdout, and bench.csv
  if (!global_options().quiet) std::cout << jobs::bench_text(result);
  if (o.out_dir.empty()) return;
  write_outputs(o.out_dir, kBenchOutputs, {{"bench.csv", jobs::bench_csv(result)}});
  info("bench: " + std::to_string(result.rows.size()) + " runs -> " + o.out_dir + "/bench.csv");
}

}  // namespace

void setup_bench(CLI::App& app) {
  auto opts = std::make_shared<BenchCommandOptions>();
  auto* cmd = app.add_subcommand(
      "bench", "time a design: kinematic sweep (lift only, all outputs), synthesis of its cam, rigid and flexible "
               "dynamics cycles, each against a tighter run of the same design (a work-precision table)");
  cmd->add_option("design", opts->job.design_file, "design file (TOML)")->required();
  cmd->add_option("--out", opts->out_dir, "output directory for bench.csv (default: the table on stdout only)");
  cmd->add_option("--control", opts->job.control,
                  "one position of the design's first control [deg or mm] (default: the control's default)");
  cmd->add_option("--rpm", opts->job.rpm, "engine speed of the dynamics runs [rpm, crankshaft] (default 6000)")
      ->check(positive_number() & CLI::Range(0.0, 1e6));
  cmd->add_option("--repeat", opts->job.repeat, "a default run's time is the best of this many runs (default 3)")
      ->check(CLI::Range(1, 1000));
  cmd->callback([opts] { run_bench(*opts); });
}

}  // namespace camopt::cli
