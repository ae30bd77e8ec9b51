// assembly analysis of compile() and its outcomes: under- and over-constrained designs are
// rejected with the names at fault, the solve order follows the dependencies (not the
// order of declaration), coupled clusters are solved simultaneously and still match the
// four-bar oracle, and a link that cannot close reports cannot_assemble with its name and
// the driver angle.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;
using Catch::Matchers::Contains;

namespace {


Vector2d polar(double r, double a) { return {r * std::cos(a), r * std::sin(a)}; }
Vec2 v2(const Vector2d& p) { return {p.x(), p.y()}; }

// the grashof crank-rocker of the closed-form tests
const oracles::FourBar kFourBar{Vector2d(0, 0), Vector2d(60, 0), 20, 55, 45, 1};
constexpr double kCrankDrawing = 30 * deg;

std::string message_of(const DesignSpec& d) {
  try {
    (void)kin::compile(d);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> unknown_names(const kin::Mechanism& m, const kin::SolveStep& s) {
  std::vector<std::string> names;
  for (int v : s.unknowns) names.push_back(m.variables[static_cast<std::size_t>(v)].name);
  return names;
}

bool has(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

TEST_CASE("assembly: a node connected to nothing is under-constrained", "[kinematics][assembly]") {
  DesignSpec d = design("loose", "cam", "tappet");
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, 20}, {0, 1}), rotational("idler", {40, 0})};
  d.profiles = {eccentric_profile("disc", 20, 4)};
  d.connections = {
      contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, 0), line_surface("tappet", {0, 20}, {0, -1}))};
  const std::string msg = message_of(d);
  INFO(msg);
  CHECK_THAT(msg, Contains("under-constrained") && Contains("'idler'") && Contains("'cam'"));
  CHECK_THAT(msg, !Contains("'tappet'"));

  // a floating plate on a single link keeps two of its three freedoms
  DesignSpec f = design("plate", "crank", "plate");
  f.nodes = {rotational("crank", {0, 0}), floating("plate")};
  f.connections = {link("rod", "crank", {20, 0}, "plate", {60, 0})};
  const std::string fmsg = message_of(f);
  INFO(fmsg);
  CHECK_THAT(fmsg, Contains("under-constrained") && Contains("plate."));
}

TEST_CASE("assembly: a redundant link between two geared nodes is over-constrained", "[kinematics][assembly]") {
  // two shafts already geared 1:-1, then tied again by a link: two equations for one unknown
  DesignSpec d = design("geared_and_tied", "a", "b");
  d.nodes = {rotational("a", {0, 0}), rotational("b", {50, 0})};
  ConnectionSpec gear;
  gear.name = "timing";
  gear.kind = ConnectionKind::gear;
  gear.node_a = "a";
  gear.node_b = "b";
  gear.ratio = -1.0;
  d.connections = {gear, link("tie_rod", "a", {0, 20}, "b", {50, -20})};
  const std::string msg = message_of(d);
  INFO(msg);
  CHECK_THAT(msg, Contains("over-constrained"));
  CHECK((msg.find("'tie_rod'") != std::string::npos || msg.find("'timing'") != std::string::npos));
  // either connection alone is fine
  d.connections = {gear};
  CHECK_NOTHROW(kin::compile(d));
}

