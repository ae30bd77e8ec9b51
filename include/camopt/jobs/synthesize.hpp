#pragma once
// the synthesize job (camopt synthesize): the cam profile that gives a target motion (theory of
// envelopes), with what the CLI writes of it in memory: profile.csv's and grinding.csv's
// columns, the DXF and design.toml texts, and report.json.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

// the files a synthesized or optimised profile is delivered in, in memory
struct ProfileExports {
  io::Columns profile;      // profile.csv: angle_deg, radius_mm, excess_radius_mm, x_mm, y_mm, radius_of_curvature_mm
  io::Columns grinding;     // grinding.csv: cam_deg, master_lift_mm (no columns: not computed, the report says why)
  std::string dxf;          // profile.dxf
  std::string design_toml;  // design.toml: the design reading profile.csv beside it (in out_dir)
};

// the exports as the files' names and texts: profile.dxf, grinding.csv (when computed),
// profile.csv and design.toml
std::vector<std::pair<std::string, std::string>> export_files(const ProfileExports& exports);

// every option of `camopt synthesize` but its report
struct SynthesizeOptions {
  std::string design_file;  // the design's file: report.json names it, design.toml is its text edited
  std::vector<io::Override> overrides;  // the changes the spec was parsed with (--set), edited into design.toml
  std::string target_file;  // the target table's name in report.json and the messages
  // the folder design.toml is written for: profile.csv beside it, its other relative
  // `file = ...` references rewritten relative to it (--out)
  std::string out_dir;
  std::string cam = "rotational";  // --cam: rotational (the driver's) or swing
  std::optional<double> control;   // --control [deg or mm] (none: the position of largest lift)
  int points = 1440;               // --points [count per revolution]
  bool smooth = false;             // --smooth: least-squares fit of a noisy target
  double knot_spacing_deg = 4.0;   // --knot-spacing [cam deg], with smooth
  double wheel_radius_mm = 0.0;    // --wheel-radius [mm] (0: no check)
  double min_radius_mm = 0.0;      // --min-radius [mm]
  double closure_tolerance_mm = 0.05;  // --closure-tolerance [mm]
  // --max-round-trip-error, in the target's unit (mm; deg for a rotational --target-node):
  // 5 um, the grinding accuracy (the bundled designs round-trip to < 1e-6 mm at 0.25 deg,
  // < 1e-4 mm at 1 deg)
  double max_round_trip_error = 0.005;
  std::string target_node;                 // --target-node ("": the valve)
  std::optional<double> master_radius_mm;  // --master-radius [mm] (none: the follower's roller, or flat)
  double grinding_step_deg = 0.25;         // --grinding-step [cam deg]
};

// what `camopt synthesize` writes, in memory
struct SynthesizeResult {
  ProfileExports exports;
  nlohmann::json report;  // report.json
  std::string summary;    // the CLI's closing line without its files ("synthesize: profile '...' ...")
};

// InputError naming the option for a value out of its range (the CLI's checks of its options)
void validate(const SynthesizeOptions& options);

// the synthesis of the design's cam for the target table (cam_deg|crank_deg and lift_mm, or
// <node>_angle_deg with --target-node), its round trip and checks. Notes: the target's
// closure, the control chosen, the radius warnings. InputError for a bad table or option;
// NumericalError naming the angle where the synthesis or its round trip fails
SynthesizeResult run_synthesize(const DesignSpec& spec, const io::CsvTable& target, const SynthesizeOptions& options,
                                Observer& observer);

}  // namespace camopt::jobs
