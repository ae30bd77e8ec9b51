#pragma once
// the steps of build_scene (scene.hpp) and what they share: the bodies beyond the
// mechanism's nodes (scene.cpp), the frames solved by the kinematics kernel
// (scene_frames.cpp), the shapes drawn from the design (scene_shapes.cpp, scene_parts.cpp)
// and the bounding box (scene.cpp).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/report/report_data.hpp"

namespace camopt::report::detail {

// a scene body that is not a node of the mechanism
struct ExtraBody {
  enum class Kind { link, carrier };
  Kind kind = Kind::link;
  int connection = -1;      // link: its connection (link or crank_slider)
  int node = -1;            // carrier: the node whose pivot a control moves
  Eigen::Vector2d a{0, 0};  // link: drawing pin a [mm]
  Eigen::Vector2d b{0, 0};  // link: the bar's other end, at the link's length from a towards pin b [mm]
};

// what the shapes need besides the design: the bodies and where the contacts went
struct SceneLayout {
  std::vector<ExtraBody> extras;  // Scene::bodies after the nodes, in order
  std::vector<int> carrier;       // per node: the scene body carrying its pivot, or -1
  // per connection and side (0: a, 1: b): the contact's surface parameter at every frame of
  // every position (curve: its parameter [rad]; line: along its tangent from its point [mm];
  // a circle on ground: the polar angle of the contact point about its centre [rad])
  std::vector<std::array<std::vector<double>, 2>> swept;
  double size = 1.0;  // the mechanism's characteristic size (Mechanism::length_scale) [mm]
};

// the bodies after the nodes (links, pivot carriers) and their names
SceneLayout plan_layout(const kin::Mechanism& mech, std::vector<std::string>& names);

// every position's frames (poses, contacts, lift), and the contacts' swept parameters into
// layout.swept. NumericalError naming the angle and the control position on a failed solve.
void solve_frames(const kin::Mechanism& mech, const std::vector<std::vector<double>>& controls,
                  const std::vector<double>& driver, SceneLayout& layout, Scene& scene);

// every shape of the scene, in drawing coordinates
void add_shapes(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene);

// ---- drawing helpers shared by the shape files -------------------------------------------
using Points = std::vector<Eigen::Vector2d>;

SceneShape make_shape(SceneShape::Kind kind, int body, const Points& points, const char* role);
SceneShape make_circle(int body, const Eigen::Vector2d& centre, double radius, const char* role);

// the radius of drawn pivots and pins [mm]
inline double pin_radius(const SceneLayout& layout) { return std::clamp(0.025 * layout.size, 1.0, 4.0); }

// the smallest interval [lo, hi] (hi - lo <= 2 pi) that covers every angle of `u` modulo 2 pi
std::array<double, 2> covering_arc(const std::vector<double>& u);

// the feature points of every body a skeleton joins to its pivot or reference [drawing mm]
using Features = std::vector<Points>;  // per scene body

// contact surfaces: profiles, circles, faces, guides (scene_shapes.cpp)
void add_surfaces(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene,
                  Features& features);
// link bars, pivots and skeletons (scene_shapes.cpp)
void add_links(const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene, Features& features);
void add_pivots(const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene);
void add_skeletons(const kin::Mechanism& mech, const SceneLayout& layout, const Features& features, Scene& scene);
// valves with their seats, and springs (scene_parts.cpp)
void add_valves(const DesignSpec& spec, const kin::Mechanism& mech, Scene& scene);
void add_springs(const DesignSpec& spec, const kin::Mechanism& mech, const SceneLayout& layout, Scene& scene,
                 Features& features);

}  // namespace camopt::report::detail
