// camopt report DIR: the interactive report.html of a result folder (docs/report.md), and the
// report and figures every command writes after its outputs (--no-report, --figures svg|png).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <utility>

#include "camopt/core/error.hpp"
#include "camopt/report/figures.hpp"
#include "camopt/report/report.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

namespace fs = std::filesystem;

void add_figures_option(CLI::App& cmd, std::string& figures, const std::string& files) {
  cmd.add_option("--figures", figures,
                 "also write the run's main plots as static images of " + std::to_string(report::kFigureWidth) + " x " +
                     std::to_string(report::kFigureHeight) + " px: " + files)
      ->check(CLI::IsMember({"svg", "png"}));
}

void add_report_options(CLI::App& cmd, ReportOptions& report, const std::string& where, const std::string& figures) {
  cmd.add_flag("--no-report", report.no_report,
               "do not write " + where + ", the interactive page of the results (camopt report rebuilds it)");
  add_figures_option(cmd, report.figures, figures + ", with the report or without it (--no-report)");
}

namespace {

// where the pages of a source go: a result folder holds report.html and <plot id>.<ext>; a
// lift table has <stem>.report.html and <stem>.<plot id>.<ext> beside it (the transaction
// takes the table's folder resolved, as it writes only into a real directory; `shown` is the
// folder as given, for the paths printed)
struct PageFiles {
  std::string dir, shown, prefix, report;
};
PageFiles page_files(const std::string& source) {
  std::error_code ec;
  if (!fs::exists(source, ec)) throw InputError("'" + source + "': no such folder or file");
  if (fs::is_directory(source, ec)) return {source, source, "", "report.html"};
  const fs::path csv(source);
  const fs::path parent = csv.parent_path().empty() ? fs::path(".") : csv.parent_path();
  const fs::path resolved = fs::canonical(parent, ec);
  const std::string stem = csv.stem().string() + ".";
  return {ec ? parent.string() : resolved.string(), csv.parent_path().string(), stem, stem + "report.html"};
}

// the report and the figures of `source` from one collect(), staged and committed together
// while the folder is locked against other camopt runs (a run committing its set meanwhile
// would give them a mix of two runs); returns the paths written, the report's first
std::vector<fs::path> write_pages(const std::string& source, const ReportOptions& report,
                                  const report::WrittenTables& written) {
  const PageFiles files = page_files(source);
  // the folder locked, then the data read and every page made before the first is staged
  std::vector<std::pair<std::string, std::string>> pages;
  io::OutputTransaction out(files.dir, {}, [](const std::string& message) { info(message); }, [&] {
    const report::ReportData data = report::collect(source, written);
    if (!report.no_report) pages.emplace_back(files.report, report::render_html(data));
    if (!report.figures.empty())
      for (auto& [name, content] :
           report::render_figures(data, report.figures == "png" ? report::FigureFormat::png : report::FigureFormat::svg))
        pages.emplace_back(files.prefix + name, std::move(content));
    std::vector<std::string> names;
    for (const auto& page : pages) names.push_back(page.first);
    return names;
  });
  std::vector<fs::path> paths;
  // rebuilt from the results at any time (camopt report): renamed into place without waiting
  // for the disk, which would cost the shortest runs a fifth of their time
  for (const auto& [name, content] : pages) {
    out.stage(name, content, io::Durability::renamed);
    paths.push_back(fs::path(files.shown) / name);
  }
  out.commit();
  return paths;
}

void run_report(const std::string& source, const std::string& figures) {
  for (const fs::path& path : write_pages(source, {false, figures}, {})) std::printf("%s\n", path.c_str());
}

// a figure file name of camopt's: a main plot id with one of the extensions
bool is_figure_file(const fs::directory_entry& e) {
  std::error_code ec;
  const std::string ext = e.path().extension().string();
  return (ext == ".svg" || ext == ".png") && e.is_regular_file(ec);
}

}  // namespace

std::vector<std::string> previous_figures(const std::string& out_dir) {
  std::error_code ec;
  fs::directory_iterator it(out_dir, ec), end;
  if (ec || std::none_of(it, end, is_figure_file)) return {};
  // the run the folder holds, read as its report reads it; a folder camopt cannot read holds no
  // figures of camopt's
  report::ReportData data;
  try {
    data = report::collect(out_dir);
  } catch (const InputError&) {
    return {};
  }
  std::vector<std::string> names;
  for (const report::Plot& p : data.plots) {
    if (!p.main || p.id.empty() || p.id.front() == '.' || p.id.find('/') != std::string::npos) continue;
    for (const char* ext : {".svg", ".png"})
      if (fs::is_regular_file(fs::path(out_dir) / (p.id + ext), ec)) names.push_back(p.id + ext);
  }
  return names;
}

report::WrittenTables hand_over(const std::map<std::string, io::FileId>& committed, const std::string& name,
                                io::Columns table) {
  const auto it = committed.find(name);
  if (it == committed.end()) return {};
  report::WrittenTables written;
  written[name] = {std::move(table), it->second};
  return written;
}

void write_run_report(const std::string& source, const ReportOptions& report, const report::WrittenTables& written) {
  if (report.no_report && report.figures.empty()) return;
  try {
    for (const fs::path& path : write_pages(source, report, written))
      info((path.extension() == ".html" ? "report: " : "figure: ") + path.string());
  } catch (const InputError& e) {
    const std::string what = report.figures.empty() ? "its report" : report.no_report ? "its figures" : "its report and figures";
    throw InputError("the run's outputs are written, but not " + what + ": " + e.what() +
                     " (camopt report rebuilds them; --no-report skips the report)");
  }
}

void setup_report(CLI::App& app) {
  auto source = std::make_shared<std::string>();
  auto figures = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand(
      "report", "rebuild the interactive report.html of a result folder (kinematics, synthesize, optimize, dynamics) "
                "or the <stem>.report.html of a lift table, and print its path (and the figures' paths); the page is "
                "self-contained and fetches nothing when opened");
  cmd->add_option("source", *source, "result folder (the --out of a run), or a lift table CSV of camopt lift")
      ->required();
  add_figures_option(*cmd, *figures,
                     "<plot id>.svg or .png in the folder (<stem>.<plot id>.svg or .png beside a lift table)");
  cmd->callback([source, figures] { run_report(*source, *figures); });
}

}  // namespace camopt::cli
