// optimize --verify: the made design checked against the constraint set (optimize_verify.hpp)
#include "optimize_verify.hpp"

#include <cmath>
#include <cstdio>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/jobs/flexible_summary.hpp"

namespace camopt::jobs {

namespace {

// the valve counts as driven above this lift [mm], kinematic and dynamic: a contact that
// opens while the valve already rests on its seat (landed early) is the seat taking the load
constexpr double kDrivenLift = 1e-3;

std::string fmt(double v) { return format_value(v, 6); }

// the rigid model at the set's speed: every contact's separation speed, the designed
// contact's least force, the springs' least margin and the largest cam torque
nlohmann::json check_rigid(const kin::Mechanism& mech, const dynamics::Model& model, const std::vector<double>& controls,
                           const std::string& cam_contact, const opt::OptimizationSpec& set, double omega,
                           const std::string& at, Verdict& verdict) {
  dynamics::RigidSweep rs;
  if (Status st = dynamics::rigid_sweep(mech, model, controls, 0.0, 360.0, set.grid_step_deg, rs); !st.ok()) {
    verdict.failed("rigid", "rigid sweep", st.str());
    return "failed: " + st.str();
  }
  const auto& l = set.limits;
  nlohmann::json out = {{"model", "rigid, kinematically constrained (friction included)"}, {"rpm", set.rpm}};
  const double need = std::max(set.rpm, l.min_separation_speed_rpm.value_or(0.0));
  for (int c = 0; c < rs.connections; ++c) {
    if (!model.contacts[static_cast<std::size_t>(c)].is_contact) continue;
    const std::string& name = mech.connections[static_cast<std::size_t>(c)].name;
    const dynamics::Separation sep = dynamics::separation_speed(rs, model, c);
    const double rpm = std::isfinite(sep.engine_rpm) ? sep.engine_rpm : 1e6;
    out["separation_speed_rpm"][name] = rpm;
    verdict.bound("rigid", "separation speed of " + name, "rpm", rpm, need, false, at + "cam " + fmt(sep.cam_deg) + " deg");
  }
  int conn = -1;
  for (int c = 0; c < rs.connections; ++c)
    if (mech.connections[static_cast<std::size_t>(c)].name == cam_contact) conn = c;
  Extremes force, torque;
  double margin = 1e300, margin_at = 0;
  for (std::size_t i = 0; i < rs.points(); ++i) {
    force.add(rs.force_at(i, conn, omega), rs.cam_deg[i]);
    torque.add(std::abs(rs.torque_at(i, omega)) * 1e-3, rs.cam_deg[i]);
    for (int s = 0; s < rs.springs; ++s) {
      const double load = rs.spring_load[i * static_cast<std::size_t>(rs.springs) + static_cast<std::size_t>(s)];
      if (!(load > 0)) continue;
      const double m = dynamics::spring_margin(rs, model, i, s, omega) / load;
      if (m < margin) margin = m, margin_at = rs.cam_deg[i];
    }
  }
  out["contact"] = cam_contact;
  out["min_contact_force_N"] = force.min;
  out["min_contact_force_at_cam_deg"] = force.min_at;
  out["max_contact_force_N"] = force.max;
  out["max_cam_torque_Nm"] = torque.max;
  if (margin < 1e300) out["min_spring_margin"] = margin;
  if (l.min_contact_force_N)
    verdict.bound("rigid", "contact force of " + cam_contact, "N", force.min, *l.min_contact_force_N, false,
                  at + "cam " + fmt(force.min_at) + " deg");
  if (l.min_spring_margin && margin < 1e300)
    verdict.bound("rigid", "spring margin", "-", margin, *l.min_spring_margin, false, at + "cam " + fmt(margin_at) + " deg");
  if (l.max_cam_torque_Nm)
    verdict.bound("rigid", "cam torque", "N m", torque.max, *l.max_cam_torque_Nm, true, at + "cam " + fmt(torque.max_at) + " deg");
  return out;
}

// the flexible model at the set's speed: no contact opens while the valve is driven, no
// seat bounce, no coil clash, the seating velocity and the lift loss within their limits
nlohmann::json check_flexible(const kin::Mechanism& mech, const dynamics::Model& model, const std::vector<double>& controls,
                              const opt::OptimizationSpec& set, const std::string& at, Verdict& verdict) {
  verdict.note("optimize --verify: " + at + "flexible model at " + fmt(set.rpm) + " rpm ...");
  dynamics::FlexibleResult fr;
  if (Status st = dynamics::run_flexible(mech, model, controls, set.rpm, 0.0, 360.0, 0.5, dynamics::FlexibleOptions{}, fr);
      !st.ok()) {
    verdict.failed("flexible", "flexible run", st.str());
    return "failed: " + st.str();
  }
  nlohmann::json flex = jobs::flexible_run_summary(mech, model, fr);
  flex["model"] = "flexible";
  flex["rpm"] = set.rpm;
  flex.erase("events");
  // open intervals of each contact that cover an output point where the valve is driven
  for (auto& [name, c] : flex["connections"].items()) {
    if (!c.contains("open_intervals_cam_deg")) continue;
    int count = 0;
    std::string first;
    for (const auto& iv : c["open_intervals_cam_deg"]) {
      const double a = iv[0].get<double>(), b = iv[1].get<double>();
      for (std::size_t i = 0; i < fr.cam_deg.size(); ++i)
        if (fr.cam_deg[i] >= a && fr.cam_deg[i] <= b && fr.lift_kinematic[i] > kDrivenLift && fr.lift[i] > kDrivenLift) {
          if (first.empty()) first = fmt(a) + ".." + fmt(b) + " deg";
          ++count;
          break;
        }
    }
    c["separations_while_driven"] = count;
    verdict.none("flexible", "separations of " + name + " while the valve is driven", count,
                 at + (first.empty() ? "" : "first cam " + first));
  }
  if (flex.contains("bounce_count") && flex["bounce_count"].get<int>() > 0)
    verdict.bound("flexible", "valve seat bounce height (" + std::to_string(flex["bounce_count"].get<int>()) + " bounces)",
                  "mm", flex["bounce_height_mm"].get<double>(), set.verify.max_bounce_height_mm, true, at);
  if (flex.contains("springs"))
    for (auto& [name, s] : flex["springs"].items())
      verdict.none("flexible", "coil clashes of " + name, s["coil_clash_events"].get<int>(), at);
  if (set.limits.max_seating_velocity_m_per_s && flex.contains("seating_velocity_m_per_s"))
    verdict.bound("flexible", "seating velocity", "m/s", flex["seating_velocity_m_per_s"].get<double>(),
                  *set.limits.max_seating_velocity_m_per_s, true, at);
  if (set.verify.max_lift_loss_mm && flex.contains("max_lift_loss_mm"))
    verdict.bound("flexible", "lift loss", "mm", flex["max_lift_loss_mm"].get<double>(), *set.verify.max_lift_loss_mm, true,
                  at + "cam " + fmt(flex["max_lift_loss_at_cam_deg"].get<double>()) + " deg");
  return flex;
}

}  // namespace

void Verdict::bound(const std::string& model, const std::string& check, const std::string& unit, double value,
                    double limit, bool upper, const std::string& at) {
  const double slack = tolerance_ * std::abs(limit);
  const bool ok = std::isfinite(value) && (upper ? value <= limit + slack : value >= limit - slack);
  checks_.push_back({model, check, unit, at, "", value, limit, upper, ok, false});
}

void Verdict::none(const std::string& model, const std::string& check, int count, const std::string& at) {
  checks_.push_back({model, check, "", at, "", static_cast<double>(count), 0.0, true, count == 0, true});
}

void Verdict::failed(const std::string& model, const std::string& check, const std::string& why) {
  checks_.push_back({model, check, "", "", why, 0.0, 0.0, true, false, false});
}

bool Verdict::passed() const {
  for (const auto& c : checks_)
    if (!c.passed) return false;
  return true;
}

nlohmann::json Verdict::json() const {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& c : checks_) {
    nlohmann::json j = {{"model", c.model}, {"check", c.check}, {"passed", c.passed}};
    if (!c.note.empty()) {
      j["failure"] = c.note;
    } else if (c.counted) {
      j["count"] = static_cast<int>(c.value);
    } else {
      j["value"] = c.value;
      j["limit"] = c.limit;
      j["limit_is"] = c.upper ? "max" : "min";
      j["unit"] = c.unit;
    }
    if (!c.at.empty()) j["at"] = c.at;
    out.push_back(j);
  }
  return out;
}

