#pragma once
// shared by the subcommands: exit codes, global options, progress bar, messages.
#include <chrono>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "camopt/io/atomic_file.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/report/report.hpp"

namespace CLI {
class App;
}

namespace camopt::cli {

// process exit codes (README "Exit codes")
enum ExitCode : int {
  exit_ok = 0,
  exit_internal_error = 1,
  exit_usage_error = 2,
  exit_input_error = 3,
  exit_numerical_failure = 4,
  exit_verification_failed = 5,  // optimize --verify: the outputs are written, the made design fails a check
};

// thrown once the outputs are written when `optimize --verify` fails a check
class VerificationFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlobalOptions {
  std::vector<std::string> set;  // --set KEY=VALUE: design overrides, in order
  bool quiet = false;
  bool verbose = false;
  int threads = 0;               // 0 = all hardware threads
  std::string progress = "auto";  // auto (when stderr is a terminal), always, never
};

GlobalOptions& global_options();
bool progress_line_wanted();  // draw progress lines in place on stderr (--progress, --quiet)
int thread_count();  // resolved --threads

// largest and smallest value of a series and where (e.g. the cam angle) each occurred
struct Extremes {
  double max = -std::numeric_limits<double>::infinity(), min = std::numeric_limits<double>::infinity();
  double max_at = 0, min_at = 0;
  void add(double v, double at) {
    if (v > max) max = v, max_at = at;
    if (v < min) min = v, min_at = at;
  }
};

// InputError naming the option when a command-line value (or an item of a list "a,b" or a
// range "a:b:n") reads as a number that is not finite ("nan", "inf", "1e999"): no option
// takes one, and CLI11 would pass it on
void check_finite_arguments(int argc, const char* const* argv);

// the largest sweep a command runs: points per position, and points over every position
// (and rpm); beyond them an InputError names the option, the count and the limit, before
// anything is allocated (docs/cli.md, "Limits")
inline constexpr double kMaxSweepPoints = 1e6;
inline constexpr double kMaxTotalPoints = 2e7;
// the point count of start..stop by step (both ends); InputError naming `option` above the limits
long sweep_points(const std::string& option, double start, double stop, double step, double positions = 1,
                  const std::string& positions_option = "--control");

// every file a folder command may write into its --out folder: a run that succeeds removes
// the files of its list it did not write (a previous run's), and never any other file.
// report.html and the figures are written after the set is committed (write_run_report), so
// the commit removes an earlier run's report and figures first
inline const std::vector<std::string> kKinematicsOutputs = {"kinematics.csv", "summary.json", "report.html"};
inline const std::vector<std::string> kDynamicsOutputs = {"dynamics.csv", "modes.csv", "summary.json", "report.html"};
inline const std::vector<std::string> kSynthesizeOutputs = {"profile.csv", "report.json", "design.toml",
                                                            "profile.dxf", "grinding.csv", "report.html"};
inline const std::vector<std::string> kOptimizeOutputs = {"lift.csv",    "swing_pitch.csv", "profile.csv",
                                                          "report.json", "design.toml",     "profile.dxf",
                                                          "grinding.csv", "report.html"};

// the output set of a run into `out_dir` (one of the lists above, and the figures of the
// run the folder holds: previous_figures), the folder locked against other camopt runs; a
// run that has to wait says so on stderr
io::OutputTransaction open_outputs(const std::string& out_dir, const std::vector<std::string>& outputs);

// the steps the commands share
// a design file as parsed and as compiled. The spec is the source description that the
// dynamics data and an edited recompile read; the compiled mechanism is what the kernels take.
struct LoadedDesign {
  DesignSpec spec;
  kin::Mechanism mech;  // kin::compile(spec)
};

// the design file parsed and compiled; the drawing check's warnings on stderr
LoadedDesign load_mechanism(const std::string& design_path);

// --set, each KEY=VALUE read (InputError for one without '=')
std::vector<io::Override> design_overrides();
// the design file parsed with the --set overrides applied (io::DesignDocument)
DesignSpec load_design_spec(const std::string& design_path);
// summary.json / report.json: "overrides": {"key.path": value} when --set was given
void record_overrides(nlohmann::json& summary);
nlohmann::json with_overrides(nlohmann::json summary);

// the design's hydraulic lash adjusters, which every model but the flexible one holds rigid
// (their node's pivot fixed): a note on stderr naming `what` ran, and their names for
// summary.json's "hla_held_rigid" (empty without an HLA)
std::vector<std::string> held_rigid_hlas(const DesignSpec& spec, const std::string& what);

// the driver range of the design and the step: --step when given (> 0), else driver.step_deg;
// InputError when the step exceeds the range
struct DriverRange {
  double start = 0.0, stop = 0.0, step = 0.0;  // [driver deg, or mm for a translational driver]
};
DriverRange driver_range(const kin::Mechanism& mech, double step_option);

// the control positions of a run: the design's first control at each value of --control (a
// value, a list a,b,c or START:STOP:COUNT, inside the control's range), the others at their
// defaults; without --control the first control's default (0 without controls)
struct ControlPositions {
  std::vector<double> values;                  // the first control's values
  std::vector<std::vector<double>> positions;  // every control, per value
  std::string unit;                            // "deg" or "mm"
};
ControlPositions resolve_controls(const kin::Mechanism& mech, const std::string& design_path,
                                  const std::string& control_option);

// a numerical failure at one control position: its Status named with the control's value
[[noreturn]] void fail_at_position(const kin::Mechanism& mech, const ControlPositions& controls, Status status,
                                   std::size_t position);

// the files of one output set (name, contents) staged into out_dir and committed together;
// returns the files committed (io::OutputTransaction::committed)
std::map<std::string, io::FileId> write_outputs(const std::string& out_dir, const std::vector<std::string>& output_set,
                                                const std::vector<std::pair<std::string, std::string>>& files);

// seconds of wall time since t0
double seconds_since(std::chrono::steady_clock::time_point t0);

// InputError when an input file is one of the files the run writes into its output folder
// (`--out`): the run would overwrite its own input
void check_inputs_outside(const std::string& out_dir, std::initializer_list<std::string> inputs,
                          const std::vector<std::string>& outputs);

// informational output on stderr (suppressed by --quiet); results go to files / stdout
void info(const std::string& message);
void detail(const std::string& message);  // only with --verbose

// a progress bar on stderr, drawn only when stderr is a terminal and not --quiet
class Progress {
 public:
  Progress(std::string label, long total);
  ~Progress();
  void advance(long steps = 1);

