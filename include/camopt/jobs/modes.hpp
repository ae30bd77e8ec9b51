#pragma once
// camopt dynamics --model modes: natural frequencies and mass-normalised mode shapes of the
// flexible model linearised about its static equilibrium at chosen cam angles (no speed),
// and the surge frequencies of every multi-mass compression spring alone.
#include <string>

#include "camopt/dynamics/flexible.hpp"

namespace CLI {
class App;
}

namespace camopt::cli {

struct ModesOptions {
  std::string cam_deg;       // --cam-deg: a value, a list or START:STOP:COUNT; empty: the defaults
  bool release_cam = false;  // --release-cam: the contacts on the driver carry no stiffness
};

// the options only --model modes reads, added to the dynamics subcommand
void add_modes_options(CLI::App& cmd, ModesOptions& options);

// what `dynamics --model modes` reads from the dynamics subcommand's options
struct ModesRequest {
  std::string design, out_dir;
  std::string control;  // --control (empty: the design's default)
  std::string rpm;      // --rpm: not used (no speed); a note when given
  dynamics::FlexibleOptions flexible;
  ModesOptions modes;
};

// writes out_dir/modes.csv and out_dir/summary.json (atomically); bad input throws
// InputError, a failed linearisation NumericalError naming the control and cam angle
void run_modes(const ModesRequest& request);

}  // namespace camopt::cli
