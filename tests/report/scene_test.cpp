// build_scene against the kinematics it draws: for every bundled design the contact point
// found on body A's posed surface and on body B's posed surface coincide (apart from an open
// lash gap, which the solver reports), the normal is unit and perpendicular to both
// surfaces, the output body's posed displacement is kin::sweep's lift and the lift_mm of a
// `camopt kinematics` run, and the shapes are posed where their bodies carry them. The
// eccentric designs' follower poses are checked against the closed forms of tests/oracles.
#include <catch2/catch.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/report/scene.hpp"
#include "cli/cli_support.hpp"
#include "oracles/oracles.hpp"
#include "support/compare.hpp"

using namespace camopt;
using Eigen::Vector2d;
using report::Scene;
using report::ScenePosition;
using report::SceneShape;

namespace {

// the solver closes a contact to ~1e-12 of the mechanism's size; the poses and the surface
// parameters reach the test along two paths (scene pose, sweep values in deg), a few ulps apart
constexpr double kContactAbs = 1e-9;      // [mm]
constexpr double kNormalAbs = 1e-9;       // |n| - 1 and n . tangent [-]
constexpr double kLiftAbs = 1e-12;        // the same solve along the same continuation [mm or deg]
constexpr double kClosedFormAbs = 1e-9;   // solver closure against the analytic pose [mm or rad]

struct Design {
  std::string file;
  DesignSpec spec;
  kin::Mechanism mech;
};

Design load(const std::string& name) {
  Design d;
  d.file = std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name;
  d.spec = io::load_design(d.file);
  d.mech = kin::compile(d.spec);
  return d;
}

std::vector<std::string> bundled_designs() {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CAMOPT_SOURCE_DIR) + "/designs"))
    if (e.path().extension() == ".toml") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// the request of a run: the design's sweep, and its control at min, middle and max
report::SceneRequest request_of(const kin::Mechanism& m) {
  report::SceneRequest r;
  r.start_deg = m.driver.start;
  r.stop_deg = m.driver.stop;
  r.step_deg = m.driver.step;
  if (!m.controls.empty())
    r.controls = {m.controls[0].min, 0.5 * (m.controls[0].min + m.controls[0].max), m.controls[0].max};
  return r;
}

// the sweep of the same request, through kin::sweep
kin::SweepResult sweep_of(const kin::Mechanism& m, const report::SceneRequest& r) {
  kin::SweepSpec s;
  s.start = r.start_deg;
  s.stop = r.stop_deg;
  s.step = r.step_deg;
  s.request.derivative_order = 1;
  s.request.contacts = true;
  for (double c : r.controls.empty() ? std::vector<double>{0.0} : r.controls) {
    std::vector<double> p = m.default_controls();
    if (!p.empty()) p[0] = c;
    s.control_positions.push_back(p);
  }
  return kin::sweep(m, s);
}

// a scene pose at one frame: current = R(angle) drawing + t
struct Posed {
  double c = 1, s = 0, tx = 0, ty = 0, angle = 0;
  Vector2d operator()(const Vector2d& p) const { return {c * p.x() - s * p.y() + tx, s * p.x() + c * p.y() + ty}; }
  Vector2d rotate(const Vector2d& v) const { return {c * v.x() - s * v.y(), s * v.x() + c * v.y()}; }
};

Posed pose_at(const ScenePosition& p, int body, std::size_t f) {
  const std::vector<double>& q = p.pose[static_cast<std::size_t>(body)];
  Posed out;
  out.tx = q[3 * f];
  out.ty = q[3 * f + 1];
  out.angle = q[3 * f + 2];
  out.c = std::cos(out.angle);
  out.s = std::sin(out.angle);
  return out;
}

int body_index(const Scene& s, const std::string& name) {
  const auto it = std::find(s.bodies.begin(), s.bodies.end(), name);
  REQUIRE(it != s.bodies.end());
  return static_cast<int>(it - s.bodies.begin());
}

// a surface variable at a sweep point, in the kernel's unit (kin::sweep writes "angles" in deg)
double variable_at(const kin::Mechanism& m, const kin::PositionResult& r, std::size_t i, int v) {
  const double x = r.value(i, v, 0);
  return m.variables[static_cast<std::size_t>(v)].is_angle ? x * rad_per_deg : x;
}

// the contact point on one surface, found from the body's scene pose: a curve or a face at
// its solved parameter; a circle at its radius along the contact normal (a: +n, b: -n)
struct SurfaceHit {
  Vector2d point, tangent;  // global [mm], unit tangent (a circle: its radius direction's normal)
};

