// the validate job: a compiled design described, as `camopt validate` prints it.
#include "camopt/jobs/validate.hpp"

#include <charconv>

#include "camopt/core/error.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/kinematics/drawing_check.hpp"

namespace camopt::jobs {

namespace {

// the flexible model's laws, stiffnesses and damping, each marked when it is a default; a
// design without the dynamics data (masses) has none
std::string describe_flexible(const DesignSpec& spec, const kin::Mechanism& mech) {
  dynamics::Model model;
  try {
    model = dynamics::compile_dynamics(spec, mech);
  } catch (const InputError& e) {
    return "flexible model: not available (" + std::string(e.what()) + ")\n";
  }
  const std::vector<double> controls = mech.default_controls();
  const auto parameters = dynamics::flexible_parameters(mech, model, controls, dynamics::FlexibleOptions{});
  if (parameters.empty()) return "flexible model: not available (its kinematic path does not assemble)\n";
  std::string out = "flexible model (docs/dynamics.md; [default] = not in the design):\n";
  for (const auto& p : parameters)
    out += "  " + p.key + " = " + p.value + (p.unit.empty() ? "" : " " + p.unit) + (p.from_design ? "" : "  [default]") + "\n";
  return out;
}

// the engine oil of the EHL film thickness ([oil]), or nothing without one
std::string describe_oil(const DesignSpec& spec) {
  if (!spec.oil) return {};
  const OilSpec& o = *spec.oil;
  std::string out = "oil: viscosity " + format_value(o.viscosity_mPa_s) + " mPa s, pressure-viscosity " +
                    format_value(o.pressure_viscosity_per_GPa) + " /GPa";
  out += o.composite_roughness_um ? ", composite roughness " + format_value(*o.composite_roughness_um) + " um"
                                  : ", no composite roughness (no lambda)";
  return out + "\n";
}

// the contacts that touch at rest, each with its solved position (shortest round-trip numbers)
std::string describe_assembled(const kin::Mechanism& mech) {
  const auto number = [](double v) {
    char buffer[32];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
  };
  const auto point = [&](const Vec2& p) { return "[" + number(p[0]) + ", " + number(p[1]) + "]"; };
  std::string out;
  for (const kin::AssembledContact& a : mech.assembled)
    out += "touch at rest: " + mech.connections[static_cast<std::size_t>(a.connection)].name + ": " + a.key +
           " solved " + point(a.solved_mm) + " (drawn " + point(a.drawn_mm) + ", moved " + number(a.moved_mm) +
           " mm along the contact normal)\n";
  return out;
}

}  // namespace

DesignFindings validate_design(const DesignSpec& spec, const kin::Mechanism& mech) {
  DesignFindings f;
  f.description = kin::describe(mech);
  f.description += describe_assembled(mech);
  f.description += describe_flexible(spec, mech);  // throws for bad flexible-model data
  f.description += describe_oil(spec);
  f.warnings = kin::check_drawing(mech);
  return f;
}

}  // namespace camopt::jobs
