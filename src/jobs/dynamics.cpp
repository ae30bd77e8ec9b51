// the dynamics job: the rigid model (mode a, or mode b with compliant contacts) and the
// flexible model of a design over engine speeds and control positions.
#include "camopt/jobs/dynamics.hpp"

#include <chrono>
#include <functional>

#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/jobs/range_option.hpp"
#include "compliant_outputs.hpp"
#include "dynamics_setup.hpp"
#include "flexible_outputs.hpp"
#include "rigid_outputs.hpp"

namespace camopt::jobs {

namespace {

// --rpm: a value, a list or a range, each in (0, 1e6]
std::vector<double> parse_rpms(const std::string& option_value) {
  const std::vector<double> rpms = parse_range("--rpm", option_value);
  for (double r : rpms)
    if (!(r > 0 && r <= 1e6)) throw InputError("--rpm: value " + format_value(r, 6) + " must be in (0, 1e6]");
  return rpms;
}

// the design's dynamics model, the speeds, the cam angles and the control positions
DynamicsSetup make_setup(const LoadedDesign& design, const DynamicsOptions& o, Observer& observer) {
  DynamicsSetup su{design.spec, design.mech, observer, {}, {}, {}, {}};
  su.model = dynamics::compile_dynamics(su.spec, su.mech);
  su.rpms = parse_rpms(o.rpm);
  su.range = driver_range(su.mech, o.step_deg);
  su.controls = resolve_controls(su.mech, o.design_file, o.control);
  sweep_points(o.step_deg > 0 ? "--step" : "driver.step_deg", su.range.start, su.range.stop, su.range.step,
               static_cast<double>(su.controls.positions.size() * su.rpms.size()), "--control x --rpm");
  return su;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// mode (a) at every control position: one sweep each, split by load case; `steps`: one
// observer step per position
std::vector<dynamics::RigidSweep> rigid_sweeps(const DynamicsSetup& su, bool steps) {
  std::vector<dynamics::RigidSweep> sweeps(su.controls.positions.size());
  if (steps) su.observer.begin("dynamics", static_cast<long>(sweeps.size()));
  StepCounter counter(su.observer);
  for (std::size_t p = 0; p < sweeps.size(); ++p) {
    const Status st = dynamics::rigid_sweep(su.mech, su.model, su.controls.positions[p], su.range.start,
                                            su.range.stop, su.range.step, sweeps[p]);
    if (!st.ok()) fail_at_position(su.mech, su.controls, st, p);
    if (steps) counter.step_done();
  }
  if (steps) su.observer.end();
  return sweeps;
}

// mode (a): the kinematically constrained inverse dynamics, one sweep per control position,
// every speed from its split load cases
DynamicsResult run_rigid(const DynamicsSetup& su, const DynamicsOptions& o) {
  DynamicsResult out;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<dynamics::RigidSweep> sweeps = rigid_sweeps(su, true);
  out.seconds = seconds_since(t0);
  out.summary = rigid_summary(su, o.design_file, sweeps, out.seconds);
  out.columns = rigid_columns(su, sweeps);
  out.points = sweeps[0].points();
  return out;
}

// mode (b): stiff separable contacts integrated in time, one run per (rpm, control)
DynamicsResult run_compliant_contacts(const DynamicsSetup& su, const DynamicsOptions& o) {
  DynamicsResult out;
  const auto t0 = std::chrono::steady_clock::now();
  // mode (a) at every control position, for its forces beside the integrated ones
  const std::vector<dynamics::RigidSweep> rigid = rigid_sweeps(su, false);
  // one CVODE run per (rpm, control position)
  const std::vector<CompliantRun> runs =
      run_grid<dynamics::CompliantResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_compliant(su.mech, su.model, controls, rpm, su.range.start, su.range.stop,
                                       su.range.step, dynamics::CompliantOptions{}, result);
      });
  out.seconds = seconds_since(t0);
  out.summary = compliant_summary(su, o.design_file, runs, out.seconds);
  out.columns = compliant_columns(su, runs, rigid);
  out.runs = runs.size();
  return out;
}

// the observer's cancel_requested for a run's output points, asked at most every 20 ms of
// wall time (the check may wait for the caller's interpreter)
constexpr std::chrono::milliseconds kCancelCheckInterval{20};
std::function<bool()> throttled_cancel_check(Observer& observer) {
  return [&observer, last = std::chrono::steady_clock::now()]() mutable {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < kCancelCheckInterval) return false;
    last = now;
    return observer.cancel_requested();
  };
}

// the flexible model: one CVODE run per (rpm, control), the last revolution reported; a
// cancel is asked between output points too, so one long run stops within tens of ms
DynamicsResult run_flexible_model(const DynamicsSetup& su, const DynamicsOptions& o) {
  DynamicsResult out;
  const auto t0 = std::chrono::steady_clock::now();
  dynamics::FlexibleOptions flexible = o.flexible;
  flexible.stop_requested = throttled_cancel_check(su.observer);
  const std::vector<FlexibleRun> runs =
      run_grid<dynamics::FlexibleResult>(su, [&](double rpm, const std::vector<double>& controls, auto& result) {
        return dynamics::run_flexible(su.mech, su.model, controls, rpm, su.range.start, su.range.stop, su.range.step,
                                      flexible, result);
      });
  out.seconds = seconds_since(t0);
  // the columns, then the summary (with the runs' warnings as notes)
  out.columns = flexible_columns(su, runs, o.flexible.coil_displacements);
  out.summary = flexible_summary(su, o.design_file, o.flexible, runs, out.seconds);
  out.runs = runs.size();
  return out;
}

}  // namespace

void validate(const DynamicsOptions& o) {
  if (o.model != "rigid" && o.model != "flexible")
    throw InputError("--model: value '" + o.model + "' is not one of rigid, flexible (modes: the CLI)");
  if (o.contacts != "rigid" && o.contacts != "compliant")
    throw InputError("--contacts: value '" + o.contacts + "' is not one of rigid, compliant");
  if (o.rpm.empty()) throw InputError("--rpm: required (an engine speed, a list or START:STOP:COUNT)");
  check_positive("--step", o.step_deg, false);
  const dynamics::FlexibleOptions& f = o.flexible;
  if (f.revolutions < 1 || f.revolutions > 1000)
    throw InputError("--revolutions: value " + std::to_string(f.revolutions) + " must be in [1, 1000]");
  if (!(f.relative_tolerance >= 1e-14 && f.relative_tolerance <= 1e-1))
    throw InputError("--rtol: value " + format_value(f.relative_tolerance) + " must be in [1e-14, 0.1]");
  if (!(f.absolute_tolerance >= 1e-16 && f.absolute_tolerance <= 1.0))
    throw InputError("--atol: value " + format_value(f.absolute_tolerance) + " must be in [1e-16, 1]");
}

DynamicsResult run_dynamics(const LoadedDesign& design, const DynamicsOptions& o, Observer& observer) {
  // the options, the dynamics model, the speeds and control positions
  validate(o);
  const DynamicsSetup su = make_setup(design, o, observer);
  // the model asked for
  DynamicsResult out = o.model == "flexible"       ? run_flexible_model(su, o)
                       : o.contacts == "compliant" ? run_compliant_contacts(su, o)
                                                   : run_rigid(su, o);
  record_overrides(out.summary, design.overrides);
  out.positions = su.controls.values.size();
  out.speeds = su.rpms.size();
  return out;
}

}  // namespace camopt::jobs