SurfaceHit hit_on(const kin::Mechanism& m, const kin::Surface& s, int side, const Posed& pose, double u,
                  const Vector2d& n) {
  SurfaceHit h;
  switch (s.kind) {
    case kin::SurfaceKind::curve: {
      const kin::CurvePoint<double> c = m.profiles[static_cast<std::size_t>(s.profile)].point(u);
      const Vector2d local(s.origin.x() + s.cos_orient * c.x - s.sin_orient * c.y,
                           s.origin.y() + s.sin_orient * c.x + s.cos_orient * c.y);
      const Vector2d d(s.cos_orient * c.dx - s.sin_orient * c.dy, s.sin_orient * c.dx + s.cos_orient * c.dy);
      h.point = pose(local);
      h.tangent = pose.rotate(d).normalized();
      break;
    }
    case kin::SurfaceKind::line: {
      const Vector2d t(-s.normal.y(), s.normal.x());
      h.point = pose(s.origin + u * t);
      h.tangent = pose.rotate(t);
      break;
    }
    case kin::SurfaceKind::point: {
      const Vector2d centre = pose(s.origin);
      h.point = centre + (side == 0 ? 1.0 : -1.0) * s.offset * n;
      const Vector2d radial = (h.point - centre) / std::abs(s.offset);
      h.tangent = {-radial.y(), radial.x()};
      break;
    }
  }
  return h;
}

// every frame of every position: contacts seen from both bodies, the normal, the lift
void check_contacts_and_lift(const Design& d, const Scene& scene, const kin::SweepResult& sw) {
  const kin::Mechanism& m = d.mech;
  const std::size_t nc = m.connections.size();
  REQUIRE(scene.positions.size() == sw.positions.size());
  const int out_body = body_index(scene, scene.output_body);
  const kin::Node& out = m.nodes[static_cast<std::size_t>(out_body)];
  for (std::size_t p = 0; p < scene.positions.size(); ++p) {
    const ScenePosition& pos = scene.positions[p];
    const kin::PositionResult& r = sw.positions[p];
    REQUIRE(r.status.ok());
    REQUIRE(pos.cam_deg == sw.driver);
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f) {
      INFO(d.file << " control " << pos.control << " cam " << pos.cam_deg[f]);
      // the lift: kin::sweep's, and the output body's posed displacement
      CHECK(std::abs(pos.lift_mm[f] - kin::output_lift(m, r, f)) <= kLiftAbs);
      const Posed po = pose_at(pos, out_body, f);
      const double shown = out.kind == NodeKind::translational ? Vector2d(po.tx, po.ty).dot(out.direction) - out.rest
                                                               : (po.angle - out.rest) * deg_per_rad;
      CHECK(std::abs(shown - kin::output_lift(m, r, f)) <= kLiftAbs);
      // ground does not move
      const Posed g = pose_at(pos, 0, f);
      CHECK((g.tx == 0.0 && g.ty == 0.0 && g.angle == 0.0));
      std::size_t k = 0;
      for (std::size_t ci = 0; ci < nc; ++ci) {
        const kin::Connection& c = m.connections[ci];
        if (c.kind != ConnectionKind::contact) continue;
        INFO("contact " << c.name);
        const std::vector<double>& rec = pos.contact[k++];
        const Vector2d x(rec[4 * f], rec[4 * f + 1]), n(rec[4 * f + 2], rec[4 * f + 3]);
        CHECK(std::abs(n.norm() - 1.0) <= kNormalAbs);
        const double ua = c.surface_a.variable >= 0 ? variable_at(m, r, f, c.surface_a.variable) : 0.0;
        const double ub = c.surface_b.variable >= 0 ? variable_at(m, r, f, c.surface_b.variable) : 0.0;
        const SurfaceHit a = hit_on(m, c.surface_a, 0, pose_at(pos, c.node_a, f), ua, n);
        const SurfaceHit b = hit_on(m, c.surface_b, 1, pose_at(pos, c.node_b, f), ub, n);
        // b's point lies (gap - lash) along n from a's: zero for a closed contact without lash
        const double gap = r.contacts[f * nc + ci].gap;
        CHECK((b.point - a.point - (gap - c.lash) * n).norm() <= kContactAbs);
        // the recorded point is the one on the curve or face (a's, between two circles)
        const bool on_b = c.surface_a.kind == kin::SurfaceKind::point && c.surface_b.kind != kin::SurfaceKind::point;
        CHECK((x - (on_b ? b.point : a.point)).norm() <= kContactAbs);
        CHECK(std::abs(n.dot(a.tangent)) <= kNormalAbs);
        CHECK(std::abs(n.dot(b.tangent)) <= kNormalAbs);
      }
    }
  }
}

