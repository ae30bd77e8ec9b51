#include "camopt/jobs/kinematics_summary.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"

namespace camopt::jobs {

namespace {

constexpr double kMmPerInch = 25.4;

// shortest round-trip text of a number
std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// one item of --duration-at: a number and an optional unit
DurationHeight parse_height(const std::string& text, const std::string& item, bool output_is_angle) {
  const std::string where = "--duration-at: '" + item + "' in '" + text + "'";
  double v = 0.0;
  const char* end = item.data() + item.size();
  const auto r = std::from_chars(item.data(), end, v);
  if (item.empty() || r.ec != std::errc() || r.ptr == item.data())
    throw InputError(where + " is not a number with an optional unit (e.g. 1, 1mm, 0.040in)");
  const std::string unit(r.ptr, end);
  if (!std::isfinite(v)) throw InputError(where + " is not a finite number");
  if (!(v > 0)) throw InputError(where + " must be a positive height");
  const std::string base = output_is_angle ? "deg" : "mm";
  if (unit.empty() || unit == base) return {v, shortest(v) + base};
  if (!output_is_angle && unit == "in") return {v * kMmPerInch, shortest(v) + "in"};
  throw InputError(where + ": unknown unit '" + unit + "' (allowed: " +
                   (output_is_angle ? std::string("deg, the output node rotates") : std::string("mm, in")) + ")");
}

// a radius and where it is met, under a key prefix
void radius_keys(nlohmann::json& j, const std::string& prefix, const kin::Extreme& e, const std::string& driver) {
  j[prefix + "_mm"] = e.value;
  j[prefix + "_at_" + driver] = e.at;
}

nlohmann::json surfaces_json(const std::vector<kin::SurfaceRadii>& surfaces, const std::string& driver) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& sf : surfaces) {
    nlohmann::json j{{"contact", sf.contact}, {"body", sf.body}, {"surface", sf.surface}};
    if (sf.convex) radius_keys(j, "min_convex_radius", sf.min_convex, driver);
    if (sf.concave) radius_keys(j, "sharpest_concave_radius", sf.sharpest_concave, driver);
    list.push_back(j);
  }
  return list;
}

nlohmann::json separations_json(const std::vector<kin::Separation>& separations, const std::string& driver) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& s : separations) {
    nlohmann::json intervals = nlohmann::json::array();
    for (const auto& [from, to] : s.intervals) intervals.push_back({from, to});
    list.push_back({{"contact", s.contact}, {"open_span_" + driver, s.open_span}, {"open_intervals_" + driver, intervals}});
  }
  return list;
}

// the contact keys: pressure angle, radii of curvature, roller speed and sliding (refined
// between the grid points unless a trial solve failed)
void contact_keys(nlohmann::json& j, const kin::PositionSummary& s, const SummaryUnits& u,
                  std::vector<std::string>& grid) {
  const std::string& d = u.driver;
  auto put = [&](const std::string& key, auto value) {
    j[key] = value;
    if (!s.contacts_refined) grid.push_back(key);
  };
  put("max_pressure_angle_deg", s.max_pressure_angle_deg);
  put("max_pressure_angle_at_" + d, s.max_pressure_angle_at);
  j["max_pressure_angle_contact"] = s.max_pressure_angle_contact;
  if (s.have_convex_cam) {
    put("min_convex_cam_radius_mm", s.min_convex_cam_radius_mm);
    put("min_convex_cam_radius_at_" + d, s.min_convex_cam_radius_at);
    j["min_convex_cam_radius_contact"] = s.min_convex_cam_radius_contact;
  }
  j["cam_surfaces"] = surfaces_json(s.cam_surfaces, d);
  j["follower_surfaces"] = surfaces_json(s.follower_surfaces, d);
  if (!s.contacts_refined) {
    grid.push_back("cam_surfaces");
    grid.push_back("follower_surfaces");
  }
  put("max_roller_speed_rad_per_" + d, s.max_roller_speed);
  put("max_sliding_mm_per_" + d, s.max_sliding);
  if (u.cam_deg_per_s > 0) {
    put("max_roller_speed_rpm", s.max_roller_speed * u.cam_deg_per_s * 60.0 / (2 * pi));
    put("max_sliding_m_per_s", s.max_sliding * u.cam_deg_per_s * 1e-3);
  }
}

std::string per(const SummaryUnits& u, int k) {
  return u.lift + "_per_" + u.driver + (k > 1 ? std::to_string(k) : "");
}
}  // namespace

