#pragma once
// the modes job (camopt dynamics --model modes): natural frequencies and mass-normalised mode
// shapes of the flexible model linearised about its static equilibrium at chosen cam angles
// (no speed), and the surge frequencies of every multi-mass compression spring alone, as the
// columns of modes.csv and summary.json.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "camopt/dynamics/flexible.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// every option of `camopt dynamics --model modes` but its files
struct ModesOptions {
  std::string design_file;   // the design's file, as summary.json and the messages name it
  std::string control;       // --control: the first control's positions [deg or mm] ("": its default)
  std::string cam_deg;       // --cam-deg: a value, a list or START:STOP:COUNT [cam deg] ("": the defaults)
  bool release_cam = false;  // --release-cam: the contacts on the driver carry no stiffness
  dynamics::FlexibleOptions flexible;  // the flexible model's parameters (its defaults)
  int threads = 1;                     // worker threads of the kinematic sweep for the peak angles
};

// what `dynamics --model modes` writes, in memory
struct ModesResult {
  io::Columns columns;     // modes.csv: one row per (control position, cam angle, mode)
  nlohmann::json summary;  // summary.json
  std::size_t linearisations = 0, coordinates = 0;
};

// the modes at every (control position, cam angle): one progress step per linearisation.
// InputError for bad options (--cam-deg, --control) or dynamics data; NumericalError naming
// the control and the cam angle where a linearisation fails; Cancelled when the observer asks
ModesResult run_modes(const LoadedDesign& design, const ModesOptions& options, Observer& observer);

}  // namespace camopt::jobs
