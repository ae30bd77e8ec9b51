#include "camopt/kinematics/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

namespace camopt::kin {

namespace {
constexpr double deg = std::numbers::pi / 180.0;

// drawing: the solved drawing to continue from (nullptr: solve() solves it itself)
void run_position(const Mechanism& m, const SweepSpec& spec, const std::vector<double>& driver, PositionResult& out,
                  const Workspace* drawing) {
  Workspace ws(m);
  ws.set_controls(out.controls);
  const std::size_t nv = m.variables.size(), nc = m.connections.size();
  // rows are appended as they are solved (no zero pass over the whole table first); a
  // failed position is padded with zeros below, so every table has one row per point
  out.data.clear();
  out.data.reserve(driver.size() * nv * 4);
  out.condition.clear();
  out.condition.reserve(driver.size());
  out.contacts.clear();
  if (spec.request.contacts) out.contacts.reserve(driver.size() * nc);
  const double unit = m.driver_is_angle() ? deg : 1.0;  // driver deg -> rad
  // output k of variable v = (k! c_k) x scale: rad -> deg for angles, x unit^k (per driver deg)
  std::vector<double> scale(nv * 4);
  for (std::size_t v = 0; v < nv; ++v) {
    double f = m.variables[v].is_angle ? 1.0 / deg : 1.0;
    for (int k = 0; k <= 3; ++k, f *= unit) scale[v * 4 + k] = f;
  }
  constexpr double factorial[4] = {1.0, 1.0, 2.0, 6.0};
  std::vector<double> row(nv * 4);
  for (std::size_t i = 0; i < driver.size(); ++i) {
    Status st = solve(m, ws, driver[i] * unit, spec.request, drawing);
    if (!st.ok()) {
      out.status = st;
      break;
    }
    for (std::size_t v = 0; v < nv; ++v)
      for (int k = 0; k <= 3; ++k) row[v * 4 + k] = factorial[k] * ws.vars[v].c[k] * scale[v * 4 + k];
    out.data.insert(out.data.end(), row.begin(), row.end());
    out.condition.push_back(ws.max_condition);
    if (spec.request.contacts) out.contacts.insert(out.contacts.end(), ws.contacts.begin(), ws.contacts.end());
  }
  out.data.resize(driver.size() * nv * 4, 0.0);
  out.condition.resize(driver.size(), 0.0);
  if (spec.request.contacts) out.contacts.resize(driver.size() * nc, ContactState{});
  out.stats = ws.stats;
}

// driver span where lift exceeds h, with linear interpolation at the crossings
double duration_above(const std::vector<double>& x, const std::vector<double>& y, double h) {
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double a = y[i] - h, b = y[i + 1] - h, dx = x[i + 1] - x[i];
    if (a >= 0 && b >= 0) total += dx;
    else if (a >= 0 || b >= 0) total += dx * (a >= 0 ? a : b) / std::abs(a - b);
  }
  return total;
}
}  // namespace