std::string Verdict::failure_table() const {
  std::string out = "model     check                                                   value          limit\n";
  for (const auto& c : checks_) {
    if (c.passed) continue;
    char line[512];
    const std::string value = !c.note.empty() ? c.note : c.counted ? std::to_string(static_cast<int>(c.value))
                                                                  : fmt(c.value) + " " + c.unit;
    const std::string limit = !c.note.empty() ? "" : c.counted ? "0" : (c.upper ? "<= " : ">= ") + fmt(c.limit) + " " + c.unit;
    std::snprintf(line, sizeof line, "%-9s %-55s %-14s %s%s\n", c.model.c_str(), c.check.c_str(), value.c_str(),
                  limit.c_str(), c.at.empty() ? "" : ("  (" + c.at + ")").c_str());
    out += line;
  }
  return out;
}

void verify_rotational(const DesignSpec& made, const synthesis::SynthesisResult& made_cam, const PeriodicSpline& lift,
                       const std::vector<double>& controls, const opt::CamProblem& problem, nlohmann::json& report,
                       Verdict& verdict) {
  const opt::OptimizationSpec& set = problem.spec();
  const auto& l = set.limits;
  // the kinematic solver on the made cam: its lift against the optimised lift, and the
  // quantities the constraints bound from its own contact outputs
  synthesis::RoundTrip rt;
  if (Status st = synthesis::round_trip(made, lift, controls, made_cam.connection, rt); !st.ok()) throw NumericalError(st);
  const kin::Mechanism mech = kin::compile(made);
  kin::SweepSpec sw;
  sw.start = 0;
  sw.stop = 360;
  sw.step = 0.5;
  sw.control_positions = {controls};
  sw.request = {3, true};
  const kin::SweepResult sr = kin::sweep(mech, sw);
  if (!sr.positions[0].status.ok()) throw NumericalError(sr.positions[0].status);
  const kin::PositionSummary s = kin::summarize(mech, sr, 0);
  const double rpm_scale = problem.cam_speed_rad_per_s() * 60.0 / (2 * pi);  // [rev/min per rad/rad]
  const double roller_rpm = s.max_roller_speed * 180.0 / pi * rpm_scale;
  report["verify"]["kinematics"] = {{"lift_error_max_mm", rt.max_error_mm},
                                    {"lift_error_max_at_cam_deg", rt.max_error_at_deg},
                                    {"max_lift_mm", s.max_lift},
                                    {"max_acceleration_mm_per_deg2", s.max_acceleration},
                                    {"min_acceleration_mm_per_deg2", s.min_acceleration},
                                    {"max_pressure_angle_deg", s.max_pressure_angle_deg},
                                    {"min_convex_cam_radius_mm", s.min_convex_cam_radius_mm},
                                    {"max_roller_speed_rpm", roller_rpm},
                                    {"duration_at_1mm_deg", s.duration_at(1.0)}};
  verdict.bound("kinematic", "lift of the made cam against the optimised lift", "mm", rt.max_error_mm,
                set.verify.max_lift_error_mm, true, "cam " + fmt(rt.max_error_at_deg) + " deg");
  if (l.acc_max_mm_per_deg2)
    verdict.bound("kinematic", "acceleration", "mm/deg^2", s.max_acceleration, *l.acc_max_mm_per_deg2, true,
                  "cam " + fmt(s.max_acceleration_at) + " deg");
  if (l.acc_min_mm_per_deg2)
    verdict.bound("kinematic", "deceleration", "mm/deg^2", s.min_acceleration, *l.acc_min_mm_per_deg2, false,
                  "cam " + fmt(s.min_acceleration_at) + " deg");
  if (l.max_pressure_angle_deg)
    verdict.bound("kinematic", "pressure angle", "deg", s.max_pressure_angle_deg, *l.max_pressure_angle_deg, true,
                  "cam " + fmt(s.max_pressure_angle_at) + " deg");
  if (l.max_roller_speed_rpm) verdict.bound("kinematic", "roller speed", "rpm", roller_rpm, *l.max_roller_speed_rpm, true);
  verdict.note("optimize --verify: kinematic lift matches the optimised lift to " + fmt(rt.max_error_mm) +
       " mm; max pressure angle " + fmt(s.max_pressure_angle_deg) + " deg");

  // rigid and flexible dynamics at the set's speed
  try {
    const dynamics::Model model = dynamics::compile_dynamics(made, mech);
    report["verify"]["rigid_dynamics"] =
        check_rigid(mech, model, controls, made_cam.connection, set, problem.cam_speed_rad_per_s(), "", verdict);
    if (set.verify.flexible) report["verify"]["flexible_dynamics"] = check_flexible(mech, model, controls, set, "", verdict);
  } catch (const InputError& e) {
    report["verify"]["rigid_dynamics"] = std::string("not run: the design lacks dynamics data: ") + e.what();
    verdict.failed("rigid", "dynamics data", e.what());
  }
}

