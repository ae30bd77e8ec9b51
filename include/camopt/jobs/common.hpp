#pragma once
// what every job shares: the observer a caller hears a job through (notes, progress,
// cancellation), a design as parsed and compiled, and the steps that turn a job's options into
// a sweep (driver range, control positions, point limits). A job is the computation of one
// CLI subcommand without its files: the CLI writes what it returns, the Python module hands
// it over as arrays and dicts. Messages name the CLI's options (--step, --control, ...).
#include <cstddef>
#include <limits>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::jobs {

// how a job talks to its caller. The CLI prints the notes on stderr and draws a progress bar;
// the Python module keeps the notes and checks for Ctrl-C. Every member may be called from a
// worker thread, one call at a time (the job serialises them).
class Observer {
 public:
  virtual ~Observer() = default;
  // an informational line ("kinematics: max lift ...", a drawing warning)
  virtual void note(const std::string& message) { (void)message; }
  // a run of `steps` steps (control positions, engine speeds) starts, named `label`
  virtual void begin(const std::string& label, long steps) { (void)label, (void)steps; }
  // one step of the run is done
  virtual void advance() {}
  // the run of steps is over (the job goes on to its summaries)
  virtual void end() {}
  // true: stop the job (it throws Cancelled); asked once per step, and within a long
  // time-integrated run at most every 20 ms of wall time, never per point
  virtual bool cancel_requested() { return false; }
};

// a job stopped because its observer asked (Observer::cancel_requested)
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// the observer's advance and cancel_requested for a job's worker threads: one call at a time,
// and Cancelled thrown when the observer asks (the sweep then stops its workers)
class StepCounter {
 public:
  explicit StepCounter(Observer& observer) : observer_(observer) {}
  void step_done();

 private:
  Observer& observer_;
  std::mutex mutex_;
};

// largest and smallest value of a series and where (e.g. the cam angle) each occurred
struct Extremes {
  double max = -std::numeric_limits<double>::infinity(), min = std::numeric_limits<double>::infinity();
  double max_at = 0, min_at = 0;
  void add(double v, double at) {
    if (v > max) max = v, max_at = at;
    if (v < min) min = v, min_at = at;
  }
};

// the largest sweep a job runs: points per position, and points over every position (and
// rpm); beyond them an InputError names the option, the count and the limit, before anything
// is allocated (docs/cli.md, "Limits")
inline constexpr double kMaxSweepPoints = 1e6;
inline constexpr double kMaxTotalPoints = 2e7;
// the point count of start..stop by step (both ends); InputError naming `option` above the limits
long sweep_points(const std::string& option, double start, double stop, double step, double positions = 1,
                  const std::string& positions_option = "--control");

// a design file as parsed and as compiled. The spec is the source description that the
// dynamics data and an edited recompile read; the compiled mechanism is what the kernels take.
struct LoadedDesign {
  DesignSpec spec;
  kin::Mechanism mech;                  // kin::compile(spec)
  std::vector<io::Override> overrides;  // the changes the spec was parsed with (--set, Design.set)
};

// a parsed design compiled; the drawing check's warnings as notes ("<file>: warning: ...");
// `overrides`: the changes it was parsed with, which its jobs' summaries record
LoadedDesign compile_design(DesignSpec spec, const std::string& design_path, Observer& observer,
                            std::vector<io::Override> overrides = {});

// summary.json's and report.json's "overrides": {"key.path": value}, the changes the design
// was parsed with (a TOML number, boolean or array reads as JSON, a string as its text); no key
// without changes
void record_overrides(nlohmann::json& summary, const std::vector<io::Override>& overrides);

// the design's hydraulic lash adjusters, which every model but the flexible one holds rigid
// (their node's pivot fixed): a note naming `what` ran, and their names for summary.json's
// "hla_held_rigid" (empty without an HLA)
std::vector<std::string> held_rigid_hlas(const DesignSpec& spec, const std::string& what, Observer& observer);

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

// InputError "<option>: value <v> must be > 0" (>= 0 when !strict), the CLI's check of a
// number option, for a caller that passes the number itself
void check_positive(const std::string& option, double value, bool strict = true);

}  // namespace camopt::jobs
