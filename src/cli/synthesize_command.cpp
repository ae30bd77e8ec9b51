// camopt synthesize: envelope-theory cam synthesis from a target lift (issue #4).
#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace camopt::cli {

namespace {
struct SynthesizeOptions {
  std::string target_csv, design, out_dir, cam = "rotational";
  double control_deg = 0.0;
  int points = 720;
};
}  // namespace

void setup_synthesize(CLI::App& app) {
  auto opts = std::make_shared<SynthesizeOptions>();
  auto* cmd = app.add_subcommand("synthesize", "compute the cam profile that produces a target valve lift (not built yet)");
  cmd->add_option("target", opts->target_csv, "target lift CSV: cam_deg|crank_deg, lift_mm")->required();
  cmd->add_option("--design", opts->design, "design file (TOML)")->required();
  cmd->add_option("--out", opts->out_dir, "output directory")->required();
  cmd->add_option("--cam", opts->cam, "which cam to synthesize")->check(CLI::IsMember({"rotational", "swing"}));
  cmd->add_option("--control", opts->control_deg, "control position [deg or mm, per the design's control unit]");
  cmd->add_option("--points", opts->points, "profile points per revolution [count]")->check(CLI::PositiveNumber);
  cmd->callback([opts] { throw NotBuilt{"synthesize is not built yet (issue #4: envelope-theory synthesis)"}; });
}

}  // namespace camopt::cli
