#include <CLI/CLI.hpp>
#include "cli_common.hpp"
namespace camopt::cli {
void setup_kinematics(CLI::App& app) { app.add_subcommand("kinematics", "tmp"); }
}
