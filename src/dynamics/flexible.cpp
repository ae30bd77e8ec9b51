// flexible lumped-parameter dynamics: the options' check, the run's orchestration and the
// model parameters it reports (flexible.hpp; the run in flexible_run.cpp, the modes and the
// linearisation in flexible_modes.cpp, the model in flexible_build.cpp)
#include "camopt/dynamics/flexible.hpp"

#include <charconv>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics {

namespace {

using detail::System;

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// "FlexibleOptions::<name> = <value>" for a rule's message
std::string option(const char* name, double value) {
  return std::string("FlexibleOptions::") + name + " = " + format_value(value);
}

// every law, stiffness and damping of a built system, and whether the design gave it
std::vector<FlexibleParameter> describe(const System& s) {
  std::vector<FlexibleParameter> p;
  auto add = [&](std::string key, double v, std::string unit, bool given) { p.push_back({key, shortest(v), unit, given}); };
  auto name = [&](std::string key, std::string v, bool given) { p.push_back({key, v, "", given}); };
  auto law = [&](const std::string& key, const detail::ForceLaw& l, const ContactLawSpec& ls) {
    name(key + ".law", to_string(l.law), l.law != ContactLaw::hertz);
    if (l.law == ContactLaw::linear) {
      add(key + ".stiffness", l.k, "N/mm", true);
      add(key + ".damping", l.c * 1e3, "N s/m", ls.damping_N_s_per_m.has_value());
      return;
    }
    add(key + ".length", l.length, "mm", true);
    add(key + ".e_star", l.e_star, "N/mm^2", true);
    name(key + ".damping_law", to_string(l.damping_law), ls.damping_law != ContactDampingLaw::hunt_crossley);
    if (l.damping_law == ContactDampingLaw::hunt_crossley) add(key + ".alpha", l.alpha * 1e3, "s/m", ls.restitution || ls.damping_N_s_per_m);
    else add(key + ".damping", l.c * 1e3, "N s/m", ls.damping_N_s_per_m.has_value());
  };
  for (int c = 0; c < s.C; ++c) {
    const ContactData& cd = s.flex.contacts[c];
    const std::string key = "connection." + s.mech.connections[c].name;
    if (cd.is_contact) {
      law(key, s.laws[c], cd.law);
    } else {
      const ConnectionKind kind = s.mech.connections[c].kind;
      const bool angular = kind == ConnectionKind::gear || kind == ConnectionKind::variable_gear;
      const LinkCompliance& link = s.flex.links[c];
      add(key + ".stiffness", s.link_k[c], angular ? "N mm/rad" : "N/mm", link.stiffness.has_value());
      add(key + ".damping", s.link_c[c], angular ? "N mm s/rad" : "N s/mm", link.damping_ratio.has_value());
    }
  }
  for (const detail::Seat& st : s.seats) {
    const SeatData& sd = s.flex.seats[st.source];
    const std::string key = "node." + s.mech.nodes[st.node].name + ".seat";
    add(key + ".diameter", sd.diameter, "mm", sd.given);
    add(key + ".angle", sd.angle_deg, "deg", sd.given);
    add(key + ".width", sd.width, "mm", sd.given);
    if (st.law.law == ContactLaw::hertz) add(key + ".crown_radius", st.radius, "mm", sd.given);
    law(key, st.law, sd.law);
  }
  for (const detail::Element& e : s.elements) {
    const std::string key = "node." + s.mech.nodes[e.node].name;
    const bool angular = s.mech.nodes[e.node].kind == NodeKind::rotational;
    add(key + ".stiffness", e.k, angular ? "N mm/rad" : "N/mm", true);
    add(key + ".damping", e.c, angular ? "N mm s/rad" : "N s/mm", e.damping_given);
    if (!e.damping_given) add(key + ".damping_ratio", e.zeta, "-", e.zeta != s.opt.component_damping_ratio);
  }
  for (const detail::Chain& ch : s.chains) {
    const std::string key = "spring." + ch.name;
    add(key + ".masses", ch.masses, "-", ch.masses > 0);
    add(key + ".damping", ch.spring_damping * 1e3, "N s/m", ch.spring_damping > 0);
    if (ch.masses > 0) add(key + ".coil_damping", ch.coil_damping * 1e3 * (ch.masses + 1), "N s/m per segment", false);
  }
  add("train_frequency", s.train_frequency_hz, "Hz", true);  // derived: the component damping's reference
  return p;
}

// started from rest: every body still, so the deviation's rate cancels the path's
void start_from_rest(System& s, Eigen::VectorXd& v0) {
  s.evaluate(0.0);
  for (int e = 0; e < s.N; ++e) v0(e) = -s.kinematic_rate(e);
}

// what the run reports besides its motion: the layout, the parameters, the names of the
// elements, chains and seats, and the lash kinks of the path within the reported window
void describe_run(const System& s, double start_deg, FlexibleResult& out) {
  const kin::Mechanism& mech = s.mech;
  out.layout = {s.R, s.E, s.N - s.core(), s.P, s.H};
  for (const detail::Plunger& p : s.plungers) out.hla_names.push_back(mech.nodes[p.node].name);
  out.connections = s.C;
  out.parameters = describe(s);
  for (int c = 0; c < s.C; ++c)
    out.contact_damping.push_back(s.flex.contacts[c].is_contact ? s.laws[c].damping_at(s.opt.reference_force)
                                                                : s.link_c[c]);
  out.train_frequency_hz = s.train_frequency_hz;
  for (const detail::Element& e : s.elements) out.element_names.push_back(mech.nodes[e.node].name);
  for (const detail::Chain& ch : s.chains) out.chain_names.push_back(ch.name), out.chain_segments.push_back(ch.masses + 1);
  for (const detail::Seat& st : s.seats) out.seat_names.push_back(mech.nodes[st.node].name), out.seat_area.push_back(st.area);
  for (double k : s.kinks) {
    const double x = k / rad_per_deg - start_deg;
    out.kink_deg.push_back(start_deg + x - 360.0 * std::floor(x / 360.0));
  }
}

}  // namespace

