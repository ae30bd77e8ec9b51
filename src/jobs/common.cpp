#include "camopt/jobs/common.hpp"

#include <cmath>

#include "camopt/jobs/range_option.hpp"
#include "camopt/kinematics/drawing_check.hpp"

namespace camopt::jobs {

void StepCounter::step_done() {
  const std::lock_guard<std::mutex> lock(mutex_);
  observer_.advance();
  if (observer_.cancel_requested()) throw Cancelled();
}

long sweep_points(const std::string& option, double start, double stop, double step, double positions,
                  const std::string& positions_option) {
  const double points = std::floor((stop - start) / step + 0.5) + 1.0;
  if (!(points <= kMaxSweepPoints))
    throw InputError(option + ": value " + format_value(step, 6) + " gives " + format_value(points, 6) +
                     " points over the driver range " + format_value(start, 6) + ".." + format_value(stop, 6) +
                     " (at most " + format_value(kMaxSweepPoints, 6) + ")");
  if (!(points * positions <= kMaxTotalPoints))
    throw InputError(positions_option + ": " + format_value(positions, 6) + " runs x " + format_value(points, 6) +
                     " points = " + format_value(points * positions, 6) + " (at most " +
                     format_value(kMaxTotalPoints, 6) + ")");
  return static_cast<long>(points);
}

std::vector<std::string> held_rigid_hlas(const DesignSpec& spec, const std::string& what, Observer& observer) {
  std::vector<std::string> names;
  for (const HlaSpec& h : spec.hlas) {
    names.push_back(h.name);
    observer.note(what + ": note: hla '" + h.name + "' under node '" + h.node +
                  "' is held rigid (its pivot fixed); dynamics --model flexible moves it with its oil");
  }
  return names;
}

LoadedDesign compile_design(DesignSpec spec, const std::string& design_path, Observer& observer,
                            std::vector<io::Override> overrides) {
  LoadedDesign d;
  d.spec = std::move(spec);
  d.mech = kin::compile(d.spec);
  d.overrides = std::move(overrides);
  for (const auto& note : kin::check_drawing(d.mech)) observer.note(design_path + ": warning: " + note);
  return d;
}

void record_overrides(nlohmann::json& summary, const std::vector<io::Override>& overrides) {
  if (overrides.empty()) return;
  nlohmann::json recorded = nlohmann::json::object();
  for (const io::Override& o : overrides) {
    // a TOML number, boolean or array of numbers reads as JSON; a string is unquoted
    nlohmann::json value = nlohmann::json::parse(o.value, nullptr, false);
    if (value.is_discarded()) value = o.value;
    recorded[o.key] = value;
  }
  summary["overrides"] = recorded;
}

DriverRange driver_range(const kin::Mechanism& mech, double step_option) {
  DriverRange r;
  r.start = mech.driver.start;
  r.stop = mech.driver.stop;
  r.step = step_option > 0 ? step_option : mech.driver.step;
  if (r.step > r.stop - r.start)
    throw InputError("--step: value " + std::to_string(r.step) + " exceeds the driver range " +
                     std::to_string(r.stop - r.start));
  return r;
}

ControlPositions resolve_controls(const kin::Mechanism& mech, const std::string& design_path,
                                  const std::string& control_option) {
  ControlPositions c;
  if (!control_option.empty()) {
    if (mech.controls.empty()) throw InputError("--control: design '" + design_path + "' has no [[control]]");
    const auto& c0 = mech.controls[0];
    c.values = parse_range("--control", control_option);
    for (double v : c.values)
      if (v < c0.min - 1e-12 || v > c0.max + 1e-12)
        throw InputError("--control: value " + format_value(v, 12) + " is outside control '" + c0.name +
                         "' range [" + format_value(c0.min, 12) + ", " + format_value(c0.max, 12) + "]");
  } else {
    c.values.push_back(mech.controls.empty() ? 0.0 : mech.controls[0].default_value);
  }
  const std::vector<double> defaults = mech.default_controls();
  for (double v : c.values) {
    auto pos = defaults;
    if (!pos.empty()) pos[0] = v;
    c.positions.push_back(pos);
  }
  c.unit = mech.controls.empty() || mech.controls[0].is_angle ? "deg" : "mm";
  return c;
}

void fail_at_position(const kin::Mechanism& mech, const ControlPositions& controls, Status status,
                      std::size_t position) {
  if (!mech.controls.empty())
    status.where += ", control " + mech.controls[0].name + " = " + format_value(controls.values[position], 12);
  throw NumericalError(status);
}

void check_positive(const std::string& option, double value, bool strict) {
  if (strict ? !(value > 0.0) : !(value >= 0.0))
    throw InputError(option + ": value " + format_value(value) + (strict ? " must be > 0" : " must be >= 0"));
}

}  // namespace camopt::jobs