TEST_CASE("assembly: a four-bar followed by a contact is solved in dependency order", "[kinematics][assembly]") {
  // the rocker carries a pad (radius 15) pressing a valve whose flat tip faces up; the
  // contact is declared first, but it needs the rocker, so the link is solved first.
  // closed form: the pad centre C turns with the rocker about O4; the valve (travel -y)
  // sits under it: valve = C0.y - C(theta).y, differentiated through the rocker angle q:
  //   (C.y)' = c cos(b) q',  (C.y)'' = c (cos(b) q'' - sin(b) q'^2),
  //   (C.y)''' = c (cos(b) q''' - 3 sin(b) q' q'' - cos(b) q'^3),  b = b0 + q.
  const double pad = 15.0;
  const Vector2d O4 = kFourBar.rocker_pivot;
  const Vector2d C0 = O4 + polar(30.0, -70 * deg);
  const double th4_0 = kFourBar.solve(kCrankDrawing).rocker_angle[0];
  const Vector2d A0 = polar(kFourBar.crank, kCrankDrawing), B0 = O4 + polar(kFourBar.rocker, th4_0);
  DesignSpec d = design("rocker_valve", "crank", "valve");
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", v2(O4)),
             translational("valve", {C0.x(), C0.y() - pad}, {0, -1})};
  d.connections = {contact("pad_valve", circle_surface("rocker", v2(C0), pad, false),
                           line_surface("valve", {C0.x(), C0.y() - pad}, {0, 1})),
                   link("coupler", "crank", v2(A0), "rocker", v2(B0))};
  const auto m = kin::compile(d);
  REQUIRE(m.plan.size() == 2);
  CHECK(m.connections[static_cast<std::size_t>(m.plan[0].connections.at(0))].name == "coupler");
  CHECK(m.plan[0].method == kin::StepMethod::link_closed_form);
  CHECK(m.plan[0].output_node == m.node_index("rocker"));
  CHECK(unknown_names(m, m.plan[0]) == std::vector<std::string>{"rocker"});
  CHECK(m.connections[static_cast<std::size_t>(m.plan[1].connections.at(0))].name == "pad_valve");
  // a pad on a flat valve tip with the valve unknown: the closure is linear in the travel
  CHECK(m.plan[1].method == kin::StepMethod::contact_line_closed_form);
  CHECK(has(unknown_names(m, m.plan[1]), "valve"));
  CHECK(has(unknown_names(m, m.plan[1]), "pad_valve.u_b"));
  const std::string text = kin::describe(m);
  INFO(text);
  CHECK_THAT(text, Contains("1. coupler -> rocker  (closed form, branch"));
  CHECK_THAT(text, Contains("2. pad_valve -> ") && Contains("(closed form)"));

  kin::Workspace ws(m);
  const double b0 = std::atan2(C0.y() - O4.y(), C0.x() - O4.x()), c = (C0 - O4).norm();
  SweepCompare valve("valve under the rocker", false), rocker("rocker", true);
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    const Status st = kin::solve(m, ws, t, {});
    INFO(st.str());
    REQUIRE(st.ok());
    Motion q = kFourBar.solve(kCrankDrawing + t).rocker_angle;
    q[0] = oracles::wrap_angle(q[0] - th4_0);
    rocker.add(t, motion_of(node_jet(m, ws, "rocker")), q);
    const double b = b0 + q[0], cb = std::cos(b), sb = std::sin(b);
    const Motion cy = {O4.y() + c * sb, c * cb * q[1], c * (cb * q[2] - sb * q[1] * q[1]),
                       c * (cb * q[3] - 3 * sb * q[1] * q[2] - cb * q[1] * q[1] * q[1])};
    valve.add(t, motion_of(node_jet(m, ws, "valve")), {C0.y() - cy[0], -cy[1], -cy[2], -cy[3]});
  }
  CHECK_COMPARISONS(rocker.compare());
  CHECK_COMPARISONS(valve.compare());
}

