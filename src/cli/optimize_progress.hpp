#pragma once
// camopt optimize's progress on stderr, fed by opt::SolverOptions::progress: on a terminal one
// line redrawn in place (\r) at most 10 times a second with the phase, iteration, objective,
// worst violation and elapsed time, cleared when the phase ends; otherwise (a log, a pipe)
// one line per phase as it ends: each ipopt working-set round, nlopt run, global start and
// feasibility-phase solve. nothing with --quiet.
#include <cstdio>
#include <functional>

#include "camopt/opt/solve.hpp"

namespace camopt::cli {

using ProgressCallback = std::function<void(const opt::SolverProgress&)>;

// the printer for stderr (terminal or not, from isatty); empty with --quiet
ProgressCallback make_progress_printer();
// the printer on `out`, drawn in place when `terminal`
ProgressCallback make_progress_printer(std::FILE* out, bool terminal);

}  // namespace camopt::cli