std::vector<DurationHeight> parse_duration_heights(const std::string& text, bool output_is_angle) {
  std::vector<DurationHeight> heights;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    DurationHeight h = parse_height(text, item, output_is_angle);
    for (const auto& other : heights)
      if (other.value == h.value)
        throw InputError("--duration-at: '" + text + "' gives the height " + h.label + " twice");
    heights.push_back(std::move(h));
  }
  if (heights.empty()) throw InputError("--duration-at: empty list (e.g. 1,0.1 or 0.040in)");
  return heights;
}

std::string duration_key(const DurationHeight& h, const std::string& driver_unit) {
  return "duration_at_" + h.label + (driver_unit == "deg" ? "_cam_deg" : "_driver_mm");
}

void check_duration_heights(const std::vector<DurationHeight>& heights, const std::vector<kin::PositionSummary>& summaries,
                            const std::string& lift_unit) {
  double highest = -INFINITY;
  for (const auto& s : summaries) highest = std::max(highest, s.max_lift);
  for (const auto& h : heights)
    if (h.value >= highest)
      throw InputError("--duration-at: height " + h.label + " (" + format_value(h.value, 6) + " " + lift_unit +
                       ") is not below the maximum lift " + format_value(highest, 6) + " " + lift_unit +
                       (summaries.size() > 1 ? " of any control position" : "") +
                       ": the lift never exceeds it (heights are in " + lift_unit + " unless written with a unit)");
}

nlohmann::json position_summary_json(const kin::PositionSummary& s, const std::vector<DurationHeight>& heights,
                                     const SummaryUnits& u) {
  nlohmann::json j;
  std::vector<std::string> grid;  // keys whose values are taken at the grid points
  std::vector<std::string> notes;
  auto put = [&](const std::string& key, double value) {
    j[key] = value;
    if (!s.refined) grid.push_back(key);
  };
  const std::string& d = u.driver;
  put("max_lift_" + u.lift, s.max_lift);
  put("max_lift_at_" + d, s.max_lift_at);
  for (std::size_t k = 0; k < heights.size(); ++k) {
    const std::string key = duration_key(heights[k], d);
    put(key, s.durations[k].span);
    if (heights[k].value >= s.max_lift)
      notes.push_back(key + ": the lift never exceeds " + heights[k].label + " at this position (max lift " +
                      format_value(s.max_lift, 6) + " " + u.lift + ")");
  }
  put("lift_area_" + u.lift + "_" + d, s.lift_area);
  if (u.order >= 1) {
    put("max_vel_" + per(u, 1), s.max_velocity);
    put("max_vel_at_" + d, s.max_velocity_at);
    put("min_vel_" + per(u, 1), s.min_velocity);
    put("min_vel_at_" + d, s.min_velocity_at);
  }
  if (u.order >= 2) {
    put("max_acc_" + per(u, 2), s.max_acceleration);
    put("max_acc_at_" + d, s.max_acceleration_at);
    put("min_acc_" + per(u, 2), s.min_acceleration);
    put("min_acc_at_" + d, s.min_acceleration_at);
  }
  if (u.order >= 3) {
    put("max_abs_jerk_" + per(u, 3), s.max_jerk_abs);
    put("max_abs_jerk_at_" + d, s.max_jerk_abs_at);
  }
  if (s.have_contacts) contact_keys(j, s, u, grid);
  j["separations"] = separations_json(s.separations, d);
  if (!s.refined) grid.push_back("separations");
  j["grid_values"] = grid;
  j["notes"] = notes;
  return j;
}

std::string position_summary_line(const kin::PositionSummary& s, const std::vector<DurationHeight>& heights,
                                  const SummaryUnits& u) {
  const std::string d = u.driver == "deg" ? "cam deg" : "driver mm";
  std::string line = "max lift " + format_value(s.max_lift, 6) + " " + u.lift + " at " + format_value(s.max_lift_at, 6) +
                     " " + d + "; duration";
  for (std::size_t k = 0; k < heights.size(); ++k)
    line += (k ? ", " : " ") + format_value(s.durations[k].span, 6) + " at " + heights[k].label;
  line += " [" + d + "]";
  // the sharpest radius of each kind over the cam surfaces, with its surface
  const kin::SurfaceRadii *convex = nullptr, *concave = nullptr;
  for (const auto& sf : s.cam_surfaces) {
    if (sf.convex && (!convex || sf.min_convex.value < convex->min_convex.value)) convex = &sf;
    if (sf.concave && (!concave || sf.sharpest_concave.value > concave->sharpest_concave.value)) concave = &sf;
  }
  if (convex)
    line += "; min convex cam radius " + format_value(convex->min_convex.value, 5) + " mm (" + convex->contact + ": " +
            convex->surface + ")";
  if (concave)
    line += "; sharpest concave cam radius " + format_value(concave->sharpest_concave.value, 5) + " mm (" +
            concave->contact + ": " + concave->surface + ")";
  return line;
}

}  // namespace camopt::jobs
