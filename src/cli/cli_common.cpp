#include "cli_common.hpp"

#include <unistd.h>

#include <thread>

namespace camopt::cli {

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

void info(const std::string& message) {
  if (!global_options().quiet) std::fprintf(stderr, "%s\n", message.c_str());
}

void detail(const std::string& message) {
  if (global_options().verbose && !global_options().quiet) std::fprintf(stderr, "%s\n", message.c_str());
}

Progress::Progress(std::string label, long total)
    : label_(std::move(label)), total_(total),
      enabled_(total > 0 && !global_options().quiet && isatty(STDERR_FILENO) == 1) {
  if (enabled_) draw();
}

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void Progress::advance(long steps) {
  done_ += steps;
  if (enabled_) draw();
}

void Progress::draw() {
  const int percent = static_cast<int>(100 * done_ / total_);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  constexpr int width = 30;
  const int filled = width * percent / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "##############################",
               width - filled, "", percent);
  std::fflush(stderr);
}

}  // namespace camopt::cli
