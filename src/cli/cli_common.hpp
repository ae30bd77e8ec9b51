#pragma once
// shared by the subcommands: exit codes, global options, progress bar, messages.
#include <chrono>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "camopt/io/atomic_file.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/common.hpp"
#include "camopt/jobs/range_option.hpp"
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

// InputError naming the option when a command-line value (or an item of a list "a,b" or a
// range "a:b:n") reads as a number that is not finite ("nan", "inf", "1e999"): no option
// takes one, and CLI11 would pass it on
void check_finite_arguments(int argc, const char* const* argv);

// every file a folder command may write into its --out folder: a run that succeeds removes
// the files of its list it did not write (a previous run's), and never any other file.
// report.html and the figures are written after the set is committed (write_run_report), so
// the commit removes an earlier run's report and figures first
inline const std::vector<std::string> kKinematicsOutputs = {"kinematics.csv", "kinematics.npz", "summary.json",
                                                            "report.html"};
inline const std::vector<std::string> kDynamicsOutputs = {"dynamics.csv", "dynamics.npz", "modes.csv", "summary.json",
                                                          "report.html"};
inline const std::vector<std::string> kSynthesizeOutputs = {"profile.csv", "report.json", "design.toml",
                                                            "profile.dxf", "grinding.csv", "report.html"};
inline const std::vector<std::string> kOptimizeOutputs = {"lift.csv",    "swing_pitch.csv", "profile.csv",
                                                          "report.json", "design.toml",     "profile.dxf",
                                                          "grinding.csv", "report.html"};

// the output set of a run into `out_dir` (one of the lists above, and the figures of the
// run the folder holds: previous_figures), the folder locked against other camopt runs; a
// run that has to wait says so on stderr
io::OutputTransaction open_outputs(const std::string& out_dir, const std::vector<std::string>& outputs);

// the steps the commands share, from the jobs layer
using jobs::ControlPositions;
using jobs::DriverRange;
using jobs::Extremes;
using jobs::LoadedDesign;
using jobs::driver_range;
using jobs::fail_at_position;
using jobs::held_rigid_hlas;
using jobs::kMaxSweepPoints;
using jobs::kMaxTotalPoints;
using jobs::parse_range;
using jobs::resolve_controls;
using jobs::sweep_points;

// the design file parsed and compiled; the drawing check's warnings on stderr
LoadedDesign load_mechanism(const std::string& design_path);

// --set, each KEY=VALUE read (InputError for one without '=')
std::vector<io::Override> design_overrides();
// the design file parsed with the --set overrides applied (io::DesignDocument)
DesignSpec load_design_spec(const std::string& design_path);

// the files of one output set (name, contents) staged into out_dir and committed together;
// returns the files committed (io::OutputTransaction::committed)
std::map<std::string, io::FileId> write_outputs(const std::string& out_dir, const std::vector<std::string>& output_set,
                                                const std::vector<std::pair<std::string, std::string>>& files);

// --format of a command that writes one result table (docs/outputs.md, "Table formats"):
// long (the CSV, one row per key values and angle), wide (the CSV, one row per angle, its
// first `wide_keys` columns folded into the names of the columns after its `wide_angles`
// angle columns) or npz (the long table's
// columns as NumPy arrays in <stem>.npz)
struct TableFormat {
  std::string layout = "long";
  std::size_t wide_keys = 0, wide_angles = 1;  // the long table's key and angle columns
};
// the --format option on a command; `wide`: what the wide layout is for, in its help
void add_format_option(CLI::App& cmd, std::string& layout, const std::string& wide);
// the file the table goes to: csv_name, or its stem with .npz
std::string table_file_name(const std::string& csv_name, const TableFormat& format);

// a job's table as table_file_name(csv_name, format) and its summary as summary.json
// (indented by 2), committed together into out_dir (write_outputs); the CSV is formatted on
// thread_count() threads
std::map<std::string, io::FileId> write_table_and_summary(const std::string& out_dir,
                                                          const std::vector<std::string>& output_set,
                                                          const std::string& csv_name, const io::Columns& table,
                                                          const nlohmann::json& summary,
                                                          const TableFormat& format = {});

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

// a job's observer on the terminal: its notes on stderr (info), its steps as a progress bar
class TerminalObserver : public jobs::Observer {
 public:
  void note(const std::string& message) override;
  void begin(const std::string& label, long steps) override;
  void advance() override;
  void end() override;

 private:
  std::optional<Progress> progress_;
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
void setup_study(CLI::App& app);
void setup_bench(CLI::App& app);

}  // namespace camopt::cli
