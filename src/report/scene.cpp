// build_scene: the bodies, the frames solved by the kinematics kernel, the shapes drawn from
// the design, and the bounding box over every frame (scene.hpp)
#include "camopt/report/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

#include "camopt/core/units.hpp"
#include "scene_detail.hpp"

namespace camopt::report {

namespace {

// the driver grid [deg or mm]: start, start + step, ..., stop (the last step may be short),
// the grid of kin::sweep, so that a frame is the CSV row of the same angle
std::vector<double> driver_grid(const SceneRequest& r) {
  std::vector<double> driver;
  const long n = std::lround((r.stop_deg - r.start_deg) / r.step_deg);
  driver.reserve(static_cast<std::size_t>(n) + 1);
  for (long i = 0; i <= n; ++i) driver.push_back(std::min(r.stop_deg, r.start_deg + r.step_deg * static_cast<double>(i)));
  return driver;
}

// every position: every control at its default, the first one at the requested value
std::vector<std::vector<double>> control_positions(const kin::Mechanism& mech, const SceneRequest& r) {
  std::vector<double> values = r.controls;
  if (values.empty()) values.push_back(mech.controls.empty() ? 0.0 : mech.controls[0].default_value);
  std::vector<std::vector<double>> positions;
  for (double v : values) {
    std::vector<double> p = mech.default_controls();
    if (!p.empty()) p[0] = v;
    positions.push_back(std::move(p));
  }
  return positions;
}

// grows box by a point
void extend(double* box, double x, double y) {
  box[0] = std::min(box[0], x);
  box[1] = std::min(box[1], y);
  box[2] = std::max(box[2], x);
  box[3] = std::max(box[3], y);
}

// the points of a body that can be extreme in any pose: the convex hull of its shape points
// (Andrew's monotone chain; a rotation and a translation keep a set's extremes on its hull),
// and its circles (centre, radius)
struct BodyExtent {
  std::vector<std::array<double, 2>> hull;
  std::vector<std::array<double, 3>> circles;
};

std::vector<std::array<double, 2>> convex_hull(std::vector<std::array<double, 2>> pts) {
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  const auto cross = [](const auto& o, const auto& a, const auto& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  std::vector<std::array<double, 2>> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

std::vector<BodyExtent> body_extents(const Scene& scene) {
  std::vector<std::vector<std::array<double, 2>>> points(scene.bodies.size());
  std::vector<BodyExtent> out(scene.bodies.size());
  for (const SceneShape& s : scene.shapes)
    for (std::size_t k = 0; k + 1 < s.xy.size(); k += 2) {
      // a spring's second end moves with body_b
      const auto body = static_cast<std::size_t>(s.kind == SceneShape::Kind::spring && k == 2 ? s.body_b : s.body);
      if (s.kind == SceneShape::Kind::circle)
        out[body].circles.push_back({s.xy[k], s.xy[k + 1], s.radius});
      else
        points[body].push_back({s.xy[k], s.xy[k + 1]});
    }
  for (std::size_t b = 0; b < out.size(); ++b) out[b].hull = convex_hull(std::move(points[b]));
  return out;
}

// the bounding box of every shape point posed by its body's pose at every frame [mm]
void bounding_box(Scene& scene) {
  double box[4] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  const std::vector<BodyExtent> extents = body_extents(scene);
  for (const ScenePosition& p : scene.positions)
    for (std::size_t f = 0; f < p.cam_deg.size(); ++f)
      for (std::size_t b = 0; b < extents.size(); ++b) {
        const std::vector<double>& pose = p.pose[b];
        const double tx = pose[3 * f], ty = pose[3 * f + 1], a = pose[3 * f + 2];
        const double c = std::cos(a), sn = std::sin(a);
        for (const auto& q : extents[b].hull) extend(box, c * q[0] - sn * q[1] + tx, sn * q[0] + c * q[1] + ty);
        for (const auto& q : extents[b].circles) {
          const double x = c * q[0] - sn * q[1] + tx, y = sn * q[0] + c * q[1] + ty;
          extend(box, x - q[2], y - q[2]);
          extend(box, x + q[2], y + q[2]);
        }
      }
  std::copy(box, box + 4, scene.bbox);
}

}  // namespace

void SceneRequest::validate(const kin::Mechanism& mech) const {
  CAMOPT_THROW_UNLESS(std::isfinite(start_deg), "scene start_deg = " + format_value(start_deg) + " must be finite");
  CAMOPT_THROW_UNLESS(std::isfinite(stop_deg), "scene stop_deg = " + format_value(stop_deg) + " must be finite");
  CAMOPT_THROW_UNLESS(stop_deg >= start_deg, "scene stop_deg = " + format_value(stop_deg) +
                                                 " must be >= start_deg = " + format_value(start_deg));
  CAMOPT_THROW_UNLESS(step_deg > 0 && std::isfinite(step_deg),
                      "scene step_deg = " + format_value(step_deg) + " must be > 0");
  for (double v : controls) {
    if (mech.controls.empty()) {
      CAMOPT_THROW_UNLESS(v == 0.0 && controls.size() == 1, "scene controls: design '" + mech.name +
                                                                "' has no [[control]]: give none or {0}, not " +
                                                                format_value(v));
      continue;
    }
    const kin::Control& c = mech.controls[0];
    CAMOPT_THROW_UNLESS(v >= c.min - 1e-12 && v <= c.max + 1e-12,
                        "scene controls: value " + format_value(v, 12) + " is outside control '" + c.name +
                            "' range [" + format_value(c.min, 12) + ", " + format_value(c.max, 12) + "]");
  }
}

Scene build_scene(const DesignSpec& spec, const kin::Mechanism& mech, const SceneRequest& request) {
  request.validate(mech);
  Scene scene;
  // the bodies: the nodes, then link bars and pivot carriers
  for (const kin::Node& n : mech.nodes) scene.bodies.push_back(n.name);
  detail::SceneLayout layout = detail::plan_layout(mech, scene.bodies);
  for (const kin::Connection& c : mech.connections)
    if (c.kind == ConnectionKind::contact) scene.contacts.push_back(c.name);
  if (!mech.controls.empty()) scene.control_name = mech.controls[0].name;
  scene.control_unit = mech.controls.empty() || mech.controls[0].is_angle ? "deg" : "mm";
  scene.output_body = mech.nodes[static_cast<std::size_t>(mech.output_node)].name;
  // the frames, solved at every control position and driver angle
  detail::solve_frames(mech, control_positions(mech, request), driver_grid(request), layout, scene);
  // the shapes, from the design and the swept contacts
  detail::add_shapes(spec, mech, layout, scene);
  // the box that holds every frame
  bounding_box(scene);
  return scene;
}

namespace detail {

SceneLayout plan_layout(const kin::Mechanism& mech, std::vector<std::string>& names) {
  SceneLayout layout;
  layout.size = mech.length_scale;
  layout.carrier.assign(mech.nodes.size(), -1);
  layout.swept.resize(mech.connections.size());
  std::set<std::string> taken(names.begin(), names.end());
  auto unique = [&](std::string name, const char* suffix) {
    while (!taken.insert(name).second) name += suffix;
    return name;
  };
  // a link's bar: pin a and the point at the link's length towards pin b
  for (std::size_t ci = 0; ci < mech.connections.size(); ++ci) {
    const kin::Connection& c = mech.connections[ci];
    if (c.kind != ConnectionKind::link && c.kind != ConnectionKind::crank_slider) continue;
    ExtraBody e;
    e.connection = static_cast<int>(ci);
    e.a = c.pin_a;
    const Eigen::Vector2d d = c.pin_b - c.pin_a;
    e.b = d.norm() > 0 ? Eigen::Vector2d(c.pin_a + d.normalized() * c.length) : c.pin_b;
    layout.extras.push_back(e);
    names.push_back(unique(c.name, " link"));
  }
  // the carrier of every pivot a control moves
  for (std::size_t n = 0; n < mech.nodes.size(); ++n) {
    if (mech.nodes[n].ground || mech.nodes[n].pivot_control < 0) continue;
    ExtraBody e;
    e.kind = ExtraBody::Kind::carrier;
    e.node = static_cast<int>(n);
    layout.carrier[n] = static_cast<int>(names.size());
    layout.extras.push_back(e);
    names.push_back(unique(mech.nodes[n].name + " pivot", "'"));
  }
  return layout;
}

SceneShape make_shape(SceneShape::Kind kind, int body, const Points& points, const char* role) {
  SceneShape s;
  s.kind = kind;
  s.body = body;
  s.role = role;
  s.xy.reserve(points.size() * 2);
  for (const Eigen::Vector2d& p : points) {
    s.xy.push_back(p.x());
    s.xy.push_back(p.y());
  }
  return s;
}

SceneShape make_circle(int body, const Eigen::Vector2d& centre, double radius, const char* role) {
  SceneShape s = make_shape(SceneShape::Kind::circle, body, {centre}, role);
  s.radius = radius;
  return s;
}

std::array<double, 2> covering_arc(const std::vector<double>& u) {
  if (u.empty()) return {0.0, 0.0};
  std::vector<double> w(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    w[i] = std::fmod(u[i], 2 * pi);
    if (w[i] < 0) w[i] += 2 * pi;
  }
  std::sort(w.begin(), w.end());
  // the largest gap between neighbours (the last one wraps round); the arc is the rest
  double gap = w.front() + 2 * pi - w.back();
  std::size_t after = 0;  // the first angle after the largest gap
  for (std::size_t i = 1; i < w.size(); ++i)
    if (w[i] - w[i - 1] > gap) {
      gap = w[i] - w[i - 1];
      after = i;
    }
  return {w[after], w[after] + 2 * pi - gap};
}

}  // namespace detail

}  // namespace camopt::report
