#include "camopt/kinematics/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "camopt/core/units.hpp"

namespace camopt::kin {

namespace {

// bit s: plan step s holds a lash gap open (steps from 63 on share bit 63)
std::uint64_t lash_mask(const Workspace& ws) {
  std::uint64_t mask = 0;
  for (std::size_t s = 0; s < ws.lash_open().size(); ++s)
    if (ws.lash_open()[s]) mask |= std::uint64_t{1} << std::min<std::size_t>(s, 63);
  return mask;
}

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
  out.lash_open.clear();
  out.lash_open.reserve(driver.size());
  out.toggle_margin.clear();
  out.toggle_margin_at.clear();
  out.contacts.clear();
  if (spec.request.contacts) out.contacts.reserve(driver.size() * nc);
  const double unit = m.driver_is_angle() ? rad_per_deg : 1.0;  // driver deg -> rad
  // output k of variable v = (k! c_k) x scale: rad -> deg for angles, x unit^k (per driver deg)
  std::vector<double> scale(nv * 4);
  for (std::size_t v = 0; v < nv; ++v) {
    double f = m.variables[v].is_angle ? 1.0 / rad_per_deg : 1.0;
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
    out.lash_open.push_back(lash_mask(ws));
    out.toggle_margin.push_back(ws.path_margin);
    out.toggle_margin_at.push_back(ws.path_margin_at / unit);
    if (spec.request.contacts) out.contacts.insert(out.contacts.end(), ws.contacts.begin(), ws.contacts.end());
  }
  out.variables = nv;
  out.data.resize(driver.size() * nv * 4, 0.0);
  out.condition.resize(driver.size(), 0.0);
  out.lash_open.resize(driver.size(), 0);
  out.toggle_margin.resize(driver.size(), 1.0);
  out.toggle_margin_at.resize(driver.size(), 0.0);
  if (spec.request.contacts) out.contacts.resize(driver.size() * nc, ContactState{});
  out.stats = ws.stats;
}

}  // namespace

void SweepSpec::validate() const {
  CAMOPT_THROW_UNLESS(std::isfinite(start), "sweep start = " + format_value(start) + " must be finite");
  CAMOPT_THROW_UNLESS(std::isfinite(stop), "sweep stop = " + format_value(stop) + " must be finite");
  CAMOPT_THROW_UNLESS(stop >= start,
                      "sweep stop = " + format_value(stop) + " must be >= start = " + format_value(start));
  CAMOPT_THROW_UNLESS(step > 0 && std::isfinite(step), "sweep step = " + format_value(step) + " must be > 0");
  request.validate();
}

namespace {

// the driver grid [deg or mm]: start, start + step, ..., stop (the last step may be short)
std::vector<double> driver_grid(const SweepSpec& spec) {
  std::vector<double> driver;
  const long n = std::lround((spec.stop - spec.start) / spec.step);
  for (long i = 0; i <= n; ++i) driver.push_back(std::min(spec.stop, spec.start + spec.step * static_cast<double>(i)));
  return driver;
}

// every control position has one value per control of the mechanism
void check_control_positions(const Mechanism& m, const std::vector<std::vector<double>>& positions) {
  for (std::size_t p = 0; p < positions.size(); ++p)
    CAMOPT_THROW_UNLESS(positions[p].size() == m.controls.size(),
                        "sweep control_positions[" + std::to_string(p) + "] has " +
                            std::to_string(positions[p].size()) + " value(s), the mechanism has " +
                            std::to_string(m.controls.size()) + " control(s) (one value per control, in its order)");
}

// the first exception thrown by any worker, kept to be rethrown on the caller's thread
class FirstException {
 public:
  void capture() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!first_) first_ = std::current_exception();
  }
  bool any() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return first_ != nullptr;
  }
  void rethrow() {
    if (first_) std::rethrow_exception(first_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr first_;
};

}  // namespace

