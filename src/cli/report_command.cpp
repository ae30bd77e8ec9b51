// camopt report DIR: the interactive report.html of a result folder (docs/report.md), and the
// report every folder command writes after its outputs (--no-report skips it).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "camopt/core/error.hpp"
#include "camopt/report/report.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

void add_report_flag(CLI::App& cmd, bool& no_report, const std::string& where) {
  cmd.add_flag("--no-report", no_report,
               "do not write " + where + ", the interactive page of the results (camopt report rebuilds it)");
}

namespace {

// the report of a result folder, made and written while the folder is locked against other
// camopt runs (a run committing its set meanwhile would give the page a mix of two runs), or
// the report beside a lift table; returns its path
std::filesystem::path write_report_of(const std::string& source) {
  std::error_code ec;
  if (!std::filesystem::is_directory(source, ec)) return report::write_report(source);
  io::OutputTransaction out = open_outputs(source, {"report.html"});
  // rebuilt from the results at any time: renamed into place without waiting for the disk
  out.stage("report.html", report::render_html(report::collect(source)), io::Durability::renamed);
  out.commit();
  return report::report_path(source);
}

void run_report(const std::string& source) {
  const std::filesystem::path path = write_report_of(source);
  std::printf("%s\n", path.c_str());
}

}  // namespace

void write_run_report(const std::string& source, bool no_report) {
  if (no_report) return;
  try {
    info("report: " + write_report_of(source).string());
  } catch (const InputError& e) {
    throw InputError(std::string("the run's outputs are written, but not its report: ") + e.what() +
                     " (camopt report rebuilds it; --no-report skips it)");
  }
}

namespace {

}  // namespace

void setup_report(CLI::App& app) {
  auto source = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand(
      "report", "rebuild the interactive report.html of a result folder (kinematics, synthesize, optimize, dynamics) "
                "or the <stem>.report.html of a lift table, and print its path; the page is self-contained and "
                "fetches nothing when opened");
  cmd->add_option("source", *source, "result folder (the --out of a run), or a lift table CSV of camopt lift")
      ->required();
  cmd->callback([source] { run_report(*source); });
}

}  // namespace camopt::cli