TEST_CASE("assembly: a floating rocker held by two ground links is a coupled cluster", "[kinematics][assembly]") {
  // the rocker as a floating plate: two links from ground pins G1, G2 to its pivot point O4
  // pin that point in place, the coupler drives its pin B. three equations in (x, y, phi),
  // all coupled: one block solved simultaneously; phi must follow the four-bar oracle.
  const Vector2d O4 = kFourBar.rocker_pivot, G1 = O4 + Vector2d(-25, -30), G2 = O4 + Vector2d(28, -22);
  const double th4_0 = kFourBar.solve(kCrankDrawing).rocker_angle[0];
  const Vector2d A0 = polar(kFourBar.crank, kCrankDrawing), B0 = O4 + polar(kFourBar.rocker, th4_0);
  DesignSpec d = design("floating_rocker", "crank", "plate");
  d.nodes = {rotational("crank", {0, 0}), floating("plate")};
  d.connections = {link("hold_1", "ground", v2(G1), "plate", v2(O4)), link("hold_2", "ground", v2(G2), "plate", v2(O4)),
                   link("coupler", "crank", v2(A0), "plate", v2(B0))};
  const auto m = kin::compile(d);
  REQUIRE(m.plan.size() == 1);
  CHECK(m.plan[0].connections.size() == 3);
  CHECK(m.plan[0].method == kin::StepMethod::implicit);
  const auto names = unknown_names(m, m.plan[0]);
  CHECK(names.size() == 3);
  CHECK((has(names, "plate.x") && has(names, "plate.y") && has(names, "plate.phi")));
  CHECK_THAT(kin::describe(m), Contains("(coupled cluster, Broyden/Newton)"));

  const auto& plate = m.nodes[static_cast<std::size_t>(m.node_index("plate"))];
  kin::Workspace ws(m);
  SweepCompare phi("floating rocker angle", true);
  ScalarCompare pivot("plate's O4 away from the ground pivot [mm]");
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    const Status st = kin::solve(m, ws, t, {});
    INFO(st.str());
    REQUIRE(st.ok());
    const auto* v = &ws.vars[static_cast<std::size_t>(plate.first_variable)];
    Motion q = kFourBar.solve(kCrankDrawing + t).rocker_angle;
    q[0] = oracles::wrap_angle(q[0] - th4_0);
    phi.add(t, motion_of(v[2]), q);
    // the plate's pose p = (x, y) + ref + R(phi) (p_drawing - ref) keeps O4 in place
    const Vector2d ref = plate.reference, r = O4 - ref;
    const double a = v[2].value();
    const Vector2d o4 = Vector2d(v[0].value(), v[1].value()) + ref +
                        Vector2d(std::cos(a) * r.x() - std::sin(a) * r.y(), std::sin(a) * r.x() + std::cos(a) * r.y());
    pivot.add(t, (o4 - O4).norm(), 0.0);
  }
  CHECK_COMPARISONS(phi.compare());
  CHECK_SERIES(pivot.compare(0.0, kPoseAbs));
}

TEST_CASE("assembly: a floating coupler pinned by link pairs closes the four-bar simultaneously",
          "[kinematics][assembly]") {
  // the coupler as a floating body; two links from the crank pin A to coupler points P1, P2
  // fix A in the coupler (a rigid triangle), two from the rocker pin B to P3, P4 fix B: four
  // equations in the coupler's (x, y, phi) and the rocker angle, one 4x4 cluster. the rocker
  // and the coupler angle must follow the four-bar with coupler |A - B|.
  const double th4_0 = kFourBar.solve(kCrankDrawing).rocker_angle[0];
  const double th3_0 = kFourBar.solve(kCrankDrawing).coupler_angle[0];
  const Vector2d O4 = kFourBar.rocker_pivot;
  const Vector2d A0 = polar(kFourBar.crank, kCrankDrawing), B0 = O4 + polar(kFourBar.rocker, th4_0);
  const Vector2d P1 = A0 + polar(10, th3_0 + 50 * deg), P2 = A0 + polar(10, th3_0 - 50 * deg);
  const Vector2d P3 = B0 + polar(10, th3_0 + 130 * deg), P4 = B0 + polar(10, th3_0 - 130 * deg);
  DesignSpec d = design("floating_coupler", "crank", "rocker");
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", v2(O4)), floating("coupler")};
  d.connections = {link("a1", "crank", v2(A0), "coupler", v2(P1)), link("a2", "crank", v2(A0), "coupler", v2(P2)),
                   link("b1", "rocker", v2(B0), "coupler", v2(P3)), link("b2", "rocker", v2(B0), "coupler", v2(P4))};
  const auto m = kin::compile(d);
  REQUIRE(m.plan.size() == 1);
  CHECK(m.plan[0].connections.size() == 4);
  CHECK(m.plan[0].unknowns.size() == 4);
  CHECK(m.plan[0].method == kin::StepMethod::implicit);

  const int coupler_phi = m.nodes[static_cast<std::size_t>(m.node_index("coupler"))].first_variable + 2;
  kin::Workspace ws(m);
  SweepCompare rocker("rocker through a floating coupler", true), coupler("floating coupler angle", true);
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    const Status st = kin::solve(m, ws, t, {});
    INFO(st.str());
    REQUIRE(st.ok());
    const auto s = kFourBar.solve(kCrankDrawing + t);
    Motion q4 = s.rocker_angle, q3 = s.coupler_angle;
    q4[0] = oracles::wrap_angle(q4[0] - th4_0);
    q3[0] = oracles::wrap_angle(q3[0] - th3_0);
    rocker.add(t, motion_of(node_jet(m, ws, "rocker")), q4);
    coupler.add(t, motion_of(ws.vars[static_cast<std::size_t>(coupler_phi)]), q3);
  }
  CHECK_COMPARISONS(rocker.compare());
  CHECK_COMPARISONS(coupler.compare());
}