void verify_swing_dynamics(const DesignSpec& made, const opt::CamProblem& problem, nlohmann::json& report,
                           Verdict& verdict) {
  const opt::SwingCamLift& model = *problem.swing();
  const opt::OptimizationSpec& set = problem.spec();
  try {
    const kin::Mechanism mech = kin::compile(made);
    const dynamics::Model dyn = dynamics::compile_dynamics(made, mech);
    nlohmann::json rigid = nlohmann::json::array();
    for (std::size_t k = 0; k < model.positions().size(); ++k) {
      const std::string at = "control " + fmt(model.positions()[k]) + ", ";
      nlohmann::json r = check_rigid(mech, dyn, model.controls(static_cast<int>(k)), model.connection(), set,
                                     problem.cam_speed_rad_per_s(), at, verdict);
      r["control"] = model.positions()[k];
      rigid.push_back(r);
    }
    report["verify"]["rigid_dynamics"] = rigid;
    if (set.verify.flexible) {
      nlohmann::json f = check_flexible(mech, dyn, model.controls(0), set, "control " + fmt(model.positions()[0]) + ", ", verdict);
      if (f.is_object()) f["control"] = model.positions()[0];
      report["verify"]["flexible_dynamics"] = f;
    }
  } catch (const InputError& e) {
    report["verify"]["rigid_dynamics"] = std::string("not run: the design lacks dynamics data: ") + e.what();
    verdict.failed("rigid", "dynamics data", e.what());
  }
}

void record_verdict(const Verdict& verdict, nlohmann::json& report) {
  report["verified"] = verdict.passed();
  report["verification"] = verdict.json();
}

}  // namespace camopt::jobs
