// camopt synthesize: envelope-theory cam synthesis from a target valve lift (the synthesize job),
// written as profile.csv, report.json, design.toml, profile.dxf and grinding.csv.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/jobs/synthesize.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct SynthesizeOptions {
  jobs::SynthesizeOptions job;  // the target, the design, --out and the synthesis options
  ReportOptions report;         // --no-report, --figures
};

void run_synthesize(SynthesizeOptions& o) {
  // the design, and the target table (inputs outside the output folder)
  const DesignSpec spec = load_design_spec(o.job.design_file);
  check_inputs_outside(o.job.out_dir, {o.job.design_file, o.job.target_file}, kSynthesizeOutputs);
  const io::CsvTable target = io::read_csv(o.job.target_file);
  // the synthesis, its checks and its files
  o.job.overrides = design_overrides();
  TerminalObserver terminal;
  const jobs::SynthesizeResult result = jobs::run_synthesize(spec, target, o.job, terminal);
  // profile.csv, profile.dxf, grinding.csv, design.toml and report.json, committed together
  auto files = jobs::export_files(result.exports);
  files.emplace_back("report.json", result.report.dump(2) + "\n");
  write_outputs(o.job.out_dir, kSynthesizeOutputs, files);
  info(result.summary + " -> " + o.job.out_dir + "/profile.csv, report.json, design.toml, profile.dxf, grinding.csv");
  // the page of the results
  write_run_report(o.job.out_dir, o.report);
}

}  // namespace

void setup_synthesize(CLI::App& app) {
  auto opts = std::make_shared<SynthesizeOptions>();
  auto* cmd = app.add_subcommand("synthesize", "compute the cam profile that produces a target valve lift "
                                               "(theory of envelopes)");
  cmd->add_option("target", opts->job.target_file,
                  "target lift CSV: cam_deg|crank_deg (explicit basis) and lift_mm [mm]")->required();
  cmd->add_option("--design", opts->job.design_file, "design file (TOML); its profile on the cam is replaced")->required();
  cmd->add_option("--out", opts->job.out_dir,
                  "output directory (profile.csv, report.json, design.toml, profile.dxf, grinding.csv, report.html)")
      ->required();
  add_report_options(*cmd, opts->report);
  cmd->add_option("--cam", opts->job.cam, "which cam to synthesize: rotational (the driver's) or swing")
      ->check(CLI::IsMember({"rotational", "swing"}));
  cmd->add_option("--control", opts->job.control,
                  "control position [deg or mm, per the design's control unit] (default: the position of largest lift)");
  cmd->add_option("--points", opts->job.points, "profile resolution [count per revolution]: neighbouring points at most 360/N deg apart in "
                  "polar angle, cam angle and tangent turn (a sharp nose gets more points)")
      ->check(CLI::Range(36, 36000));
  cmd->add_flag("--smooth", opts->job.smooth, "smooth a measured, noisy target by least squares (residual reported)");
  cmd->add_option("--knot-spacing", opts->job.knot_spacing_deg, "knot spacing of the smoothing spline [cam deg]")
      ->check(positive_number());
  cmd->add_option("--wheel-radius", opts->job.wheel_radius_mm,
                  "grinding wheel radius [mm]: concave radii must be at least this (0: no check)")
      ->check(non_negative_number());
  cmd->add_option("--target-node", opts->job.target_node,
                  "node whose motion the target gives (default: the valve); e.g. the swing cam, with a column "
                  "<node>_angle_deg [deg] (or <node>_disp_mm [mm]) against cam_deg|crank_deg");
  cmd->add_option("--master-radius", opts->job.master_radius_mm,
                  "radius of the master roller or grinding wheel of the grinding table [mm] (0: flat; default: the "
                  "follower's roller radius, or flat for a flat follower)")
      ->check(non_negative_number());
  cmd->add_option("--grinding-step", opts->job.grinding_step_deg, "cam angle step of the grinding table [cam deg]")
      ->check(CLI::Range(0.01, 10.0));
  cmd->add_option("--closure-tolerance", opts->job.closure_tolerance_mm,
                  "largest lift at the ends of a partial table, or step at the seam, closed on the base circle [mm]")
      ->check(non_negative_number());
  cmd->add_option("--min-radius", opts->job.min_radius_mm, "smallest allowed radius of curvature of the cam [mm]")
      ->check(non_negative_number());
  cmd->add_option("--max-round-trip-error", opts->job.max_round_trip_error,
                  "largest error of the synthesized profile's forward kinematics against the target, else no output "
                  "and exit 4 [mm; deg for a rotational --target-node]")
      ->check(positive_number());
  cmd->callback([opts, cmd] {
    if (!opts->job.smooth) reject_unused(*cmd, {"--knot-spacing"}, "without --smooth");
    run_synthesize(*opts);
  });
}

}  // namespace camopt::cli