TEST_CASE("assembly: a link that cannot close reports cannot_assemble with its name and the angle",
          "[kinematics][assembly]") {
  // crank 30 on ground 60 with coupler 40 + rocker 25: the crank pin leaves the rocker's
  // reach |O4 - A| <= 65 once cos(theta) < (30^2 + 60^2 - 65^2)/(2 30 60) = 275/3600, i.e.
  // past 85.62 deg: the first failing point of a 0.5 deg sweep is 86 deg
  const oracles::FourBar bad{Vector2d(0, 0), Vector2d(60, 0), 30, 40, 25, 1};
  const double limit = std::acos(275.0 / 3600.0) / deg;
  REQUIRE_ABS(limit, 85.62, kPrintedLimitAbs);
  const double th4_0 = bad.solve(0.0).rocker_angle[0];
  DesignSpec d = design("too_long_crank", "crank", "rocker");
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", {60, 0})};
  d.connections = {link("coupler", "crank", {30, 0}, "rocker", v2(Vector2d(60, 0) + polar(25, th4_0)))};
  const auto m = kin::compile(d);

  kin::Workspace ws(m);
  double failed_at = -1.0;
  Status failure;
  for (int i = 0; i < kSweepPoints && failed_at < 0; ++i) {
    const double t = i * kSweepStepDeg;
    const Status st = kin::solve(m, ws, t * deg, {});
    if (!st.ok()) failed_at = t, failure = st;
  }
  CHECK(failed_at == 86.0);
  CHECK(failure.code == StatusCode::cannot_assemble);
  INFO(failure.str());
  CHECK_THAT(failure.message, Contains("coupler"));
  CHECK_THAT(failure.where, Contains("86 deg"));
  CHECK_THAT(failure.str(), Contains("coupler") && Contains("86 deg"));

  // a sweep stops there with the same status, the points before it solved
  kin::SweepSpec spec;
  spec.step = kSweepStepDeg;
  const auto r = kin::sweep(m, spec);
  CHECK(r.positions[0].status.code == StatusCode::cannot_assemble);
  CHECK_THAT(r.positions[0].status.where, Contains("86 deg"));
}

TEST_CASE("mechanism: a compiled mechanism reports the design's name and file and its driver defaults",
          "[kinematics][assembly]") {
  DesignSpec d = design("facts", "cam", "tappet");
  d.file = "designs/facts.toml";
  d.driver.start_deg = -20.0;
  d.driver.stop_deg = 340.0;
  d.driver.step_deg = 0.25;
  d.driver.crank_per_cam = 1.0;
  d.controls = {ControlSpec{"shaft", "deg", -10.0, 30.0, 7.5, {}}, ControlSpec{"shift", "mm", 0.0, 2.0, 1.25, {}}};
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, 20}, {0, 1})};
  d.profiles = {lobe_table("unused"), eccentric_profile("disc", 20, 4)};
  d.connections = {
      contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, 0), line_surface("tappet", {0, 20}, {0, -1}))};
  const kin::Mechanism m = kin::compile(d);
  CHECK(m.name == "facts");
  CHECK(m.file == "designs/facts.toml");
  CHECK(m.driver.start == -20.0);
  CHECK(m.driver.stop == 340.0);
  CHECK(m.driver.step == 0.25);
  CHECK(m.driver.crank_per_cam == 1.0);
  CHECK(m.default_controls() == std::vector<double>{7.5, 1.25});
  // the disc compiles to a circle surface that still names the profile it is made from
  const kin::Connection& c = m.connections[0];
  CHECK(c.surface_a.kind == kin::SurfaceKind::point);
  REQUIRE(c.surface_a.source_profile == 1);
  CHECK(m.profiles[1].name() == "disc");
  CHECK(c.surface_b.source_profile == -1);
}