// every posed shape point of every frame lies in the bbox, and the bbox touches them
void check_shapes_and_bbox(const Scene& scene) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const SceneShape& s : scene.shapes) {
    CHECK((s.body >= 0 && s.body < static_cast<int>(scene.bodies.size())));
    CHECK((s.body_b >= 0 && s.body_b < static_cast<int>(scene.bodies.size())));
    CHECK((s.xy.size() % 2 == 0 && !s.xy.empty()));
    CHECK(!s.role.empty());
  }
  for (const ScenePosition& pos : scene.positions)
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f)
      for (const SceneShape& s : scene.shapes)
        for (std::size_t k = 0; k + 1 < s.xy.size(); k += 2) {
          const int body = s.kind == SceneShape::Kind::spring && k == 2 ? s.body_b : s.body;
          const Vector2d q = pose_at(pos, body, f)(Vector2d(s.xy[k], s.xy[k + 1]));
          const double r = s.kind == SceneShape::Kind::circle ? s.radius : 0.0;
          for (int i = 0; i < 2; ++i) {
            lo[i] = std::min(lo[i], q[i] - r);
            hi[i] = std::max(hi[i], q[i] + r);
          }
        }
  const double eps = 1e-9;
  CHECK(scene.bbox[0] <= lo[0]);
  CHECK(scene.bbox[1] <= lo[1]);
  CHECK(scene.bbox[2] >= hi[0]);
  CHECK(scene.bbox[3] >= hi[1]);
  CHECK(scene.bbox[0] >= lo[0] - eps);
  CHECK(scene.bbox[1] >= lo[1] - eps);
  CHECK(scene.bbox[2] <= hi[0] + eps);
  CHECK(scene.bbox[3] <= hi[1] + eps);
}

// the shapes on a body stay where the mechanism carries them: a link bar's ends on its nodes'
// pins, a pivot circle on its node's pivot (also when a control moves the pivot)
void check_attachments(const Design& d, const Scene& scene) {
  const kin::Mechanism& m = d.mech;
  for (const ScenePosition& pos : scene.positions)
    for (std::size_t f = 0; f < pos.cam_deg.size(); f += 7) {
      for (const kin::Connection& c : m.connections) {
        if (c.kind != ConnectionKind::link && c.kind != ConnectionKind::crank_slider) continue;
        const int bar = body_index(scene, c.name);
        const Posed pb = pose_at(pos, bar, f);
        const auto it = std::find_if(scene.shapes.begin(), scene.shapes.end(), [&](const SceneShape& s) {
          return s.body == bar && s.kind == SceneShape::Kind::polyline;
        });
        REQUIRE(it != scene.shapes.end());
        const Vector2d end_a = pb({it->xy[0], it->xy[1]}), end_b = pb({it->xy[2], it->xy[3]});
        CHECK((end_a - pose_at(pos, c.node_a, f)(c.pin_a)).norm() <= kContactAbs);
        CHECK((end_b - pose_at(pos, c.node_b, f)(c.pin_b)).norm() <= kContactAbs);
      }
      // every pivot circle of a turning node on ground or on the carrier a control turns
      for (std::size_t n = 1; n < m.nodes.size(); ++n) {
        const kin::Node& node = m.nodes[n];
        if (node.kind != NodeKind::rotational) continue;
        const auto it = std::find_if(scene.shapes.begin(), scene.shapes.end(), [&](const SceneShape& s) {
          return s.role == "pivot" && s.kind == SceneShape::Kind::circle && s.xy[0] == node.pivot.x() &&
                 s.xy[1] == node.pivot.y() && s.body != static_cast<int>(n);
        });
        REQUIRE(it != scene.shapes.end());
        CHECK((pose_at(pos, it->body, f)(node.pivot) - pose_at(pos, static_cast<int>(n), f)(node.pivot)).norm() <=
              kContactAbs);
      }
    }
}

}  // namespace

