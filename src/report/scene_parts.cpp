// the scene's shapes that come from the nodes and springs: every translating body's stem,
// the valve's head and seat, and the springs from their ground seat to the point they push
#include <cmath>

#include "camopt/core/units.hpp"
#include "scene_detail.hpp"

namespace camopt::report::detail {

namespace {

// a translating body drawn as a stem along its direction from its origin: a valve's stem
// with the retainer near the tip and the head at the seat end (the opening direction)
struct Stem {
  Eigen::Vector2d tip{0, 0};     // the origin of the node [mm]
  Eigen::Vector2d dir{0, 1};     // unit opening direction
  Eigen::Vector2d across{-1, 0};  // unit normal to it
  double head = 29.0;            // head diameter: the seat's [mm]
  double width = 5.8;            // stem diameter [mm]
  double retainer = 2.9;         // spring retainer from the tip [mm]
  double spring = 37.7;          // spring length [mm] (installed, when given)
  double length = 55.0;          // tip to the head [mm]
  bool valve = false;            // a head and a seat (the node has a seat)
};

const NodeSpec* node_spec(const DesignSpec& spec, const std::string& name) {
  for (const NodeSpec& n : spec.nodes)
    if (n.name == name) return &n;
  return nullptr;
}

// a compression spring that pushes the stem (no point of its own)
const SpringSpec* stem_spring(const DesignSpec& spec, const std::string& node) {
  for (const SpringSpec& s : spec.springs)
    if (s.node == node && s.kind == SpringKind::compression && !s.point_mm) return &s;
  return nullptr;
}

Stem stem_of(const DesignSpec& spec, const kin::Mechanism& mech, int n) {
  const kin::Node& node = mech.nodes[static_cast<std::size_t>(n)];
  const NodeSpec* ns = node_spec(spec, node.name);
  Stem s;
  s.dir = node.direction.normalized();
  s.across = {-s.dir.y(), s.dir.x()};
  if (ns == nullptr) return s;
  s.tip = {ns->origin_mm[0], ns->origin_mm[1]};
  s.valve = ns->seat.enabled && (n == mech.output_node || ns->seat.given);
  s.head = ns->seat.diameter_mm;
  s.width = 0.2 * s.head;
  s.retainer = 0.1 * s.head;
  const SpringSpec* spring = stem_spring(spec, node.name);
  s.spring = spring != nullptr && spring->installed_length_mm ? *spring->installed_length_mm : 1.3 * s.head;
  s.length = spring != nullptr ? s.retainer + s.spring + 0.5 * s.head : 2.0 * s.head;
  return s;
}

// the head's outline, mirrored about the stem axis: neck, seat face (45 deg), rim
Points head_outline(const Stem& s) {
  const Eigen::Vector2d neck = s.tip + s.length * s.dir, face = neck + 0.2 * s.head * s.dir;
  const double bevel = 0.05 * s.head, rim = 0.06 * s.head, r = 0.5 * s.head;
  Points half = {neck + 0.5 * s.width * s.across, face + (r - bevel) * s.across,
                 face + bevel * s.dir + r * s.across, face + (bevel + rim) * s.dir + r * s.across};
  Points out = half;
  for (auto p = half.rbegin(); p != half.rend(); ++p) {
    const double off = (*p - neck).dot(s.across);
    out.push_back(*p - 2 * off * s.across);
  }
  return out;
}

// the seat on ground under the head's face, on both sides (the drawing is the valve closed)
void add_seat(const Stem& s, Scene& scene) {
  const Eigen::Vector2d face = s.tip + (s.length + 0.2 * s.head) * s.dir;
  const double bevel = 0.05 * s.head, r = 0.5 * s.head, depth = 0.15 * s.head;
  for (double side : {1.0, -1.0}) {
    const Eigen::Vector2d a = side * s.across;
    const Eigen::Vector2d inner = face + (r - bevel) * a, outer = face + bevel * s.dir + r * a;
    scene.shapes.push_back(
        make_shape(SceneShape::Kind::polygon, 0, {inner, outer, outer + depth * a, inner + depth * a}, "seat"));
  }
}

SceneShape spring_shape(int ground_body, const Eigen::Vector2d& seat, int body, const Eigen::Vector2d& point) {
  SceneShape s = make_shape(SceneShape::Kind::spring, ground_body, {seat, point}, "spring");
  s.body_b = body;
  return s;
}

// a torsion spring at the pivot: a short coil from the ground (or the pivot's carrier) to an
// arm of the body, on the side of the pivot away from the body's features
void add_torsion_spring(const kin::Mechanism& mech, const SceneLayout& layout, int n, Scene& scene,
                        Features& features) {
  const kin::Node& node = mech.nodes[static_cast<std::size_t>(n)];
  Eigen::Vector2d mean(0, 0);
  for (const Eigen::Vector2d& f : features[static_cast<std::size_t>(n)]) mean += f;
  const std::size_t count = features[static_cast<std::size_t>(n)].size();
  const Eigen::Vector2d away = count > 0 ? Eigen::Vector2d(node.pivot - mean / static_cast<double>(count))
                                         : Eigen::Vector2d(0, -1);
  const double a0 = away.norm() > 1e-9 ? std::atan2(away.y(), away.x()) : -0.5 * pi;
  const double arm = std::max(3 * pin_radius(layout), 0.1 * layout.size);
  auto at = [&](double a) { return Eigen::Vector2d(node.pivot + arm * Eigen::Vector2d(std::cos(a), std::sin(a))); };
  const Eigen::Vector2d end = at(a0 - 0.6);
  scene.shapes.push_back(spring_shape(std::max(layout.carrier[static_cast<std::size_t>(n)], 0), at(a0 + 0.6), n, end));
  features[static_cast<std::size_t>(n)].push_back(end);
}

}  // namespace

void add_valves(const DesignSpec& spec, const kin::Mechanism& mech, Scene& scene) {
  for (std::size_t n = 0; n < mech.nodes.size(); ++n) {
    const kin::Node& node = mech.nodes[n];
    if (node.ground || node.kind != NodeKind::translational) continue;
    const Stem s = stem_of(spec, mech, static_cast<int>(n));
    const Eigen::Vector2d end = s.tip + s.length * s.dir, w = 0.5 * s.width * s.across;
    const int body = static_cast<int>(n);
    scene.shapes.push_back(make_shape(SceneShape::Kind::polygon, body, {s.tip + w, end + w, end - w, s.tip - w}, "valve"));
    if (!s.valve) continue;
    scene.shapes.push_back(make_shape(SceneShape::Kind::polygon, body, head_outline(s), "valve"));
    add_seat(s, scene);
  }
}

void add_springs(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene,
                 Features& features) {
  for (const SpringSpec& sp : spec.springs) {
    const int n = mech.node_index(sp.node);
    if (n <= 0) continue;
    const kin::Node& node = mech.nodes[static_cast<std::size_t>(n)];
    if (sp.kind == SpringKind::torsion) {
      if (node.kind == NodeKind::rotational) add_torsion_spring(mech, layout, n, scene, features);
      continue;
    }
    if (sp.point_mm) {
      // a spring on a point of the body: its seat along the line of action, beyond the point
      const Eigen::Vector2d p((*sp.point_mm)[0], (*sp.point_mm)[1]);
      Eigen::Vector2d d = sp.direction ? Eigen::Vector2d((*sp.direction)[0], (*sp.direction)[1]) : Eigen::Vector2d(0, 1);
      d = d.norm() > 0 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(0, 1);
      const double length = sp.installed_length_mm ? *sp.installed_length_mm : 0.3 * layout.size;
      scene.shapes.push_back(spring_shape(0, p + length * d, n, p));
      features[static_cast<std::size_t>(n)].push_back(p);
    } else if (node.kind == NodeKind::translational) {
      // a valve spring: from the retainer to its seat on ground, around the stem
      const Stem s = stem_of(spec, mech, n);
      const Eigen::Vector2d retainer = s.tip + s.retainer * s.dir;
      scene.shapes.push_back(spring_shape(0, retainer + s.spring * s.dir, n, retainer));
    }
  }
}

}  // namespace camopt::report::detail
