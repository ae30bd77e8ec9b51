// the scene's shapes that come from the connections: contact surfaces (profiles, circles,
// flat faces, ground guides), link bars, pivots, and the lever skeletons that join every
// turning or floating body's pivot or reference to its features
#include <algorithm>
#include <cmath>

#include "camopt/core/units.hpp"
#include "scene_detail.hpp"

namespace camopt::report::detail {

namespace {

constexpr double kArcMargin = 12.0 * rad_per_deg;  // drawn beyond the swept part of a curve or guide [rad]
constexpr double kStep = 1.0 * rad_per_deg;        // profile sampling: the coarsest parameter step [rad]
constexpr double kMinStep = kStep / 64;            // ... and the finest
constexpr double kChordError = 0.005;              // largest distance of the curve from a chord [mm]

// a curve surface's point at parameter u in its body's drawing frame [mm]
Eigen::Vector2d curve_point(const kin::Mechanism& mech, const kin::Surface& s, double u) {
  const kin::CurvePoint<double> c = mech.profiles[static_cast<std::size_t>(s.profile)].point(u, false);
  return {s.origin.x() + s.cos_orient * c.x - s.sin_orient * c.y, s.origin.y() + s.sin_orient * c.x + s.cos_orient * c.y};
}

// the curve from u0 to u1 (both included): steps of at most kStep, halved until the midpoint
// lies within kChordError of the chord
Points sample_curve(const kin::Mechanism& mech, const kin::Surface& s, double u0, double u1) {
  Points out{curve_point(mech, s, u0)};
  double u = u0;
  while (u < u1) {
    double h = std::min(kStep, u1 - u);
    Eigen::Vector2d p1 = curve_point(mech, s, u + h);
    for (;;) {
      const Eigen::Vector2d pm = curve_point(mech, s, u + h / 2), chord = p1 - out.back();
      const double n = chord.norm();
      const double off = n > 0 ? std::abs(chord.x() * (pm - out.back()).y() - chord.y() * (pm - out.back()).x()) / n
                               : (pm - out.back()).norm();
      if (off <= kChordError || h <= kMinStep) break;
      h /= 2;
      p1 = pm;
    }
    out.push_back(p1);
    u = u1 - u <= h ? u1 : u + h;
  }
  return out;
}

// a profile: its whole outline on a body that turns through a revolution, else the part its
// contacts sweep plus a margin (an oscillating swing cam or working curve), whose ends the
// skeleton joins (not its polar origin, which may lie off the part: the Valvetronic lever's
// working curve is centred on the camshaft)
void add_curve(const kin::Mechanism& mech, const kin::Surface& s, int body, const std::vector<double>& swept,
               Scene& scene, Features& features) {
  const std::array<double, 2> arc = covering_arc(swept);
  const bool whole = body == mech.driver_node || swept.empty() || arc[1] - arc[0] + 2 * kArcMargin >= 2 * pi;
  if (whole) {
    Points outline = sample_curve(mech, s, 0.0, 2 * pi);
    outline.pop_back();  // the closing point repeats the first
    scene.shapes.push_back(make_shape(SceneShape::Kind::polygon, body, outline, "profile"));
    features[static_cast<std::size_t>(body)].push_back(s.origin);  // a lobe whose origin is off the pivot
  } else {
    const Points part = sample_curve(mech, s, arc[0] - kArcMargin, arc[1] + kArcMargin);
    scene.shapes.push_back(make_shape(SceneShape::Kind::polyline, body, part, "profile"));
    features[static_cast<std::size_t>(body)].push_back(part.front());
    features[static_cast<std::size_t>(body)].push_back(part.back());
  }
}

// a circle on ground (a guide): the arc its contact sweeps plus a margin
void add_guide(const kin::Surface& s, const std::vector<double>& swept, Scene& scene) {
  const std::array<double, 2> arc = covering_arc(swept);
  const double r = std::abs(s.offset);
  if (swept.empty() || arc[1] - arc[0] + 2 * kArcMargin >= 2 * pi) {
    scene.shapes.push_back(make_circle(0, s.origin, r, "profile"));
    return;
  }
  const double a0 = arc[0] - kArcMargin, a1 = arc[1] + kArcMargin;
  const int n = std::max(2, static_cast<int>(std::ceil((a1 - a0) / kStep)));
  Points points;
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    points.push_back(s.origin + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  scene.shapes.push_back(make_shape(SceneShape::Kind::polyline, 0, points, "profile"));
}

// a flat face: the extent its contact sweeps plus a margin, at least its half-width
void add_face(const kin::Surface& s, const ConnectionSpec* cs, int side, int body, const std::vector<double>& swept,
              double size, Scene& scene, Features& features) {
  double lo = 0.0, hi = 0.0;
  if (!swept.empty()) {
    const auto [mn, mx] = std::minmax_element(swept.begin(), swept.end());
    const double margin = std::max(0.1 * (*mx - *mn), 0.03 * size);
    lo = *mn - margin;
    hi = *mx + margin;
  }
  const SurfaceSpec* ss = cs == nullptr ? nullptr : side == 0 ? &cs->surface_a : &cs->surface_b;
  if (ss != nullptr && ss->half_width_mm) {
    lo = std::min(lo, -*ss->half_width_mm);
    hi = std::max(hi, *ss->half_width_mm);
  }
  const Eigen::Vector2d t(-s.normal.y(), s.normal.x());  // the face parameter runs along it
  scene.shapes.push_back(make_shape(SceneShape::Kind::polyline, body, {s.origin + lo * t, s.origin + hi * t}, "profile"));
  features[static_cast<std::size_t>(body)].push_back(s.origin + 0.5 * (lo + hi) * t);
}

const ConnectionSpec* connection_spec(const DesignSpec& spec, const std::string& name) {
  for (const ConnectionSpec& cs : spec.connections)
    if (cs.name == name) return &cs;
  return nullptr;
}

}  // namespace

void add_surfaces(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene,
                  Features& features) {
  for (std::size_t ci = 0; ci < mech.connections.size(); ++ci) {
    const kin::Connection& c = mech.connections[ci];
    if (c.kind != ConnectionKind::contact) continue;
    for (int side = 0; side < 2; ++side) {
      const kin::Surface& s = side == 0 ? c.surface_a : c.surface_b;
      const int body = side == 0 ? c.node_a : c.node_b;
      const std::vector<double>& swept = layout.swept[ci][static_cast<std::size_t>(side)];
      switch (s.kind) {
        case kin::SurfaceKind::curve: add_curve(mech, s, body, swept, scene, features); break;
        case kin::SurfaceKind::line:
          add_face(s, connection_spec(spec, c.name), side, body, swept, layout.size, scene, features);
          break;
        case kin::SurfaceKind::point:
          if (mech.nodes[static_cast<std::size_t>(body)].ground) {
            add_guide(s, swept, scene);
          } else {
            scene.shapes.push_back(make_circle(body, s.origin, std::abs(s.offset), s.roller ? "roller" : "profile"));
            features[static_cast<std::size_t>(body)].push_back(s.origin);
          }
          break;
      }
    }
  }
}

void add_links(const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene, Features& features) {
  const int first = static_cast<int>(mech.nodes.size());
  for (std::size_t e = 0; e < layout.extras.size(); ++e) {
    const ExtraBody& x = layout.extras[e];
    if (x.kind != ExtraBody::Kind::link) continue;
    const int body = first + static_cast<int>(e);
    const kin::Connection& c = mech.connections[static_cast<std::size_t>(x.connection)];
    scene.shapes.push_back(make_shape(SceneShape::Kind::polyline, body, {x.a, x.b}, "lever"));
    scene.shapes.push_back(make_circle(body, x.a, pin_radius(layout), "pivot"));
    scene.shapes.push_back(make_circle(body, x.b, pin_radius(layout), "pivot"));
    features[static_cast<std::size_t>(c.node_a)].push_back(c.pin_a);
    features[static_cast<std::size_t>(c.node_b)].push_back(c.pin_b);
  }
}

void add_pivots(const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene) {
  for (std::size_t n = 0; n < mech.nodes.size(); ++n) {
    const kin::Node& node = mech.nodes[n];
    if (node.ground || node.kind != NodeKind::rotational) continue;
    // on ground, or on the carrier of a pivot a control moves
    scene.shapes.push_back(make_circle(std::max(layout.carrier[n], 0), node.pivot, pin_radius(layout), "pivot"));
  }
}

void add_skeletons(const kin::Mechanism& mech, const SceneLayout& layout, const Features& features, Scene& scene) {
  for (std::size_t n = 0; n < mech.nodes.size(); ++n) {
    const kin::Node& node = mech.nodes[n];
    if (node.ground || node.kind == NodeKind::translational) continue;
    const Eigen::Vector2d hub = node.kind == NodeKind::rotational ? node.pivot : node.reference;
    Points done;
    for (const Eigen::Vector2d& f : features[n]) {
      const bool seen = std::any_of(done.begin(), done.end(), [&](const Eigen::Vector2d& d) { return (d - f).norm() < 1e-9; });
      if (seen || (f - hub).norm() <= 1e-6 * layout.size) continue;
      done.push_back(f);
      scene.shapes.push_back(make_shape(SceneShape::Kind::polyline, static_cast<int>(n), {hub, f}, "lever"));
    }
  }
}

void add_shapes(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene) {
  Features features(scene.bodies.size());
  // the parts, each collecting the features of the levers that carry it
  add_links(mech, layout, scene, features);
  add_surfaces(spec, mech, layout, scene, features);
  add_valves(spec, mech, scene);
  add_springs(spec, mech, layout, scene, features);
  add_pivots(mech, layout, scene);
  // the skeletons, drawn beneath every part
  Scene skeletons;
  add_skeletons(mech, layout, features, skeletons);
  scene.shapes.insert(scene.shapes.begin(), skeletons.shapes.begin(), skeletons.shapes.end());
}

}  // namespace camopt::report::detail