SweepResult sweep(const Mechanism& m, const SweepSpec& spec) {
  CAMOPT_ASSERT(spec.step > 0 && spec.stop >= spec.start);
  SweepResult r;
  const long n = std::lround((spec.stop - spec.start) / spec.step);
  for (long i = 0; i <= n; ++i) r.driver.push_back(std::min(spec.stop, spec.start + spec.step * static_cast<double>(i)));
  auto positions = spec.control_positions;
  if (positions.empty()) positions.push_back(m.default_controls());
  r.positions.resize(positions.size());
  for (std::size_t p = 0; p < positions.size(); ++p) r.positions[p].controls = positions[p];
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    // every position away from the drawing starts from the same drawing: solved once per
    // thread, when a position first needs it (the continuation from it, and so each
    // result, does not depend on the thread)
    Workspace drawing(m);
    enum { unsolved, solved, failed } drawing_state = unsolved;
    for (std::size_t p = next++; p < positions.size(); p = next++) {
      const bool from_drawing = at_drawing(m, r.positions[p].controls, r.driver.front());
      if (!from_drawing && drawing_state == unsolved) drawing_state = solve_drawing(m, drawing).ok() ? solved : failed;
      run_position(m, spec, r.driver, r.positions[p], drawing_state == solved ? &drawing : nullptr);
      if (spec.on_position_done) spec.on_position_done();
    }
  };
  const int threads = std::max(1, std::min<int>(spec.threads, static_cast<int>(positions.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  return r;
}

PositionSummary summarize(const Mechanism& m, const SweepResult& r, std::size_t position) {
  const PositionResult& p = r.positions[position];
  PositionSummary s;
  const std::size_t nv = m.variables.size(), nc = m.connections.size(), np = r.driver.size();
  const int out = m.nodes[m.output_node].first_variable;
  std::vector<double> lift(np);
  for (std::size_t i = 0; i < np; ++i) lift[i] = p.at(i, nv, out, 0);
  // lift measured from the output node's rest position
  const double rest = m.variables[out].is_angle ? m.nodes[m.output_node].rest / deg : m.nodes[m.output_node].rest;
  for (auto& l : lift) l -= rest;
  s.max_lift = -1e300;
  s.max_velocity = s.max_acceleration = -1e300;
  s.min_velocity = s.min_acceleration = 1e300;
  for (std::size_t i = 0; i < np; ++i) {
    if (lift[i] > s.max_lift) s.max_lift = lift[i], s.max_lift_at = r.driver[i];
    const double v = p.at(i, nv, out, 1), a = p.at(i, nv, out, 2), j = p.at(i, nv, out, 3);
    s.max_velocity = std::max(s.max_velocity, v);
    s.min_velocity = std::min(s.min_velocity, v);
    if (a > s.max_acceleration) s.max_acceleration = a, s.max_acceleration_at = r.driver[i];
    if (a < s.min_acceleration) s.min_acceleration = a, s.min_acceleration_at = r.driver[i];
    s.max_jerk_abs = std::max(s.max_jerk_abs, std::abs(j));
    if (p.condition[i] > s.max_condition) s.max_condition = p.condition[i], s.max_condition_at = r.driver[i];
  }
  s.duration_at_1mm = duration_above(r.driver, lift, 1.0);
  s.duration_at_0p1mm = duration_above(r.driver, lift, 0.1);
  for (std::size_t i = 0; i + 1 < np; ++i) s.lift_area += 0.5 * (lift[i] + lift[i + 1]) * (r.driver[i + 1] - r.driver[i]);
  if (!p.contacts.empty()) {
    s.have_contacts = true;
    s.min_cam_radius_mm = 1e300;
    const double unit = m.driver_is_angle() ? deg : 1.0;
    for (std::size_t c = 0; c < nc; ++c) {
      const Connection& conn = m.connections[c];
      if (conn.kind != ConnectionKind::contact) continue;
      double open_from = 0.0, open_span = 0.0;
      bool was_open = false;
      for (std::size_t i = 0; i < np; ++i) {
        const ContactState& cs = p.contacts[i * nc + c];
        const double pa = cs.pressure_angle / deg;
        if (!cs.open && pa > s.max_pressure_angle_deg)
          s.max_pressure_angle_deg = pa, s.max_pressure_angle_at = r.driver[i], s.max_pressure_angle_contact = conn.name;
        for (int side = 0; side < 2; ++side) {
          // cam surfaces: profiles and discs (not rollers, not flat faces)
          const Surface& sf = side == 0 ? conn.surface_a : conn.surface_b;
          if (sf.kind == SurfaceKind::line || (sf.kind == SurfaceKind::point && sf.roller)) continue;
          const double k = side == 0 ? cs.curvature_a : cs.curvature_b;
          // smallest |radius| (sign kept: negative = concave); flat points do not count
          if (k == 0.0) continue;
          const double radius = 1.0 / k;
          if (std::abs(radius) < std::abs(s.min_cam_radius_mm))
            s.min_cam_radius_mm = radius, s.min_cam_radius_at = r.driver[i], s.min_cam_radius_contact = conn.name;
        }
        s.max_roller_speed = std::max(s.max_roller_speed, std::abs(cs.roller_speed) * unit);
        s.max_sliding = std::max(s.max_sliding, std::abs(cs.sliding) * unit);
        if (cs.open && !was_open) open_from = r.driver[i];
        if (cs.open) open_span += (i + 1 < np ? r.driver[i + 1] - r.driver[i] : 0.0);
        was_open = cs.open;
      }
      (void)open_from;
      if (open_span > 0 && conn.one_sided)
        s.separations.push_back(conn.name + ": lash open over " + std::to_string(open_span) + " deg of the cycle");
    }
    if (s.min_cam_radius_mm == 1e300) s.min_cam_radius_mm = 0.0;
  }
  return s;
}

Status periodic_motion(const Mechanism& m, int node, const std::vector<double>& controls, double step_deg,
                       PeriodicSpline& motion) {
  CAMOPT_ASSERT(m.driver_is_angle() && node > 0 && step_deg > 0);
  SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0 - step_deg;
  s.step = step_deg;
  s.request = {0, false};
  if (!controls.empty()) s.control_positions = {controls};
  const SweepResult r = sweep(m, s);
  if (!r.positions[0].status.ok()) return r.positions[0].status;
  const int v = m.nodes[node].first_variable;
  const double unit = m.variables[v].is_angle ? deg : 1.0;  // output deg -> internal rad
  std::vector<double> x(r.driver.size()), y(r.driver.size());
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    x[i] = r.driver[i] * deg;
    y[i] = r.positions[0].at(i, m.variables.size(), v, 0) * unit;
  }
  motion = PeriodicSpline::interpolate(x, y, 2 * std::numbers::pi);
  return Status::success();
}

}  // namespace camopt::kin