TEST_CASE("scene: every bundled design's contacts meet on both posed bodies and its lift is the sweep's",
          "[report][scene]") {
  for (const std::string& name : bundled_designs()) {
    INFO(name);
    const Design d = load(name);
    const report::SceneRequest request = request_of(d.mech);
    const Scene scene = report::build_scene(d.spec, d.mech, request);
    REQUIRE(scene.bodies.size() >= d.mech.nodes.size());
    for (std::size_t n = 0; n < d.mech.nodes.size(); ++n) CHECK(scene.bodies[n] == d.mech.nodes[n].name);
    CHECK(scene.output_body == d.mech.nodes[static_cast<std::size_t>(d.mech.output_node)].name);
    check_contacts_and_lift(d, scene, sweep_of(d.mech, request));
    check_shapes_and_bbox(scene);
    check_attachments(d, scene);
  }
}

TEST_CASE("scene: the lift of every frame is the lift_mm that camopt kinematics writes", "[report][scene]") {
  for (const std::string& name : bundled_designs()) {
    INFO(name);
    const Design d = load(name);
    const report::SceneRequest request = request_of(d.mech);
    const Scene scene = report::build_scene(d.spec, d.mech, request);
    test::TempDir dir;
    std::vector<std::string> args = {"kinematics", d.file, "--out", dir.path().string(), "--step", "1"};
    if (!d.mech.controls.empty()) {
      const kin::Control& c = d.mech.controls[0];
      args.push_back("--control");
      args.push_back(format_value(c.min, 17) + ":" + format_value(c.max, 17) + ":3");
    }
    REQUIRE(request.step_deg == 1.0);
    const test::RunResult run = test::run_camopt(args);
    REQUIRE(run.exit_code == test::cli_ok);
    const io::CsvTable csv = io::read_csv((dir.path() / "kinematics.csv").string());
    const bool angle = d.mech.variables[static_cast<std::size_t>(d.mech.nodes[d.mech.output_node].first_variable)].is_angle;
    const std::vector<double>& lift = csv.column(angle ? "lift_deg" : "lift_mm");
    const std::vector<double>& cam = csv.column(d.mech.driver_is_angle() ? "cam_deg" : "driver_mm");
    const std::vector<double>& control = csv.values[0];
    std::size_t row = 0;
    for (const ScenePosition& pos : scene.positions)
      for (std::size_t f = 0; f < pos.cam_deg.size(); ++f, ++row) {
        REQUIRE(row < csv.rows());
        INFO("row " << row);
        CHECK(control[row] == pos.control);
        CHECK(cam[row] == pos.cam_deg[f]);
        CHECK(std::abs(lift[row] - pos.lift_mm[f]) <= kLiftAbs);
      }
    CHECK(row == csv.rows());
  }
}

TEST_CASE("scene: the eccentric designs' followers move as the closed forms say", "[report][scene]") {
  SECTION("flat-faced follower: lift e (sin(theta + phase) - sin(phase))") {
    const Design d = load("eccentric_flat_follower.toml");
    const Scene scene = report::build_scene(d.spec, d.mech, request_of(d.mech));
    const oracles::EccentricFlatFollower o{20.0, 4.0, -90.0 * rad_per_deg};
    const int cam = body_index(scene, "cam"), follower = body_index(scene, "follower");
    const ScenePosition& pos = scene.positions.at(0);
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f) {
      const double theta = pos.cam_deg[f] * rad_per_deg;
      const Posed pf = pose_at(pos, follower, f);
      CHECK(std::abs(pf.ty - o.lift(theta)[0]) <= kClosedFormAbs);
      CHECK((pf.tx == 0.0 && pf.angle == 0.0));
      CHECK(std::abs(pose_at(pos, cam, f).angle - theta) <= kClosedFormAbs);
    }
  }
  SECTION("offset roller follower: the roller centre at R + r from the disc centre on x = 3") {
    const Design d = load("eccentric_offset_roller.toml");
    const Scene scene = report::build_scene(d.spec, d.mech, request_of(d.mech));
    const oracles::EccentricOffsetRoller o{20.0, 4.0, -97.1808 * rad_per_deg, 8.0, 3.0};
    const int follower = body_index(scene, "follower");
    const ScenePosition& pos = scene.positions.at(0);
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f) {
      const Vector2d centre = pose_at(pos, follower, f)(Vector2d(3.0, 23.8118));
      CHECK(std::abs(centre.x() - 3.0) <= kClosedFormAbs);
      CHECK(std::abs(centre.y() - o.centre_height(pos.cam_deg[f] * rad_per_deg)[0]) <= kClosedFormAbs);
    }
  }
  SECTION("oscillating roller follower: the arm angle of the effective four-bar") {
    const Design d = load("eccentric_oscillating_roller.toml");
    const Scene scene = report::build_scene(d.spec, d.mech, request_of(d.mech));
    oracles::EccentricOscillatingRoller o{20.0, 4.0, -90.0 * rad_per_deg, 8.0, Vector2d(-40, 24), 40.0, 1};
    o.branch = o.linkage().branch_through(o.phase, 0.0);  // the drawing: roller centre (0, 24), arm along +x
    REQUIRE(std::abs(o.arm_angle(0.0)[0]) <= kClosedFormAbs);
    const int arm = body_index(scene, "arm");
    const ScenePosition& pos = scene.positions.at(0);
    for (std::size_t f = 0; f < pos.cam_deg.size(); ++f)
      CHECK(std::abs(pose_at(pos, arm, f).angle - o.arm_angle(pos.cam_deg[f] * rad_per_deg)[0]) <= kClosedFormAbs);
  }
}

