#pragma once
// a probe that parameterises a floating lever by the travel of one of its rollers: a flat
// face on a translating node pushing the roller along a cam pivot's radial direction
// through a roller centre (cx, cy); its travel is the roller centre's displacement along
// that direction. The lever's other contacts fix the rest of its pose, so the kinematics
// solves the lever with exact jets in the travel. Used by the inversion through a floating
// follower (floating_inversion.hpp) and by the lever path of a floating swing cam
// (lever_path.hpp).
#include <algorithm>
#include <cmath>
#include <utility>

#include "camopt/core/design_spec.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::synthesis::detail {

// whether the contacts of the plan step that solves `node` are analytic: no profile table
// among their surfaces (circles, lines and disc profiles only). Then the node's pose is
// smooth in the probe travel, and septic hermite between solves 0.5 mm apart is exact to
// round-off; a table's knots would leave it only as smooth as the table's spline
inline bool held_analytically(const kin::Mechanism& m, int node) {
  const int first = m.nodes[static_cast<std::size_t>(node)].first_variable;
  for (const kin::SolveStep& step : m.plan) {
    if (std::find(step.unknowns.begin(), step.unknowns.end(), first) == step.unknowns.end()) continue;
    for (int ci : step.connections) {
      const kin::Connection& c = m.connections[static_cast<std::size_t>(ci)];
      for (const kin::Surface* s : {&c.surface_a, &c.surface_b})
        if (s->kind == kin::SurfaceKind::curve && !m.profiles[static_cast<std::size_t>(s->profile)].is_disc())
          return false;
    }
    return true;
  }
  return false;
}

inline constexpr const char* kProbeNode = "synthesis_probe";
inline constexpr const char* kProbeFace = "synthesis_probe_face";

// the probe's node and its face on `roller` (a circle), pushing radially from the pivot
// (px, py) through (cx, cy) [mm]
inline std::pair<NodeSpec, ConnectionSpec> radial_probe(const SurfaceSpec& roller, double px, double py, double cx,
                                                        double cy) {
  const double len = std::hypot(cx - px, cy - py), dx = (cx - px) / len, dy = (cy - py) / len;
  const double r = roller.radius_mm;
  std::pair<NodeSpec, ConnectionSpec> parts;
  auto& [probe, face] = parts;
  probe.name = kProbeNode;
  probe.kind = NodeKind::translational;
  probe.origin_mm = {cx, cy};
  probe.direction = {dx, dy};
  face.name = kProbeFace;
  face.kind = ConnectionKind::contact;
  face.surface_a.node = probe.name;
  face.surface_a.shape = SurfaceShape::line;
  face.surface_a.origin_mm = {cx - r * dx, cy - r * dy};
  face.surface_a.normal = {dx, dy};
  face.surface_b = roller;
  face.surface_b.concave = false;
  return parts;
}

}  // namespace camopt::synthesis::detail
