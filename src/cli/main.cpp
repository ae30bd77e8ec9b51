// camopt: command-line entry. Maps the error channels to exit codes.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "camopt/core/error.hpp"
#include "camopt/core/process_memory.hpp"
#include "cli_common.hpp"

int main(int argc, char** argv) {
  using namespace camopt::cli;
  camopt::keep_freed_memory();
  CLI::App app{"camopt " CAMOPT_VERSION
               " - valvetrain cam design: planar kinematics, envelope synthesis, optimisation, dynamics.\n"
               "Units: lengths mm, angles deg, forces N, masses kg, speeds rpm (engine crankshaft)."};
  app.set_version_flag("--version", "camopt " CAMOPT_VERSION);
  app.require_subcommand(1);
  app.fallthrough();
  auto& global = global_options();
  app.add_flag("-q,--quiet", global.quiet, "print nothing but errors on stderr");
  app.add_flag("-v,--verbose", global.verbose, "print solver details on stderr");
  app.add_option("--threads", global.threads, "worker threads for sweeps [count]; 0 = all cores")
      ->check(CLI::NonNegativeNumber);

  setup_validate(app);
  setup_kinematics(app);
  setup_synthesize(app);
  setup_lift(app);
  setup_optimize(app);
  setup_dynamics(app);

  try {
    check_finite_arguments(argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return exit_usage_error;
  } catch (const camopt::InputError& e) {
    std::fprintf(stderr, "camopt: input error: %s\n", e.what());
    return exit_input_error;
  } catch (const VerificationFailed& e) {
    std::fprintf(stderr, "camopt: %s\n", e.what());
    return exit_verification_failed;
  } catch (const camopt::NumericalError& e) {
    std::fprintf(stderr, "camopt: numerical failure: %s\n", e.what());
    return exit_numerical_failure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "camopt: internal error: %s\n", e.what());
    return exit_internal_error;
  }
  return exit_ok;
}