void FlexibleOptions::validate() const {
  CAMOPT_THROW_UNLESS(revolutions >= 1, option("revolutions", revolutions) + " must be >= 1");
  CAMOPT_THROW_UNLESS(relative_tolerance > 0, option("relative_tolerance", relative_tolerance) + " must be > 0");
  CAMOPT_THROW_UNLESS(absolute_tolerance > 0, option("absolute_tolerance", absolute_tolerance) + " must be > 0");
  CAMOPT_THROW_UNLESS(contact_stiffness_scale > 0,
                      option("contact_stiffness_scale", contact_stiffness_scale) + " must be > 0");
  CAMOPT_THROW_UNLESS(contact_restitution > 0 && contact_restitution <= 1,
                      option("contact_restitution", contact_restitution) + " must be in (0, 1]");
  CAMOPT_THROW_UNLESS(restitution_speed_m_per_s > 0,
                      option("restitution_speed_m_per_s", restitution_speed_m_per_s) + " must be > 0");
  CAMOPT_THROW_UNLESS(contact_damping_ratio >= 0, option("contact_damping_ratio", contact_damping_ratio) + " must be >= 0");
  CAMOPT_THROW_UNLESS(component_damping_ratio >= 0,
                      option("component_damping_ratio", component_damping_ratio) + " must be >= 0");
  CAMOPT_THROW_UNLESS(spring_damping_ratio >= 0, option("spring_damping_ratio", spring_damping_ratio) + " must be >= 0");
  CAMOPT_THROW_UNLESS(friction_velocity_m_per_s > 0,
                      option("friction_velocity_m_per_s", friction_velocity_m_per_s) + " must be > 0");
  CAMOPT_THROW_UNLESS(link_stiffness > 0, option("link_stiffness", link_stiffness) + " must be > 0");
  CAMOPT_THROW_UNLESS(coil_clash_stiffness >= 0, option("coil_clash_stiffness", coil_clash_stiffness) + " must be >= 0");
  CAMOPT_THROW_UNLESS(reference_force > 0, option("reference_force", reference_force) + " must be > 0");
  CAMOPT_THROW_UNLESS(table_step_deg > 0 && table_step_deg <= 90,
                      option("table_step_deg", table_step_deg) + " must be in (0, 90]");
  CAMOPT_THROW_UNLESS(max_steps >= 1, option("max_steps", static_cast<double>(max_steps)) + " must be >= 1");
  CAMOPT_THROW_UNLESS(max_gap_error_mm > 0, option("max_gap_error_mm", max_gap_error_mm) + " must be > 0");
  CAMOPT_THROW_UNLESS(periodic_tolerance >= 0, option("periodic_tolerance", periodic_tolerance) + " must be >= 0");
}

Status run_flexible(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                    double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                    const FlexibleOptions& options, FlexibleResult& out) {
  // the arguments and the options
  CAMOPT_THROW_UNLESS(step_deg > 0, "run_flexible: step_deg = " + format_value(step_deg) + " must be > 0");
  CAMOPT_THROW_UNLESS(stop_deg > start_deg, "run_flexible: stop_deg = " + format_value(stop_deg) +
                                                " must be > start_deg = " + format_value(start_deg));
  CAMOPT_THROW_UNLESS(engine_rpm_value > 0,
                      "run_flexible: engine_rpm_value = " + format_value(engine_rpm_value) + " must be > 0");
  options.validate();
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  // the first integrated angle: revolutions - 1 before the reported one (from rest: the reported one)
  const double first_deg = options.start_at_rest ? start_deg : start_deg - 360.0 * (options.revolutions - 1);
  // the model and its static start at the first angle, or rest
  Eigen::VectorXd x0, v0;
  if (const Status st = detail::static_start(s, model, controls, first_deg * rad_per_deg, x0, v0); !st.ok()) return st;
  if (options.start_at_rest) start_from_rest(s, v0);
  // the parameters and names the run reports
  out = FlexibleResult{};
  describe_run(s, start_deg, out);
  // integrate window by window
  return detail::integrate_flexible(s, first_deg, engine_rpm_value, x0, v0, start_deg, stop_deg, step_deg, out);
}

std::vector<FlexibleParameter> flexible_parameters(const kin::Mechanism& mech, const Model& model,
                                                   const std::vector<double>& controls, const FlexibleOptions& options) {
  options.validate();
  System s(mech, options);
  s.omega = 0.0;
  const Status st = detail::build_system(s, model, controls, model.driver_start_deg * rad_per_deg);
  if (!st.ok()) return {};
  return describe(s);
}

}  // namespace camopt::dynamics
