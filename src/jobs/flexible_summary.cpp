#include "camopt/jobs/flexible_summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "camopt/core/units.hpp"
#include "camopt/jobs/common.hpp"

namespace camopt::jobs {

namespace {

// per HLA over the reported points: the plunger's drift (pump-up > 0, collapse < 0), the
// chamber pressure's range (cavitation at its floor), whether the check valve opened, and the
// oil it leaked and took in
nlohmann::json hla_summary(const dynamics::FlexibleResult& r) {
  nlohmann::json out = nlohmann::json::array();
  const std::size_t nh = r.hla_names.size(), last = r.cam_deg.size() - 1;
  for (std::size_t k = 0; k < nh; ++k) {
    Extremes pressure, force, ball, plunger;
    for (std::size_t i = 0; i <= last; ++i) {
      plunger.add(r.hla_plunger[i * nh + k], r.cam_deg[i]);
      pressure.add(r.hla_pressure[i * nh + k], r.cam_deg[i]);
      force.add(r.hla_force[i * nh + k], r.cam_deg[i]);
      ball.add(r.hla_ball_lift[i * nh + k], r.cam_deg[i]);
    }
    bool cavitates = false, ball_opens = ball.max > 0.0;
    const std::string prefix = "hla " + r.hla_names[k] + " ";
    for (const auto& ev : r.events) {
      if (ev.what.rfind(prefix, 0) != 0) continue;
      cavitates = cavitates || ev.what.ends_with("pressure floor");
      ball_opens = ball_opens || ev.what.ends_with("ball seat");
    }
    out.push_back({{"node", r.hla_names[k]},
                   {"plunger_drift_mm", r.hla_plunger[last * nh + k] - r.hla_plunger[k]},
                   {"min_plunger_mm", plunger.min},
                   {"max_plunger_mm", plunger.max},
                   {"max_force_N", force.max},
                   {"max_force_at_cam_deg", force.max_at},
                   {"max_pressure_MPa", pressure.max},
                   {"min_pressure_MPa", pressure.min},
                   {"min_pressure_at_cam_deg", pressure.min_at},
                   {"cavitates", cavitates},
                   {"ball_opens", ball_opens},
                   {"max_ball_lift_mm", ball.max},
                   {"leak_volume_mm3", r.hla_leak_volume[last * nh + k] - r.hla_leak_volume[k]},
                   {"refill_volume_mm3", r.hla_refill_volume[last * nh + k] - r.hla_refill_volume[k]}});
  }
  return out;
}

}  // namespace

nlohmann::json flexible_run_summary(const kin::Mechanism& mech, const dynamics::Model& model,
                                    const dynamics::FlexibleResult& r) {
  const std::size_t nc = mech.connections.size(), nch = r.chain_names.size();
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";
  nlohmann::json j;
  Extremes kin_lift, dyn_lift, torque, loss;
  double friction = 0.0, bounce_height = 0.0;
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
    kin_lift.add(r.lift_kinematic[i], r.cam_deg[i]);
    dyn_lift.add(r.lift[i], r.cam_deg[i]);
    loss.add(r.lift_kinematic[i] - r.lift[i], r.cam_deg[i]);
    torque.add(r.cam_torque[i] * 1e-3, r.cam_deg[i]);
    for (std::size_t c = 0; c < nc; ++c) friction += r.friction_power[i * nc + c];
    if (std::abs(r.lift_kinematic[i]) <= 1e-12) bounce_height = std::max(bounce_height, std::abs(r.lift[i]));
  }
  j["max_lift_kinematic_" + lift_unit] = kin_lift.max;
  j["max_lift_" + lift_unit] = dyn_lift.max;
  j["max_lift_loss_" + lift_unit] = loss.max;
  j["max_lift_loss_at_cam_deg"] = loss.max_at;
  j["max_cam_torque_Nm"] = torque.max;
  j["min_cam_torque_Nm"] = torque.min;
  j["mean_friction_power_W"] = friction / static_cast<double>(r.cam_deg.size());
  bool separates = false;
  for (std::size_t c = 0; c < nc; ++c) {
    Extremes f;
    for (std::size_t i = 0; i < r.cam_deg.size(); ++i) f.add(r.force[i * nc + c], r.cam_deg[i]);
    nlohmann::json cj = {{"max_force_N", f.max}, {"max_force_at_cam_deg", f.max_at}, {"min_force_N", f.min},
                         {"min_force_at_cam_deg", f.min_at}, {"damping_N_s_per_mm", r.contact_damping[c]}};
    // separation intervals: opens .. next closes of this connection; one open across the
    // revolution's end wraps ([opens, closes + 360]); one open at both ends of the output
    // window without an event of its own is cut at the window
    nlohmann::json intervals = nlohmann::json::array();
    const bool lash = model.contacts[c].held_node > 0;
    double opened = std::numeric_limits<double>::quiet_NaN(), first_close = std::numeric_limits<double>::quiet_NaN();
    bool first = true;
    for (const auto& ev : r.events) {
      if (ev.what != mech.connections[c].name) continue;
      if (first && !ev.opens) first_close = ev.cam_deg;
      first = false;
      if (ev.opens) opened = ev.cam_deg;
      else if (!std::isnan(opened)) intervals.push_back({opened, ev.cam_deg}), opened = std::numeric_limits<double>::quiet_NaN();
    }
    if (!std::isnan(opened) && !r.cam_deg.empty())
      intervals.push_back({opened, std::isnan(first_close) ? r.cam_deg.back() : first_close + 360.0});
    else if (!std::isnan(first_close) && !r.cam_deg.empty())
      intervals.insert(intervals.begin(), nlohmann::json{r.cam_deg.front(), first_close});
    cj["open_intervals_cam_deg"] = intervals;
    if (!lash && !intervals.empty()) separates = true;
    if (lash && intervals.size() > 1) separates = true;
    j["connections"][mech.connections[c].name] = cj;
  }
  j["any_contact_separates"] = separates;
  // per seat: the first closing is the seating, every further one a bounce; the bounce height
  // is the largest lift while the kinematic valve is seated
  const std::size_t nseat = r.seat_names.size();
  for (std::size_t k = 0; k < nseat; ++k) {
    int closes = 0;
    double seating = 0.0, max_force = 0.0;
    for (const auto& ev : r.events)
      if (ev.what == r.seat_names[k] + " seat" && !ev.opens) {
        if (closes == 0) seating = ev.speed_m_per_s;
        ++closes;
      }
    for (std::size_t i = 0; i < r.cam_deg.size(); ++i) max_force = std::max(max_force, r.seat_forces[i * nseat + k]);
    nlohmann::json sj = {{"seating_velocity_m_per_s", closes > 0 ? nlohmann::json(seating) : nlohmann::json(nullptr)},
                         {"bounce_count", std::max(0, closes - 1)},
                         {"max_force_N", max_force},
                         {"max_mean_pressure_MPa", max_force / r.seat_area[k]}};
    if (k == 0) {
      j["seating_velocity_m_per_s"] = sj["seating_velocity_m_per_s"];
      j["bounce_count"] = sj["bounce_count"];
      j["bounce_height_" + lift_unit] = bounce_height;
    }
    j["seats"][r.seat_names[k]] = sj;
  }
  j["lash_kinks_cam_deg"] = r.kink_deg;
  j["gap_linearisation_error_mm"] = r.gap_error_mm;
  if (!r.gap_error_contact.empty())
    j["gap_linearisation_error_at"] = {{"contact", r.gap_error_contact}, {"cam_deg", r.gap_error_at_cam_deg}};
  for (std::size_t s = 0; s < nch; ++s) {
    double surge = 0.0, coil = 0.0;
    for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
      surge = std::max(surge, std::abs(r.coil_force_base[i * nch + s] - r.spring_static_load[i * nch + s]));
      coil = std::max(coil, r.coil_force_top[i * nch + s]);
    }
    int clashes = 0;
    for (const auto& ev : r.events)
      if (ev.what.rfind(r.chain_names[s] + " coil", 0) == 0 && !ev.opens) ++clashes;
    j["springs"][r.chain_names[s]] = {{"segments", r.chain_segments[s]},
                                           {"max_retainer_force_N", coil},
                                           {"surge_amplitude_N", surge},
                                           {"coil_clash_events", clashes}};
  }
  for (std::size_t e = 0; e < r.element_names.size(); ++e) {
    double worst = 0.0;
    const std::size_t ne = r.element_names.size();
    for (std::size_t i = 0; i < r.cam_deg.size(); ++i) worst = std::max(worst, std::abs(r.deformation[i * ne + e]));
    const bool angle = mech.nodes[mech.node_index(r.element_names[e])].kind != NodeKind::translational;
    j["deformation"][r.element_names[e]] = {{std::string("max_") + (angle ? "deg" : "mm"), angle ? worst * 180.0 / pi : worst}};
  }
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : r.events)
    events.push_back({{"what", e.what}, {"cam_deg", e.cam_deg}, {"event", e.opens ? "opens" : "closes"},
                      {"speed_m_per_s", e.speed_m_per_s}});
  j["events"] = events;
  j["integrator_steps"] = r.steps;
  j["rhs_evaluations"] = r.rhs_evaluations;
  j["revolutions_integrated"] = r.revolutions_integrated;
  j["periodic_steady_state"] = r.periodic;
  if (r.periodic_difference >= 0) j["periodic_difference"] = r.periodic_difference;
  j["train_frequency_Hz"] = r.train_frequency_hz;
  double min_lift = 0.0, min_at = 0.0;
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i)
    if (r.lift[i] < min_lift) min_lift = r.lift[i], min_at = r.cam_deg[i];
  j["min_lift_" + lift_unit] = min_lift;
  j["min_lift_at_cam_deg"] = min_at;
  if (!r.hla_names.empty()) j["hla"] = hla_summary(r);
  return j;
}

}  // namespace camopt::jobs
