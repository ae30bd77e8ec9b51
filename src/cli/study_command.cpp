// camopt study STUDY.toml --out DIR: a design study (docs/studies.md). The study engine is the
// Python package's (camopt.studies: scipy's samplers, NLopt, Dask); this command runs it with
// the Python this build was made for and the package it built, replacing this process.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "cli_common.hpp"
#include "validators.hpp"

namespace camopt::cli {

namespace {

struct StudyOptions {
  std::string study_file, out_dir, scheduler;
  int workers = 0;  // 0: every core
};

[[noreturn]] void run_study(const StudyOptions& o) {
  if (!global_options().set.empty())
    throw InputError("--set: " + global_options().set.front() +
                     ": a study sets design values point by point, in its [[parameter]] tables (docs/studies.md)");
#if defined(CAMOPT_PYTHON_EXECUTABLE) && defined(CAMOPT_PYTHON_DIR)
  std::vector<std::string> args = {CAMOPT_PYTHON_EXECUTABLE, "-m", "camopt.studies", o.study_file, "--out", o.out_dir};
  if (o.workers > 0) args.insert(args.end(), {"--workers", std::to_string(o.workers)});
  if (!o.scheduler.empty()) args.insert(args.end(), {"--scheduler", o.scheduler});
  if (global_options().quiet) args.emplace_back("--quiet");
  // the package this build made first on the module path, before any the caller set
  const char* inherited = std::getenv("PYTHONPATH");
  const std::string path = std::string(CAMOPT_PYTHON_DIR) + (inherited && *inherited ? ":" + std::string(inherited) : "");
  if (setenv("PYTHONPATH", path.c_str(), 1) != 0) throw std::runtime_error("study: cannot set PYTHONPATH");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  execv(argv[0], argv.data());
  throw std::runtime_error("study: cannot run " + args[0] + " (" + std::strerror(errno) + ")");
#else
  (void)o;
  throw std::runtime_error(
      "study: this camopt was built without its Python module (CAMOPT_BUILD_PYTHON=OFF), which runs studies: "
      "build with scripts/setup.sh (pybind11-dev, python3-dev, python3-numpy) (docs/studies.md)");
#endif
}

}  // namespace

void setup_study(CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  auto* cmd = app.add_subcommand(
      "study", "run a design study: a DOE (full factorial, Latin hypercube, Sobol) or a geometry optimisation "
               "(NLopt) over design and constraint-set keys, each point a pipeline of synthesis or optimisation, "
               "kinematics and dynamics, on every local core or a Dask cluster (docs/studies.md)");
  cmd->add_option("study", o->study_file, "study file (TOML)")->required();
  cmd->add_option("--out", o->out_dir, "output directory (results.csv, pareto.csv, main_effects.csv, study.json)")
      ->required();
  cmd->add_option("--workers", o->workers, "local worker processes [count]; default every core, 1 = in one process")
      ->check(positive_number());
  cmd->add_option("--scheduler", o->scheduler, "run the points on this Dask scheduler's workers (tcp://HOST:PORT)");
  cmd->callback([o] { run_study(*o); });
}

}  // namespace camopt::cli