 private:
  void draw();
  std::string label_;
  long total_ = 0, done_ = 0;
  int last_percent_ = -1;
  bool enabled_ = false;
};

// the report (report_command.cpp): what a command that writes results writes after them.
// --no-report skips report.html (<stem>.report.html beside a lift table); --figures svg|png
// also writes the run's main plots as static images, <plot id>.svg|png in the folder
// (<stem>.<plot id>.svg|png beside a lift table), with or without the report
struct ReportOptions {
  bool no_report = false;
  std::string figures;  // "", "svg" or "png"
};
// the options' help names the files: `where` the report, `figures` the figures
void add_report_options(CLI::App& cmd, ReportOptions& report, const std::string& where = "report.html",
                        const std::string& figures = "<plot id>.svg or .png in the folder");
void add_figures_option(CLI::App& cmd, std::string& figures, const std::string& files);
// the report and figures of `source` (an --out folder or a lift table), made from one read of
// the outputs while the folder is locked and committed together. A failure leaves neither and
// says the outputs are written (InputError, exit 3)
// `written`: tables of the run still in memory, taken instead of their files while the folder
// holds the files the run committed (report::collect)
void write_run_report(const std::string& source, const ReportOptions& report, const report::WrittenTables& written = {});
// the table `name` of a run as the report takes it: with the file that write_outputs committed
// (none when it committed no such file)
report::WrittenTables hand_over(const std::map<std::string, io::FileId>& committed, const std::string& name,
                                io::Columns table);
// the figure files in out_dir of the run the folder holds: the names of its main plots in
// either format that are there (none when the folder holds no .svg or .png file, or no result
// camopt can read). A run's output set includes them, so a run removes an earlier run's figures
std::vector<std::string> previous_figures(const std::string& out_dir);

// subcommand registration: one file per subcommand (<verb>_command.cpp)
void setup_validate(CLI::App& app);
void setup_kinematics(CLI::App& app);
void setup_synthesize(CLI::App& app);
void setup_lift(CLI::App& app);
void setup_optimize(CLI::App& app);
void setup_dynamics(CLI::App& app);
void setup_report(CLI::App& app);

}  // namespace camopt::cli