SweepResult sweep(const Mechanism& m, const SweepSpec& spec) {
  spec.validate();
  check_control_positions(m, spec.control_positions);
  SweepResult r;
  r.derivative_order = spec.request.derivative_order;
  r.driver = driver_grid(spec);
  auto positions = spec.control_positions;
  if (positions.empty()) positions.push_back(m.default_controls());
  r.positions.resize(positions.size());
  for (std::size_t p = 0; p < positions.size(); ++p) r.positions[p].controls = positions[p];
  std::atomic<std::size_t> next{0};
  FirstException error;
  auto worker = [&] {
    try {
      // every position away from the drawing starts from the same drawing: solved once per
      // thread, when a position first needs it (the continuation from it, and so each
      // result, does not depend on the thread)
      Workspace drawing(m);
      enum { unsolved, solved, failed } drawing_state = unsolved;
      for (std::size_t p = next++; p < positions.size() && !error.any(); p = next++) {
        const bool from_drawing = at_drawing(m, r.positions[p].controls, r.driver.front());
        if (!from_drawing && drawing_state == unsolved)
          drawing_state = solve_drawing(m, drawing).ok() ? solved : failed;
        run_position(m, spec, r.driver, r.positions[p], drawing_state == solved ? &drawing : nullptr);
        if (spec.on_position_done) spec.on_position_done();
      }
    } catch (...) {
      // kept for the caller: an exception leaving a thread's function would terminate
      error.capture();
    }
  };
  const int threads = std::max(1, std::min<int>(spec.threads, static_cast<int>(positions.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  error.rethrow();
  return r;
}

Status periodic_motion(const Mechanism& m, int node, const std::vector<double>& controls, double step_deg,
                       PeriodicSpline& motion) {
  CAMOPT_THROW_UNLESS(m.driver_is_angle(), "periodic_motion: the driver '" + m.nodes[m.driver_node].name +
                                               "' translates; a periodic motion needs a rotating driver");
  CAMOPT_THROW_UNLESS(node > 0 && node < static_cast<int>(m.nodes.size()),
                      "periodic_motion: node = " + std::to_string(node) + " must be a body index in [1, " +
                          std::to_string(m.nodes.size()) + ")");
  CAMOPT_THROW_UNLESS(step_deg > 0 && step_deg < 360.0,
                      "periodic_motion: step_deg = " + format_value(step_deg) + " must be in (0, 360)");
  SweepSpec s;
  s.start = 0.0;
  s.stop = 360.0 - step_deg;
  s.step = step_deg;
  s.request = {0, false};
  if (!controls.empty()) s.control_positions = {controls};
  const SweepResult r = sweep(m, s);
  if (!r.positions[0].status.ok()) return r.positions[0].status;
  const int v = m.nodes[node].first_variable;
  const double unit = m.variables[v].is_angle ? rad_per_deg : 1.0;  // output deg -> internal rad
  std::vector<double> x(r.driver.size()), y(r.driver.size());
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    x[i] = r.driver[i] * rad_per_deg;
    y[i] = r.positions[0].value(i, v, 0) * unit;
  }
  motion = PeriodicSpline::interpolate(x, y, 2 * pi);
  return Status::success();
}

double output_lift(const Mechanism& mech, const PositionResult& result, std::size_t point, int order) {
  CAMOPT_THROW_UNLESS(point < result.data.size() / std::max<std::size_t>(result.variables * 4, 1),
                      "output_lift: point " + std::to_string(point) + " is beyond the sweep");
  CAMOPT_THROW_UNLESS(order >= 0 && order <= 3, "output_lift: order " + std::to_string(order) + " must be 0..3");
  const Node& out = mech.nodes[static_cast<std::size_t>(mech.output_node)];
  const bool angle = mech.variables[static_cast<std::size_t>(out.first_variable)].is_angle;
  const double rest = order > 0 ? 0.0 : angle ? out.rest / rad_per_deg : out.rest;  // as the summary's lift
  return result.value(point, out.first_variable, order) - rest;
}

}  // namespace camopt::kin
