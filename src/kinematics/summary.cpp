// the per-position summary of a sweep: extremes, durations and area of the lift refined
// between the grid points, lash openings, and the contacts' extremes refined by solves
// between the grid points (contact_extremes.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/grid_refine.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "contact_extremes.hpp"

namespace camopt::kin {

namespace {
constexpr double inf = std::numeric_limits<double>::infinity();
using detail::ContactProbe;
using detail::ContactQuantity;
using detail::refined_max;

// one quantity over the grid with its derivatives, and where lash gaps open or close
struct Series {
  const std::vector<double>& x;             // driver [deg or mm]
  std::vector<GridJet> f;                   // per point, per driver unit
  const std::vector<std::uint64_t>& lash;   // per point (PositionResult::lash_open)
  int order = 0;                            // derivatives known (0: linear between points)

  std::size_t intervals() const { return x.size() - 1; }
  // no lash gap opens or closes between points i and i + 1: the motion is smooth there
  bool smooth(std::size_t i) const { return lash[i] == lash[i + 1]; }
  HermiteInterval interval(std::size_t i) const { return HermiteInterval::fit(x[i], x[i + 1], f[i], f[i + 1], order); }
};

// a variable's series per driver unit, less `offset` from its value
Series variable_series(const SweepResult& r, std::size_t position, int v, double offset) {
  const PositionResult& p = r.positions[position];
  Series s{r.driver, {}, p.lash_open, std::min(r.derivative_order, 3)};
  s.f.resize(r.driver.size());
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    for (int k = 0; k <= 3; ++k) s.f[i][k] = k <= s.order ? p.value(i, v, k) : 0.0;
    s.f[i][0] -= offset;
  }
  return s;
}

struct Range {
  Extreme max{-inf, 0}, min{inf, 0};
  void add(double v, double at) {
    if (v > max.value) max = {v, at};
    if (v < min.value) min = {v, at};
  }
};

// extremes of the k-th derivative: the grid values, and the interpolant's stationary points
// on every smooth interval when the series has derivative k + 1 or its interpolant is of
// higher degree than k
Range extremes(const Series& s, int k) {
  Range e;
  for (std::size_t i = 0; i < s.x.size(); ++i) e.add(s.f[i][k], s.x[i]);
  if (s.order == 0 || k > s.order) return e;
  std::vector<double> at;
  for (std::size_t i = 0; i < s.intervals(); ++i) {
    if (!s.smooth(i)) continue;
    const HermiteInterval p = s.interval(i);
    p.stationary(k, at);
    for (double x : at) e.add(p.derivative(k, x), x);
  }
  return e;
}

// on interval i, where a lash gap opens or closes: the span from the end `from_left` to the
// first crossing of `level` by the interpolant of the smooth interval beyond that end,
// extrapolated (error ~ 2^(n+1) h^(2n+2) f^(2n+2) / (2n+2)!: two steps out on one side, one
// on the other)
std::optional<double> span_to_crossing(const Series& s, std::size_t i, bool from_left, double level) {
  if (s.order == 0) return std::nullopt;
  const bool have = from_left ? i >= 1 && s.smooth(i - 1) : i + 2 < s.x.size() && s.smooth(i + 1);
  if (!have) return std::nullopt;
  const HermiteInterval p = s.interval(from_left ? i - 1 : i + 1);
  std::vector<double> roots;
  p.solve(0, level, s.x[i], s.x[i + 1], roots);
  if (roots.empty()) return std::nullopt;
  return from_left ? roots.front() - s.x[i] : s.x[i + 1] - roots.back();
}

// the span of interval i where the value is above `level`
double span_above(const Series& s, std::size_t i, double level) {
  const double a = s.f[i][0] - level, b = s.f[i + 1][0] - level, dx = s.x[i + 1] - s.x[i];
  const bool above_a = a > 0, above_b = b > 0;
  if (s.order > 0 && s.smooth(i)) {
    // the interpolant's crossings split the interval; each piece is above or below
    const HermiteInterval p = s.interval(i);
    std::vector<double> cut;
    p.solve(0, level, s.x[i], s.x[i + 1], cut);
    cut.insert(cut.begin(), s.x[i]);
    cut.push_back(s.x[i + 1]);
    double span = 0.0;
    for (std::size_t j = 0; j + 1 < cut.size(); ++j)
      if (p.derivative(0, 0.5 * (cut[j] + cut[j + 1])) > level) span += cut[j + 1] - cut[j];
    return span;
  }
  if (above_a == above_b) return above_a ? dx : 0.0;
  // a lash gap opens or closes here: the side above the level is the moving one
  if (const auto span = span_to_crossing(s, i, above_a, level)) return *span;
  return dx * (above_a ? a : b) / std::abs(a - b);  // linear
}

double duration_above(const Series& s, double level) {
  double total = 0.0;
  for (std::size_t i = 0; i < s.intervals(); ++i) total += span_above(s, i, level);
  return total;
}

// the integral of the interpolant; the trapezoid where a lash gap opens or closes
double area(const Series& s) {
  double total = 0.0;
  for (std::size_t i = 0; i < s.intervals(); ++i)
    total += s.order > 0 && s.smooth(i) ? s.interval(i).integral()
                                        : 0.5 * (s.f[i][0] + s.f[i + 1][0]) * (s.x[i + 1] - s.x[i]);
  return total;
}

// the lift's extremes and those of its derivatives (each up to the series' order)
void lift_extremes(const Series& lift, PositionSummary& s) {
  const Range l = extremes(lift, 0);
  s.max_lift = l.max.value, s.max_lift_at = l.max.at;
  if (lift.order >= 1) {
    const Range v = extremes(lift, 1);
    s.max_velocity = v.max.value, s.max_velocity_at = v.max.at;
    s.min_velocity = v.min.value, s.min_velocity_at = v.min.at;
  }
  if (lift.order >= 2) {
    const Range a = extremes(lift, 2);
    s.max_acceleration = a.max.value, s.max_acceleration_at = a.max.at;
    s.min_acceleration = a.min.value, s.min_acceleration_at = a.min.at;
  }
  if (lift.order >= 3) {
    const Range j = extremes(lift, 3);
    const bool upper = j.max.value >= -j.min.value;
    s.max_jerk_abs = upper ? j.max.value : -j.min.value;
    s.max_jerk_abs_at = upper ? j.max.at : j.min.at;
  }
}

// the open spans of one lash step: the follower node is held at rest while open, so a gap
// opens or closes where the node's motion on the closed side reaches its rest position
Separation separation(const Mechanism& m, const SweepResult& r, std::size_t position, int step) {
  const SolveStep& st = m.plan[step];
  const Node& node = m.nodes[st.output_node];
  const int v = node.first_variable;
  const double rest = m.variables[v].is_angle ? node.rest / rad_per_deg : node.rest;
  Series s = variable_series(r, position, v, rest);
  const std::uint64_t bit = std::uint64_t{1} << std::min(step, 63);
  auto open = [&](std::size_t i) { return (s.lash[i] & bit) != 0; };
  Separation out;
  out.contact = m.connections[st.connections[0]].name;
  double from = s.x[0];
  for (std::size_t i = 0; i < s.intervals(); ++i) {
    const double dx = s.x[i + 1] - s.x[i];
    if (open(i) == open(i + 1)) {
      if (open(i)) out.open_span += dx;
      continue;
    }
    // the closed side's motion, signed to be positive there, reaches rest at the crossing
    const bool closed_left = !open(i);
    const std::size_t c = closed_left ? i : i + 1;
    const double sign = s.f[c][0] < 0 ? -1.0 : 1.0;
    Series signed_series = s;
    for (auto& jet : signed_series.f)
      for (double& d : jet) d *= sign;
    const double closed = span_to_crossing(signed_series, i, closed_left, 0.0).value_or(0.5 * dx);
    out.open_span += dx - closed;
    if (closed_left) from = s.x[i] + closed;
    else out.intervals.emplace_back(from, s.x[i + 1] - closed);
  }
  if (open(s.x.size() - 1)) out.intervals.emplace_back(from, s.x.back());
  return out;
}

// the [[profile]] a contact surface is made from (discs too), or "" (a circle, roller or face)
const std::string& source_profile(const Mechanism& m, std::size_t connection, int side) {
  static const std::string none;
  const Connection& c = m.connections[connection];
  const int profile = (side == 0 ? c.surface_a : c.surface_b).source_profile;
  return profile >= 0 ? m.profiles[static_cast<std::size_t>(profile)].name() : none;
}

// the radii of curvature each curved contact surface meets while its contact is closed,
// refined: the largest curvature (smallest convex radius) and the most negative one
// (sharpest concave radius); the cam surfaces are those made from a [[profile]]
void contact_radii(ContactProbe& probe, PositionSummary& s) {
  const Mechanism& m = probe.mech;
  const std::size_t nc = m.connections.size();
  for (std::size_t c = 0; c < nc; ++c) {
    const Connection& conn = m.connections[c];
    if (conn.kind != ConnectionKind::contact) continue;
    for (int side = 0; side < 2; ++side) {
      const Surface& sf = side == 0 ? conn.surface_a : conn.surface_b;
      if (sf.kind == SurfaceKind::line) continue;
      SurfaceRadii out;
      out.contact = conn.name;
      out.body = m.nodes[sf.node].name;
      const std::string& profile = source_profile(m, c, side);
      const bool cam = !profile.empty();
      out.surface = cam ? profile : sf.roller ? "roller" : "circle";
      // the curvature [1/mm] signed to be largest where sharpest: flat points have no radius
      auto curvature = [side](double sign) -> ContactQuantity {
        return [side, sign](const ContactState& cs) {
          const double k = side == 0 ? cs.curvature_a : cs.curvature_b;
          return cs.open ? -inf : sign * k;
        };
      };
      if (const auto convex = refined_max(probe, {c}, curvature(1.0), 0.0); convex && convex->extreme.value > 0)
        out.min_convex = {1.0 / convex->extreme.value, convex->extreme.at}, out.convex = true;
      if (const auto concave = refined_max(probe, {c}, curvature(-1.0), 0.0); concave && concave->extreme.value > 0)
        out.sharpest_concave = {-1.0 / concave->extreme.value, concave->extreme.at}, out.concave = true;
      if (cam && out.convex && (!s.have_convex_cam || out.min_convex.value < s.min_convex_cam_radius_mm)) {
        s.have_convex_cam = true;
        s.min_convex_cam_radius_mm = out.min_convex.value;
        s.min_convex_cam_radius_at = out.min_convex.at;
        s.min_convex_cam_radius_contact = conn.name;
      }
      (cam ? s.cam_surfaces : s.follower_surfaces).push_back(std::move(out));
    }
  }
}

// the largest pressure angle (closed contacts), roller speed and sliding over every contact,
// refined
void contact_extremes(ContactProbe& probe, PositionSummary& s) {
  const Mechanism& m = probe.mech;
  std::vector<std::size_t> contacts;
  for (std::size_t c = 0; c < m.connections.size(); ++c)
    if (m.connections[c].kind == ConnectionKind::contact) contacts.push_back(c);
  const double unit = m.driver_is_angle() ? rad_per_deg : 1.0;
  const auto pressure = refined_max(probe, contacts, [](const ContactState& cs) {
    return cs.open ? -inf : cs.pressure_angle;
  });
  if (pressure && pressure->extreme.value > 0) {
    s.max_pressure_angle_deg = pressure->extreme.value / rad_per_deg;
    s.max_pressure_angle_at = pressure->extreme.at;
    s.max_pressure_angle_contact = m.connections[pressure->contact].name;
  }
  const auto roller = refined_max(probe, contacts, [](const ContactState& cs) { return std::abs(cs.roller_speed); });
  if (roller) s.max_roller_speed = roller->extreme.value * unit, s.max_roller_speed_at = roller->extreme.at;
  const auto sliding = refined_max(probe, contacts, [](const ContactState& cs) { return std::abs(cs.sliding); });
  if (sliding) s.max_sliding = sliding->extreme.value * unit, s.max_sliding_at = sliding->extreme.at;
}
}  // namespace

