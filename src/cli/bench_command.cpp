// camopt bench: work-precision benchmarks (issue #8); per-capability benchmarks live in bench/.
#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace camopt::cli {

void setup_bench(CLI::App& app) {
  auto out_dir = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("bench", "run time against error for every capability (not built yet; "
                                          "see bench/README.md for the bench/ executables)");
  cmd->add_option("--out", *out_dir, "output directory for the work-precision CSV tables");
  cmd->callback([out_dir] { throw NotBuilt{"bench is not built yet (issue #8); use the bench/ executables"}; });
}

}  // namespace camopt::cli
