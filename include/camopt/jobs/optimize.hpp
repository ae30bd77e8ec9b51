#pragma once
// the optimize job (camopt optimize): a cam's lift optimised under a constraint set, the profile
// synthesized for it and (verify) the made design checked, with what the CLI writes in memory:
// lift.csv (and a swing cam's swing_pitch.csv), the profile's files and report.json.
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/jobs/common.hpp"
#include "camopt/jobs/synthesize.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"

namespace camopt::jobs {

// every option of `camopt optimize` but its report
struct OptimizeOptions {
  std::string design_file;       // the design's file: report.json names it, design.toml is its text edited
  std::vector<io::Override> overrides;  // the changes the spec was parsed with (--set), edited into design.toml
  std::string constraints_file;  // the constraint set's file, as report.json names it
  std::string out_dir;           // the folder design.toml is written for (see SynthesizeOptions)
  std::string solver = "ipopt";  // --solver: ipopt, slsqp, mma, cobyla or global
  std::string cam = "rotational";  // --cam: rotational or swing
  bool verify = false;           // --verify
  int points = 1440;             // --points [count per revolution]
  int max_iterations = 3000;     // --max-iterations
  int starts = 6;                // --starts (global)
  // the solver's progress as it runs (the CLI's line on stderr); none: not reported
  std::function<void(const opt::SolverProgress&)> progress;
};

// what `camopt optimize` writes, in memory
struct OptimizeResult {
  // lift.csv, and a swing cam's swing_pitch.csv (none for an infeasible set)
  std::vector<std::pair<std::string, io::Columns>> tables;
  std::optional<ProfileExports> exports;  // none for an infeasible set
  nlohmann::json report;                  // report.json
  Status status;                          // the solver's: a failure is raised once the outputs are written
  bool verified = true;                   // verify: every check holds
  std::string verification_failures;      // verify: the failed checks, one line each
  std::string summary;                    // the CLI's closing line without its files
};

// InputError naming the option for a value out of its range (the CLI's checks of its options)
void validate(const OptimizeOptions& options);

// the optimisation, its profile and (verify) the made design's checks. Notes: the problem's
// size, the conflicting limits of an infeasible set, the verification's runs. The solver's
// phases are the observer's runs (begin, end), and its cancel check is asked at every
// iteration: Cancelled stops the solve. InputError for a bad set or option; NumericalError
// when the profile of the optimised lift cannot be made
OptimizeResult run_optimize(const DesignSpec& spec, opt::OptimizationSpec set, const OptimizeOptions& options,
                            Observer& observer);

}  // namespace camopt::jobs
