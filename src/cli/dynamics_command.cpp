// camopt dynamics: rigid (issue #6) and flexible (issue #7) valvetrain dynamics.
#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace camopt::cli {

namespace {
struct DynamicsOptions {
  std::string design, model = "rigid", rpm, out_dir;
};
}  // namespace

void setup_dynamics(CLI::App& app) {
  auto opts = std::make_shared<DynamicsOptions>();
  auto* cmd = app.add_subcommand("dynamics", "rigid or flexible valvetrain dynamics (not built yet)");
  cmd->add_option("design", opts->design, "design file (TOML)")->required();
  cmd->add_option("--model", opts->model, "rigid or flexible")->check(CLI::IsMember({"rigid", "flexible"}));
  cmd->add_option("--rpm", opts->rpm, "engine speed [rpm, crankshaft]: a value, a list a,b,c or START:STOP:COUNT")
      ->required();
  cmd->add_option("--out", opts->out_dir, "output directory")->required();
  cmd->callback([opts] { throw NotBuilt{"dynamics is not built yet (issues #6 rigid, #7 flexible)"}; });
}

}  // namespace camopt::cli
