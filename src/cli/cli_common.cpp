#include "cli_common.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <thread>

#include "camopt/core/error.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/io/npz.hpp"
#include "camopt/io/table_layout.hpp"

namespace camopt::cli {

namespace fs = std::filesystem;

GlobalOptions& global_options() {
  static GlobalOptions options;
  return options;
}

int thread_count() {
  const int requested = global_options().threads;
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

namespace {

// a whole token that strtod reads as a number that is not finite
bool non_finite_number(const std::string& piece) {
  if (piece.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(piece.c_str(), &end);
  return end == piece.c_str() + piece.size() && !std::isfinite(v);
}

}  // namespace

void check_finite_arguments(int argc, const char* const* argv) {
  std::string option = "argument";
  for (int i = 1; i < argc; ++i) {
    std::string token = argv[i], name = option;
    const bool is_option = token.size() > 1 && token[0] == '-' && !non_finite_number(token) &&
                           !(std::isdigit(static_cast<unsigned char>(token[1])) || token[1] == '.');
    if (is_option) {
      const auto eq = token.find('=');
      option = token.substr(0, eq);
      if (eq == std::string::npos) continue;
      name = option;
      token = token.substr(eq + 1);
    }
    std::size_t start = 0;
    for (std::size_t k = 0; k <= token.size(); ++k) {
      if (k < token.size() && token[k] != ',' && token[k] != ':') continue;
      const std::string piece = token.substr(start, k - start);
      if (non_finite_number(piece))
        throw InputError(name + ": value '" + piece + "' is not a finite number");
      start = k + 1;
    }
    if (!is_option) option = "argument";
  }
}

std::vector<io::Override> design_overrides() {
  std::vector<io::Override> out;
  for (const std::string& argument : global_options().set) out.push_back(io::parse_override(argument));
  return out;
}

DesignSpec load_design_spec(const std::string& design_path) {
  return io::load_design(design_path, design_overrides());
}

LoadedDesign load_mechanism(const std::string& design_path) {
  TerminalObserver notes;
  return jobs::compile_design(load_design_spec(design_path), design_path, notes, design_overrides());
}

std::map<std::string, io::FileId> write_outputs(const std::string& out_dir, const std::vector<std::string>& output_set,
                                                const std::vector<std::pair<std::string, std::string>>& files) {
  io::OutputTransaction out = open_outputs(out_dir, output_set);
  for (const auto& [name, contents] : files) out.stage(name, contents);
  out.commit();
  return out.committed();
}

void add_format_option(CLI::App& cmd, std::string& layout, const std::string& wide) {
  cmd.add_option("--format", layout,
                 "the table's layout: long (the default: one row per " + wide +
                     " and angle), wide (one row per angle, a column group per " + wide +
                     ") or npz (the long table's columns as NumPy arrays, .npz)")
      ->check(CLI::IsMember({"long", "wide", "npz"}));
}

std::string table_file_name(const std::string& csv_name, const TableFormat& format) {
  if (format.layout != "npz") return csv_name;
  return fs::path(csv_name).replace_extension(".npz").string();
}

std::map<std::string, io::FileId> write_table_and_summary(const std::string& out_dir,
                                                          const std::vector<std::string>& output_set,
                                                          const std::string& csv_name, const io::Columns& table,
                                                          const nlohmann::json& summary, const TableFormat& format) {
  // the table in its format
  std::string contents;
  if (format.layout == "npz") contents = io::format_npz(table);
  else if (format.layout == "wide") contents = io::format_csv(io::wide_table(table, format.wide_keys, format.wide_angles), thread_count());
  else contents = io::format_csv(table, thread_count());
  return write_outputs(out_dir, output_set,
                       {{table_file_name(csv_name, format), std::move(contents)},
                        {"summary.json", summary.dump(2) + "\n"}});
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

io::OutputTransaction open_outputs(const std::string& out_dir, const std::vector<std::string>& outputs) {
  return io::OutputTransaction(
      out_dir, outputs, [](const std::string& message) { info(message); }, [&out_dir] { return previous_figures(out_dir); });
}

void check_inputs_outside(const std::string& out_dir, std::initializer_list<std::string> inputs,
                          const std::vector<std::string>& outputs) {
  std::error_code ec;
  const std::filesystem::path out = std::filesystem::weakly_canonical(out_dir, ec);
  if (ec) return;
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    const std::filesystem::path in = std::filesystem::weakly_canonical(input, ec);
    bool written = false;
    for (const std::string& name : outputs) written = written || in.filename() == name;
    if (!ec && written && in.parent_path() == out)
      throw InputError("--out: '" + out_dir + "' holds the input '" + input +
                       "': the results would overwrite it; write them to another folder");
  }
}

bool progress_line_wanted() {
  const GlobalOptions& g = global_options();
  if (g.quiet || g.progress == "never") return false;
  return g.progress == "always" || isatty(STDERR_FILENO) == 1;
}

namespace {

bool progress_line_drawn = false;  // a Progress line is on the terminal, without its newline

// a message starts on a clean line: the progress line, if any, is cleared first
void clear_progress_line() {
  if (progress_line_drawn) std::fprintf(stderr, "\r\033[K");
  progress_line_drawn = false;
}

}  // namespace

void info(const std::string& message) {
  if (global_options().quiet) return;
  clear_progress_line();
  std::fprintf(stderr, "%s\n", message.c_str());
}

void detail(const std::string& message) {
  if (!global_options().verbose || global_options().quiet) return;
  clear_progress_line();
  std::fprintf(stderr, "%s\n", message.c_str());
}

Progress::Progress(std::string label, long total)
    : label_(std::move(label)), total_(total),
      enabled_(total > 0 && progress_line_wanted()) {
  if (enabled_) draw();
}

Progress::~Progress() {
  if (enabled_) clear_progress_line();
}

void Progress::advance(long steps) {
  done_ += steps;
  if (enabled_) draw();
}

void TerminalObserver::note(const std::string& message) { info(message); }

void TerminalObserver::begin(const std::string& label, long steps) { progress_.emplace(label, steps); }

void TerminalObserver::advance() {
  if (progress_) progress_->advance();
}

void TerminalObserver::end() { progress_.reset(); }

void Progress::draw() {
  const int percent = static_cast<int>(100 * done_ / total_);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  constexpr int width = 30;
  const int filled = width * percent / 100;
  // at 100 % the summaries and the output files are still to come: say so
  std::fprintf(stderr, "\r\033[K%s [%.*s%*s] %3d%%%s", label_.c_str(), filled, "##############################",
               width - filled, "", percent, percent == 100 ? ", writing the outputs ..." : "");
  std::fflush(stderr);
  progress_line_drawn = true;
}

}  // namespace camopt::cli
