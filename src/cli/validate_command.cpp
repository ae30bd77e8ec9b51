// camopt validate: check a design file and print the compiled mechanism.
#include <CLI/CLI.hpp>
#include <iostream>

#include "camopt/io/design_file.hpp"
#include "camopt/jobs/validate.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

void setup_validate(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("validate", "check design files and print each compiled mechanism "
                                             "(nodes, connections, solve order); writes no files, so no report");
  cmd->add_option("designs", *files, "design files (TOML)")->required();
  cmd->callback([files] {
    for (const auto& f : *files) {
      const DesignSpec spec = load_design_spec(f);
      const kin::Mechanism mech = kin::compile(spec);
      const jobs::DesignFindings findings = jobs::validate_design(spec, mech);
      if (!global_options().quiet) std::cout << f << ": ok\n" << findings.description;
      for (const auto& note : findings.warnings) info(f + ": warning: " + note);
      if (!global_options().quiet) std::cout << "\n";
    }
  });
}

}  // namespace camopt::cli