double PositionSummary::duration_at(double height) const {
  for (const Duration& d : durations)
    if (d.height == height) return d.span;
  CAMOPT_ASSERT_MSG(false, "duration_at: the height is not one of SummaryOptions::duration_heights");
  return 0.0;
}

PositionSummary summarize(const Mechanism& m, const SweepResult& r, std::size_t position,
                          const SummaryOptions& options) {
  const PositionResult& p = r.positions[position];
  PositionSummary s;
  // the output node's lift, measured from its rest position, with its derivatives
  const Node& out = m.nodes[m.output_node];
  const int v = out.first_variable;
  const Series lift = variable_series(r, position, v, m.variables[v].is_angle ? out.rest / rad_per_deg : out.rest);
  s.refined = lift.order > 0;
  // extremes, durations and area of the lift
  lift_extremes(lift, s);
  for (double h : options.duration_heights) s.durations.push_back({h, duration_above(lift, h)});
  s.lift_area = area(lift);
  // the worst conditioned solve (grid value)
  for (std::size_t i = 0; i < r.driver.size(); ++i)
    if (p.condition[i] > s.max_condition) s.max_condition = p.condition[i], s.max_condition_at = r.driver[i];
  // the closest approach to a singular configuration (on the way to each point)
  for (std::size_t i = 0; i < r.driver.size(); ++i)
    if (p.toggle_margin[i] < s.min_toggle_margin)
      s.min_toggle_margin = p.toggle_margin[i], s.min_toggle_margin_at = p.toggle_margin_at[i];
  s.near_toggle = s.min_toggle_margin < near_singular_margin;
  // lash gaps that open
  for (std::size_t step = 0; step < m.plan.size(); ++step) {
    if (!m.plan[step].one_sided) continue;
    Separation sep = separation(m, r, position, static_cast<int>(step));
    if (sep.open_span > 0) s.separations.push_back(std::move(sep));
  }
  // contact quantities
  if (!p.contacts.empty()) {
    s.have_contacts = true;
    ContactProbe probe(m, r, position);
    const bool solved = p.status.ok();  // a failed position's later points are zeros
    if (solved) {
      contact_extremes(probe, s);
      contact_radii(probe, s);
    }
    s.contacts_refined = solved && !probe.failed();
  }
  return s;
}

}  // namespace camopt::kin
