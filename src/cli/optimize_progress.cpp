#include "optimize_progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <string>

#include "cli_common.hpp"

namespace camopt::cli {

namespace {

// [s] least time between two redraws of the terminal line
constexpr double kRedrawInterval = 0.1;

// a log's line at the end of a phase: "optimize: ipopt round 2 (812 of 2020 rows): 31
// iterations, objective -0.907559, worst violation 1.2e-09, 0.84 s"
std::string end_line(const opt::SolverProgress& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, ": %d iterations, objective %.6g, worst violation %.2g, %.2f s", p.iteration,
                p.objective, p.violation, p.elapsed_s);
  return "optimize: " + p.phase + buf;
}

// the terminal's line, numbers first so that a narrow terminal cuts the phase's name:
// "optimize 0.8 s: iteration 29, objective -1.05928, worst violation 0.95; ipopt round 2 (...)"
std::string running_line(const opt::SolverProgress& p) {
  char buf[160];
  if (p.event == opt::SolverProgress::Event::begin)
    std::snprintf(buf, sizeof buf, "optimize %.1f s: ", p.elapsed_s);
  else
    std::snprintf(buf, sizeof buf, "optimize %.1f s: iteration %d, objective %.6g, worst violation %.2g; ", p.elapsed_s,
                  p.iteration, p.objective, p.violation);
  return buf + p.phase;
}

// columns of the terminal on `out` (80 when it does not say): a longer line would wrap, and
// \r would then redraw only its last row
std::size_t columns(std::FILE* out) {
  winsize w{};
  if (ioctl(fileno(out), TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  return 80;
}

struct Printer {
  std::FILE* out;
  bool terminal;
  double last_draw = -1.0;  // [s] elapsed at the last redraw (-1: none yet)
  bool drawn = false;       // a line is on the terminal

  void operator()(const opt::SolverProgress& p) {
    if (!terminal) {
      if (p.event == opt::SolverProgress::Event::end) std::fprintf(out, "%s\n", end_line(p).c_str());
      return;
    }
    // the line is cleared when a phase ends (what the run prints next starts on a clean line)
    // and drawn at most every kRedrawInterval, whatever the phases
    if (p.event == opt::SolverProgress::Event::end) {
      if (drawn) std::fprintf(out, "\r\033[K");
      std::fflush(out);
      drawn = false;
      return;
    }
    if (last_draw >= 0.0 && p.elapsed_s - last_draw < kRedrawInterval) return;
    last_draw = p.elapsed_s;
    std::string text = running_line(p);
    const std::size_t width = columns(out);
    if (text.size() >= width) text.resize(width - 1);
    std::fprintf(out, "\r\033[K%s", text.c_str());
    std::fflush(out);
    drawn = true;
  }
};

}  // namespace

ProgressCallback make_progress_printer(std::FILE* out, bool terminal) {
  auto printer = std::make_shared<Printer>(Printer{out, terminal});
  return [printer](const opt::SolverProgress& p) { (*printer)(p); };
}

ProgressCallback make_progress_printer() {
  if (global_options().quiet || global_options().progress == "never") return {};
  return make_progress_printer(stderr, progress_line_wanted());
}

}  // namespace camopt::cli