TEST_CASE("scene: the drawn profiles lie on the cam profiles and the valve spring has its installed length",
          "[report][scene]") {
  // the bucket tappet's lobe (asymmetric: a mirrored or turned outline is off its radii):
  // every vertex at the polar radius of its polar angle in the profile frame (turned by
  // +90 deg in the drawing), the whole turn covered in steps of at most 1 deg
  const Design bucket = load("bucket_tappet.toml");
  const Scene bucket_scene = report::build_scene(bucket.spec, bucket.mech, request_of(bucket.mech));
  const kin::CamProfile& lobe = bucket.mech.profiles.at(0);
  const int lobe_body = body_index(bucket_scene, "cam");
  const auto outline = std::find_if(bucket_scene.shapes.begin(), bucket_scene.shapes.end(), [&](const SceneShape& s) {
    return s.body == lobe_body && s.role == "profile";
  });
  REQUIRE(outline != bucket_scene.shapes.end());
  CHECK(outline->kind == SceneShape::Kind::polygon);
  REQUIRE(outline->xy.size() >= 2 * 360);
  double previous = 0.0, turned = 0.0, largest_step = 0.0;
  for (std::size_t k = 0; k < outline->xy.size(); k += 2) {
    const double x = outline->xy[k], y = outline->xy[k + 1];
    const double polar = std::fmod(std::atan2(y, x) - 90.0 * rad_per_deg + 4 * pi, 2 * pi);
    CHECK(std::abs(std::hypot(x, y) - lobe.radius_at(polar)) <= 1e-9);
    if (k > 0) {
      const double step = std::remainder(polar - previous, 2 * pi);
      largest_step = std::max(largest_step, std::abs(step));
      turned += step;
    }
    previous = polar;
  }
  CHECK(largest_step <= 1.0 * rad_per_deg + 1e-12);
  CHECK(turned + largest_step >= 2 * pi - 1e-9);  // with the closing edge, once round
  const Design d = load("roller_finger_follower.toml");
  const Scene scene = report::build_scene(d.spec, d.mech, request_of(d.mech));
  const int valve = body_index(scene, "valve");
  // the valve spring from its seat on ground to the retainer on the valve, 38.8 mm installed
  const auto spring = std::find_if(scene.shapes.begin(), scene.shapes.end(),
                                   [&](const SceneShape& s) { return s.kind == SceneShape::Kind::spring; });
  REQUIRE(spring != scene.shapes.end());
  CHECK(spring->body == 0);
  CHECK(spring->body_b == valve);
  CHECK_REL(std::hypot(spring->xy[2] - spring->xy[0], spring->xy[3] - spring->xy[1]), 38.8, 1e-12);
  // the valve opens along -y: its seat end is below the tip
  CHECK(spring->xy[1] < spring->xy[3]);
}

TEST_CASE("scene: a request outside the design's control range or with a bad step is an input error",
          "[report][scene]") {
  const Design d = load("cvvl_swing_cam.toml");
  report::SceneRequest r = request_of(d.mech);
  r.controls = {17.0};
  CHECK_THROWS_WITH(report::build_scene(d.spec, d.mech, r), Catch::Contains("outside control 'shaft' range [0, 16]"));
  r = request_of(d.mech);
  r.step_deg = 0.0;
  CHECK_THROWS_WITH(report::build_scene(d.spec, d.mech, r), Catch::Contains("scene step_deg = 0 must be > 0"));
  const Design plain = load("four_bar.toml");
  r = request_of(plain.mech);
  r.controls = {5.0};
  CHECK_THROWS_WITH(report::build_scene(plain.spec, plain.mech, r), Catch::Contains("has no [[control]]"));
}
