// single connections solved in closed form: a link or a circle on a circle (a distance
// between two pins: the law of cosines, or a quadratic on a slide), a circle on a flat face
// with a translating unknown (linear in the travel), gears, racks and variable gears. They
// run on jets, so the taylor coefficients come with the value.
#include <cmath>
#include <type_traits>

#include "kernel.hpp"

namespace camopt::kin::detail {

// |pin_u(q) - pin_k| = L for the one unknown q of node u (rotational: law of cosines in the
// triangle pivot - known pin - unknown pin; translational: a quadratic in the travel)
template <class T>
Status Kernel::distance_closed_form(const SolveStep& step, const T* vars, T& q, double driver,
                                    const Eigen::Vector2d& pin_u, int k, const Eigen::Vector2d& pin_k, double L) {
  using std::acos;
  // the message prefix is built only on failure (no allocation on the hot path)
  const auto what = [&] {
    const Connection& c = m_.connections[step.connections[0]];
    return (c.kind == ConnectionKind::contact ? "contact '" : "link '") + c.name + "'";
  };
  using std::atan2;
  using std::sqrt;
  const int u = step.output_node;
  const Node& node = m_.nodes[u];
  const auto pk = known_pose(k, vars).apply(pin_k.x(), pin_k.y());
  if (node.kind == NodeKind::rotational) {
    const Eigen::Vector2d o = st_.pivots[u];
    const Eigen::Vector2d a0 = pin_u - node.pivot;
    const double rho = a0.norm();
    const V2<T> d{pk.x - o.x(), pk.y - o.y()};
    const T dist2 = dot(d, d);
    const T dist = sqrt(dist2);
    const T cos_beta = (dist2 + rho * rho - L * L) / (2.0 * dist * rho);
    const double cb = value_of(cos_beta);
    if (!(std::abs(cb) <= 1.0))
      return {StatusCode::cannot_assemble,
              what() + " cannot close: pivot of '" + node.name + "' is " + fmt(value_of(dist)) +
                  " mm from the known point, outside the reach [" + fmt(std::abs(rho - L)) + ", " + fmt(rho + L) +
                  "] mm of arm " + fmt(rho) + " mm and distance " + fmt(L) + " mm",
              driver_text(m_, driver)};
    ws_.max_condition = std::max(ws_.max_condition, 1.0 / std::max(1e-300, std::sqrt(1.0 - cb * cb)));
    // the transmission angle mu at the unknown pin: sin mu / dist = sin beta / L (law of sines)
    note_margin(std::min(1.0, value_of(dist) * std::sqrt(1.0 - cb * cb) / L));
    if (std::abs(cb) == 1.0)
      return {StatusCode::singular, what() + " is exactly at toggle (transmission angle 0 or 180 deg)",
              driver_text(m_, driver)};
    const T beta = acos(cos_beta);
    q = atan2(d.y, d.x) + double(step.branch) * beta - atan2_by_atan(a0.y(), a0.x());
  } else {
    // slider: |pin_u + s dir - pk| = L  ->  s^2 + 2 w s + (|e|^2 - L^2) = 0
    const V2<T> e{pin_u.x() - pk.x, pin_u.y() - pk.y};
    const T w = node.direction.x() * e.x + node.direction.y() * e.y;
    const T disc = w * w - (dot(e, e) - L * L);
    if (!(value_of(disc) >= 0.0))
      return {StatusCode::cannot_assemble,
              what() + " cannot close: the line of '" + node.name + "' passes farther than " + fmt(L) +
                  " mm from the known point",
              driver_text(m_, driver)};
    if (value_of(disc) == 0.0)
      return {StatusCode::singular, what() + " is at toggle (perpendicular to the slide)", driver_text(m_, driver)};
    ws_.max_condition = std::max(ws_.max_condition, L / std::sqrt(value_of(disc)));
    note_margin(std::sqrt(value_of(disc)) / L);  // the cosine of the link's angle to the slide
    q = -w + double(step.branch) * sqrt(disc);
  }
  return Status::success();
}

// a circle against a flat face, one of them on the translating unknown: the closure
// (c - q_line) . n - r + lash = 0 is linear in the travel s; the face parameter is the
// foot of the circle centre on the face. gap_at_rest (s = rest) is returned for lash.
template <class T>
Status Kernel::line_closed_form(const SolveStep& step, const T* vars, T& s_out, T& u_out, double& gap_at_rest,
                                double driver) {
  const Connection& c = m_.connections[step.connections[0]];
  const int un = step.output_node;
  const Node& node = m_.nodes[un];
  const bool line_on_a = c.surface_a.kind == SurfaceKind::line;
  const Surface& line = line_on_a ? c.surface_a : c.surface_b;
  const Surface& circle = line_on_a ? c.surface_b : c.surface_a;
  const int line_node = line_on_a ? c.node_a : c.node_b;
  const int circle_node = line_on_a ? c.node_b : c.node_a;
  const double tx0 = -line.normal.y(), ty0 = line.normal.x();
  const Eigen::Vector2d dir = node.direction;
  V2<T> centre, point, n, t;
  T k;  // d(closure)/ds
  if (line_node == un) {
    const auto pose = known_pose(circle_node, vars);
    centre = pose.apply(circle.origin.x(), circle.origin.y());
    point = {T(line.origin.x()), T(line.origin.y())};  // the face at s = 0
    n = {T(line.normal.x()), T(line.normal.y())};
    t = {T(tx0), T(ty0)};
    k = T(-(dir.x() * line.normal.x() + dir.y() * line.normal.y()));
  } else {
    const auto pose = known_pose(line_node, vars);
    point = pose.apply(line.origin.x(), line.origin.y());
    n = pose.rotate(line.normal.x(), line.normal.y());
    t = pose.rotate(tx0, ty0);
    centre = {T(circle.origin.x()), T(circle.origin.y())};  // the circle at s = 0
    k = dir.x() * n.x + dir.y() * n.y;
  }
  const V2<T> d{centre.x - point.x, centre.y - point.y};
  const T closure0 = dot(d, n) - circle.offset + c.lash;  // at s = 0
  const double kv = value_of(k);
  if (!(std::abs(kv) > 1e-12))
    return {StatusCode::singular,
            "contact '" + c.name + "': the face normal is perpendicular to the travel of '" + node.name +
                "' (pressure angle 90 deg)",
            driver_text(m_, driver)};
  ws_.max_condition = std::max(ws_.max_condition, 1.0 / std::abs(kv));
  note_margin(std::abs(kv));  // the cosine of the pressure angle
  // on values as the jets' value (a / b is a * (1 / b) there): both forms agree to the bit
  if constexpr (std::is_same_v<T, double>)
    s_out = -closure0 * (1.0 / k);
  else
    s_out = -closure0 / k;
  gap_at_rest = value_of(closure0) + kv * node.rest;
  // foot of the centre on the face, in the face's own parameter
  const double sign = line_node == un ? -1.0 : 1.0;  // the moving side shifts d by s dir
  const V2<T> ds{d.x + sign * s_out * dir.x(), d.y + sign * s_out * dir.y()};
  u_out = dot(ds, t);
  return Status::success();
}

void Kernel::hold_at_rest(const SolveStep& step, int step_index, double gap) {
  st_.open[step_index] = true;
  ws_.contacts[step.connections[0]].gap = gap;
  set_constant(m_.nodes[step.output_node].first_variable, m_.nodes[step.output_node].rest);
  st_.invalidate_pose(step.output_node);
}

// a link, or a circle on a circle (a link between the centres at the touching distance);
// held: a lash contact whose gap is open with the follower at rest (q not set)
Status Kernel::distance_step(const SolveStep& step, int step_index, double driver, Jet3& q, bool& held) {
  const Connection& c = m_.connections[step.connections[0]];
  const int var = m_.nodes[step.output_node].first_variable;
  held = false;
  const int u = step.output_node, k = u == c.node_a ? c.node_b : c.node_a;
  Eigen::Vector2d pin_u, pin_k;
  double L = c.length;
  if (step.method == StepMethod::contact_distance_closed_form) {
    const Surface& su = u == c.node_a ? c.surface_a : c.surface_b;
    const Surface& sk = u == c.node_a ? c.surface_b : c.surface_a;
    pin_u = su.origin;
    pin_k = sk.origin;
    // centre distance at contact: r_a + r_b (outside) or R - r (inside a concave circle)
    const bool inside = su.offset < 0 || sk.offset < 0;
    const double touching = std::abs(su.offset + sk.offset);
    L = inside ? touching + c.lash : touching - c.lash;
    if (c.one_sided) {
      // the follower at rest: is the physical gap open?
      st_.values[var] = m_.nodes[u].rest;
      const auto pu = node_pose(m_, u, st_.values.data(), st_.pivots.data()).apply(pin_u.x(), pin_u.y());
      const auto pk = node_pose(m_, k, st_.values.data(), st_.pivots.data()).apply(pin_k.x(), pin_k.y());
      const double dist = std::hypot(pu.x - pk.x, pu.y - pk.y);
      const double gap = (inside ? touching - dist : dist - touching) + c.lash;
      if (gap > 0.0) {
        hold_at_rest(step, step_index, gap);
        held = true;
        return Status::success();
      }
      ws_.contacts[step.connections[0]].gap = 0.0;
    }
  } else {
    pin_u = u == c.node_a ? c.pin_a : c.pin_b;
    pin_k = u == c.node_a ? c.pin_b : c.pin_a;
  }
  const double previous = st_.values[var];
  ++ws_.stats.jet_closed_forms;
  Status st = distance_closed_form(step, ws_.vars.data(), q, driver, pin_u, k, pin_k, L);
  if (!st.ok()) return st;
  if (m_.nodes[step.output_node].kind == NodeKind::rotational) {
    // keep the angle continuous with the previous value
    const double turns = std::round((previous - q.value()) / (2 * pi));
    q.c[0] += turns * 2 * pi;
  }
  return Status::success();
}

// a circle on a flat face, the translating unknown linear in its travel; held: a lash
// contact whose gap is open with the follower at rest (q not set)
Status Kernel::line_step(const SolveStep& step, int step_index, double driver, Jet3& q, bool& held) {
  const Connection& c = m_.connections[step.connections[0]];
  held = false;
  const Surface& line = c.surface_a.kind == SurfaceKind::line ? c.surface_a : c.surface_b;
  Jet3 u;
  double gap_at_rest = 0.0, s_value = 0.0, u_value = 0.0;
  if (c.one_sided) {
    // a lash contact is first solved on values: while its gap is open (the follower at
    // rest) the series are not needed
    if (Status st = line_closed_form(step, st_.values.data(), s_value, u_value, gap_at_rest, driver); !st.ok())
      return st;
  }
  if (!c.one_sided || !(gap_at_rest > 0.0)) {
    ++ws_.stats.jet_closed_forms;
    if (Status st = line_closed_form(step, ws_.vars.data(), q, u, gap_at_rest, driver); !st.ok()) return st;
    s_value = q.value();
    u_value = u.value();
  }
  if (c.one_sided && gap_at_rest > 0.0) {
    // open: the follower rests; the face parameter is the foot of the centre at rest
    const double rest = m_.nodes[step.output_node].rest;
    const double shift = rest - s_value;
    const Node& node = m_.nodes[step.output_node];
    const bool line_moves = (c.surface_a.kind == SurfaceKind::line) == (step.output_node == c.node_a);
    const double tx = -line.normal.y(), ty = line.normal.x();
    // the face moving by +shift moves the foot by -shift (dir . t); the circle by +shift
    const double du = (line_moves ? -1.0 : 1.0) * shift * (node.direction.x() * tx + node.direction.y() * ty);
    hold_at_rest(step, step_index, gap_at_rest);
    held = true;
    u = Jet3(u_value + du);
    ws_.vars[line.variable] = u;
    st_.values[line.variable] = u.value();
    return Status::success();
  }
  if (c.one_sided) ws_.contacts[step.connections[0]].gap = 0.0;
  ws_.vars[line.variable] = u;
  st_.values[line.variable] = u.value();
  return Status::success();
}

// the step's one unknown node from its one connection, on jets
Status Kernel::closed_form(const SolveStep& step, int step_index, double driver) {
  const Connection& c = m_.connections[step.connections[0]];
  const int var = m_.nodes[step.output_node].first_variable;
  const bool out_b = step.output_node == c.node_b;
  const int ia = m_.nodes[c.node_a].first_variable, ib = m_.nodes[c.node_b].first_variable;
  Jet3 q;
  st_.open[step_index] = false;
  bool held = false;
  switch (step.method) {
    case StepMethod::link_closed_form:
    case StepMethod::contact_distance_closed_form:
      if (Status st = distance_step(step, step_index, driver, q, held); !st.ok() || held) return st;
      break;
    case StepMethod::contact_line_closed_form:
      if (Status st = line_step(step, step_index, driver, q, held); !st.ok() || held) return st;
      break;
    case StepMethod::gear_closed_form:
      q = out_b ? c.ratio * ws_.vars[ia] : ws_.vars[ib] / c.ratio;
      break;
    case StepMethod::rack_closed_form:
      q = out_b ? c.pitch_radius * ws_.vars[ia] : ws_.vars[ib] / c.pitch_radius;
      break;
    case StepMethod::variable_gear_closed_form:
      q = gear_integral(c, ws_.vars[ia]);
      break;
    case StepMethod::implicit:
      CAMOPT_ASSERT(false);
  }
  ws_.vars[var] = q;
  st_.values[var] = q.value();
  st_.invalidate_pose(step.output_node);
  return Status::success();
}

}  // namespace camopt::kin::detail
