#include "camopt/synthesis/mechanism_cut.hpp"

#include <functional>
#include <map>

namespace camopt::synthesis {

MechanismCut cut_mechanism(const DesignSpec& spec, const std::string& cam_kind, const std::string& target_node) {
  MechanismCut cut;
  std::vector<int> candidates;
  auto node_kind = [&](const std::string& name) -> const NodeSpec* {
    for (const auto& n : spec.nodes)
      if (n.name == name) return &n;
    return nullptr;
  };
  for (int i = 0; i < static_cast<int>(spec.connections.size()); ++i) {
    const auto& c = spec.connections[i];
    if (c.kind != ConnectionKind::contact) continue;
    for (int side = 0; side < 2; ++side) {
      const SurfaceSpec& s = side == 0 ? c.surface_a : c.surface_b;
      const SurfaceSpec& o = side == 0 ? c.surface_b : c.surface_a;
      if (s.shape != SurfaceShape::profile || o.shape == SurfaceShape::profile) continue;
      const NodeSpec* n = node_kind(s.node);
      // a rotational cam, or a swing cam on a rotational node or a floating lever
      if (!n || n->kind == NodeKind::translational) continue;
      if (n->kind == NodeKind::floating && cam_kind == "rotational") continue;
      if (n->control) continue;  // set by a control (an eccentric shaft): not driven by the cam
      const bool is_driver = s.node == spec.driver.node;
      if ((cam_kind == "rotational") != is_driver) continue;
      candidates.push_back(i * 2 + side);
    }
  }
  if (candidates.empty())
    throw InputError("synthesize --cam " + cam_kind + ": design '" + spec.name + "' has no contact between a " +
                     (cam_kind == "rotational" ? std::string("profile on the driver '") + spec.driver.node + "'"
                                               : std::string("profile on a rotational node other than the driver or on a floating lever")) +
                     " and a roller, pad or flat face");
  if (candidates.size() > 1) {
    std::string names;
    for (int c : candidates) names += (names.empty() ? "'" : ", '") + spec.connections[c / 2].name + "'";
    throw InputError("synthesize --cam " + cam_kind + ": several contacts qualify (" + names +
                     "); the design must have exactly one");
  }
  cut.connection = candidates[0] / 2;
  cut.profile_on_a = candidates[0] % 2 == 0;
  const auto& c = spec.connections[cut.connection];
  const SurfaceSpec& cam_surface = cut.profile_on_a ? c.surface_a : c.surface_b;
  const SurfaceSpec& follower_surface = cut.profile_on_a ? c.surface_b : c.surface_a;
  cut.cam_node = cam_surface.node;
  cut.follower_node = follower_surface.node;
  cut.profile = cam_surface.profile;
  if (follower_surface.shape == SurfaceShape::circle && follower_surface.concave)
    throw InputError(c.where, "synthesize: the follower of contact '" + c.name +
                                  "' is a concave circle; synthesis supports rollers, convex pads and flat faces");

  // components of the node graph without the designed contact (ground does not connect)
  std::map<std::string, std::string> parent;
  for (const auto& n : spec.nodes) parent[n.name] = n.name;
  std::function<std::string(const std::string&)> find = [&](const std::string& x) {
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  auto unite = [&](const std::string& a, const std::string& b) {
    if (a == "ground" || b == "ground") return;
    parent[find(a)] = find(b);
  };
  for (int i = 0; i < static_cast<int>(spec.connections.size()); ++i) {
    if (i == cut.connection) continue;
    const auto& k = spec.connections[i];
    if (k.kind == ConnectionKind::contact) unite(k.surface_a.node, k.surface_b.node);
    else if (k.kind == ConnectionKind::link || k.kind == ConnectionKind::crank_slider) unite(k.pin_a.node, k.pin_b.node);
    else unite(k.node_a, k.node_b);
  }
  if (!parent.count(target_node))
    throw InputError("synthesize --target-node: no node '" + target_node + "' in design '" + spec.name + "'");
  const std::string up_root = find(spec.driver.node), down_root = find(target_node);
  if (find(cut.cam_node) != up_root || find(cut.follower_node) != down_root || up_root == down_root)
    throw InputError(c.where, "synthesize: contact '" + c.name +
                                  "' does not separate the driver from '" + target_node + "', so the target motion "
                                  "does not determine its follower alone");
  auto half = [&](const std::string& root) {
    DesignSpec h = spec;
    h.nodes.clear();
    h.connections.clear();
    h.springs.clear();
    h.gas_forces.clear();
    for (const auto& n : spec.nodes)
      if (find(n.name) == root) h.nodes.push_back(n);
    auto inside = [&](const std::string& n) { return n == "ground" || find(n) == root; };
    for (int i = 0; i < static_cast<int>(spec.connections.size()); ++i) {
      if (i == cut.connection) continue;
      auto k = spec.connections[i];
      const bool in = k.kind == ConnectionKind::contact ? inside(k.surface_a.node) && inside(k.surface_b.node)
                      : (k.kind == ConnectionKind::link || k.kind == ConnectionKind::crank_slider)
                          ? inside(k.pin_a.node) && inside(k.pin_b.node)
                          : inside(k.node_a) && inside(k.node_b);
      if (!in) continue;
      k.lash_mm = 0.0;
      h.connections.push_back(k);
    }
    // only the profiles this half uses (compile builds every listed profile)
    std::erase_if(h.profiles, [&](const ProfileSpec& p) {
      for (const auto& k : h.connections)
        if ((k.surface_a.shape == SurfaceShape::profile && k.surface_a.profile == p.name) ||
            (k.surface_b.shape == SurfaceShape::profile && k.surface_b.profile == p.name))
          return false;
      return true;
    });
    return h;
  };
  cut.upstream = half(up_root);
  cut.upstream.output_node = cut.cam_node;
  cut.downstream = half(down_root);
  cut.downstream.driver.node = target_node;
  cut.downstream.output_node = cut.follower_node;
  return cut;
}

}  // namespace camopt::synthesis
