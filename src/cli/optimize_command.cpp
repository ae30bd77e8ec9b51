// camopt optimize: constrained cam optimisation with Ipopt / NLopt (issue #5).
#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace camopt::cli {

namespace {
struct OptimizeOptions {
  std::string design, constraints, solver = "ipopt", out_dir;
  bool verify = false;
};
}  // namespace

void setup_optimize(CLI::App& app) {
  auto opts = std::make_shared<OptimizeOptions>();
  auto* cmd = app.add_subcommand("optimize", "optimise a cam profile under acceleration, curvature, pressure-angle "
                                             "and stress limits (not built yet)");
  cmd->add_option("design", opts->design, "design file (TOML)")->required();
  cmd->add_option("--constraints", opts->constraints, "constraint set (TOML, see constraints/)")->required();
  cmd->add_option("--solver", opts->solver, "ipopt, slsqp, mma, cobyla or global");
  cmd->add_option("--out", opts->out_dir, "output directory")->required();
  cmd->add_flag("--verify", opts->verify, "run the optimised design through kinematics and dynamics");
  cmd->callback([opts] { throw NotBuilt{"optimize is not built yet (issue #5: constrained optimisation)"}; });
}

}  // namespace camopt::cli
