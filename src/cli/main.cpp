// camopt: command-line entry. Maps the error channels to exit codes.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/core/printable.hpp"
#include "camopt/core/process_memory.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace {

// prints "camopt: <kind><message>" with the message's control bytes and bytes that are not
// UTF-8 escaped line by line (a message may quote a user's binary file or a file name)
void report(const char* kind, const char* message) {
  std::string safe;
  for (std::string_view rest = message;;) {
    const std::size_t end = rest.find('\n');
    safe += camopt::printable(rest.substr(0, end), std::string::npos);
    if (end == std::string_view::npos) break;
    safe += '\n';
    rest.remove_prefix(end + 1);
  }
  std::fprintf(stderr, "camopt: %s%s\n", kind, safe.c_str());
}

// --set changes a design: a subcommand that reads none refuses it (before it runs)
void check_overrides_apply(int argc, const char* const* argv) {
  std::string subcommand, first_set;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--set" && i + 1 < argc && first_set.empty()) first_set = argv[i + 1];
    if (word.rfind("--set=", 0) == 0 && first_set.empty()) first_set = word.substr(6);
    if (word == "--threads" || word == "--progress" || word == "--set") ++i;
    else if (subcommand.empty() && !word.empty() && word[0] != '-') subcommand = word;
  }
  if (!first_set.empty() && (subcommand == "lift" || subcommand == "report"))
    throw camopt::InputError("--set " + first_set + ": '" + subcommand +
                             "' reads no design file (--set applies to validate, kinematics, synthesize, "
                             "optimize, dynamics and bench)");
}

}  // namespace

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
  app.add_option("--set", global.set,
                 "KEY=VALUE: change a value of the design before it is read, e.g. --set "
                 "connection.cam_roller.b.radius_mm=9 (repeatable; key paths: docs/design-format.md)")
      ->allow_extra_args(false)
      ->type_name("KEY=VALUE");
  app.add_flag("-q,--quiet", global.quiet, "print nothing but errors on stderr");
  app.add_flag("-v,--verbose", global.verbose, "print solver details on stderr");
  app.add_option("--threads", global.threads, "worker threads for sweeps [count]; 0 = all cores")
      ->check(non_negative_number());
  app.add_option("--progress", global.progress,
                 "progress on stderr: auto (a line redrawn in place when stderr is a terminal, else one line per "
                 "optimiser phase), always (redrawn in place), never")
      ->check(CLI::IsMember({"auto", "always", "never"}));

  setup_validate(app);
  setup_kinematics(app);
  setup_synthesize(app);
  setup_lift(app);
  setup_optimize(app);
  setup_dynamics(app);
  setup_report(app);
  setup_study(app);
  setup_bench(app);

  // a first word that names no subcommand (a typo): say so, with the subcommands
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--threads" || word == "--progress" || word == "--set") ++i;
    if (word.empty() || word[0] == '-') continue;
    std::string names;
    bool known = false;
    for (const auto* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == word;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (known) break;
    std::fprintf(stderr, "camopt: unknown subcommand '%s' (subcommands: %s)\nRun with --help for more information.\n",
                 camopt::printable(word).c_str(), names.c_str());
    return exit_usage_error;
  }

  try {
    check_finite_arguments(argc, argv);
    check_overrides_apply(argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ValidationError& e) {
    // a value out of its range: bad input, as the design and table checks
    report("input error: ", e.what());
    return exit_input_error;
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return exit_usage_error;
  } catch (const camopt::InputError& e) {
    report("input error: ", e.what());
    return exit_input_error;
  } catch (const VerificationFailed& e) {
    report("", e.what());
    return exit_verification_failed;
  } catch (const camopt::NumericalError& e) {
    report("numerical failure: ", e.what());
    return exit_numerical_failure;
  } catch (const std::exception& e) {
    report("internal error: ", e.what());
    return exit_internal_error;
  }
  return exit_ok;
}
