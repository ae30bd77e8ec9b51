// camopt lift: lift-law library (issue #4).
#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace camopt::cli {

namespace {
struct LiftOptions {
  std::string law, out;
  double lift_mm = 10.0, duration_deg = 240.0;
};
}  // namespace

void setup_lift(CLI::App& app) {
  auto opts = std::make_shared<LiftOptions>();
  auto* cmd = app.add_subcommand("lift", "generate a target valve lift from a lift law (not built yet)");
  cmd->add_option("--law", opts->law, "lift law: polynomial-345, polynomial-4567, cycloidal, modified-trapezoid, "
                                      "modified-sine, polydyne, bspline")->required();
  cmd->add_option("--lift", opts->lift_mm, "maximum lift [mm]");
  cmd->add_option("--duration", opts->duration_deg, "duration [cam deg]");
  cmd->add_option("--out", opts->out, "output CSV (cam_deg, lift_mm, ...)")->required();
  cmd->callback([opts] { throw NotBuilt{"lift is not built yet (issue #4: lift-law library)"}; });
}

}  // namespace camopt::cli
