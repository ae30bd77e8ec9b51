#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::test::tol;

namespace {
DesignSpec eccentric_flat(double R, double e) {
  DesignSpec d;
  d.name = "ecc_flat";
  d.output_node = "follower";
  d.driver.node = "cam";
  NodeSpec cam;
  cam.name = "cam";
  cam.kind = NodeKind::rotational;
  NodeSpec fol;
  fol.name = "follower";
  fol.kind = NodeKind::translational;
  fol.origin_mm = {0, R};
  fol.direction = {0, 1};
  d.nodes = {cam, fol};
  ProfileSpec p;
  p.name = "disc";
  p.form = ProfileForm::eccentric;
  p.disc_radius_mm = R;
  p.eccentricity_mm = e;
  d.profiles = {p};
  ConnectionSpec c;
  c.name = "contact";
  c.kind = ConnectionKind::contact;
  c.surface_a.node = "cam";
  c.surface_a.shape = SurfaceShape::profile;
  c.surface_a.profile = "disc";
  c.surface_b.node = "follower";
  c.surface_b.shape = SurfaceShape::line;
  c.surface_b.origin_mm = {0, R};
  c.surface_b.normal = {0, -1};
  d.connections = {c};
  return d;
}
}  // namespace

TEST_CASE("eccentric disc with flat follower matches s = e sin(theta)", "[kinematics][smoke]") {
  const double R = 20, e = 5;
  const auto mech = kin::compile(eccentric_flat(R, e));
  kin::Workspace ws(mech);
  kin::Request rq;
  rq.contacts = true;
  for (int i = 0; i <= 720; ++i) {
    const double th = i * camopt::pi / 360.0;
    auto st = kin::solve(mech, ws, th, rq);
    REQUIRE(st.ok());
    const auto& q = ws.vars[mech.nodes[mech.output_node].first_variable];
    CHECK_ABS(q.value(), e * std::sin(th), kEccentricSolveAbs);
    CHECK_ABS(q.derivative(1), e * std::cos(th), kEccentricRateAbs);
    CHECK_ABS(q.derivative(2), -e * std::sin(th), kEccentricRateAbs);
    CHECK_ABS(q.derivative(3), -e * std::cos(th), kEccentricRateAbs);
  }
}

TEST_CASE("solve: a bad request or control count is an InputError naming the field", "[kinematics][solver]") {
  const auto mech = kin::compile(eccentric_flat(20, 5));
  kin::Workspace ws(mech);
  CHECK_THROWS_AS((void)kin::solve(mech, ws, 0.0, kin::Request{-1, false}), InputError);
  CHECK_THROWS_WITH((void)kin::solve(mech, ws, 0.0, kin::Request{-1, false}),
                    Catch::Contains("request.derivative_order = -1 must be in [0, 3]"));
  CHECK_THROWS_WITH((void)kin::solve(mech, ws, 0.0, kin::Request{0, true}),
                    Catch::Contains("request.contacts = true needs request.derivative_order >= 1"));
  const std::vector<double> one_control = {1.0};
  CHECK_THROWS_AS(ws.set_controls(one_control), InputError);
  CHECK_THROWS_WITH(ws.set_controls(one_control),
                    Catch::Contains("control position: 1 value(s) given, the mechanism has 0 control(s)"));
}

TEST_CASE("workspace: a copy continues exactly as the original and a moved-from one can be assigned to",
          "[kinematics][solver]") {
  // the CVVL: blocks solved simultaneously, whose warm starts and step history the copy carries
  const auto mech = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml"));
  const int out = mech.nodes[mech.output_node].first_variable;
  kin::Workspace ws(mech);
  for (int deg = 0; deg <= 150; deg += 2) REQUIRE(kin::solve(mech, ws, deg * camopt::rad_per_deg, {3, false}).ok());
  // the next point from the copy is the original's to the bit
  kin::Workspace copy = ws;
  REQUIRE(kin::solve(mech, ws, 152 * camopt::rad_per_deg, {3, false}).ok());
  REQUIRE(kin::solve(mech, copy, 152 * camopt::rad_per_deg, {3, false}).ok());
  CHECK(copy.values() == ws.values());
  for (int k = 0; k <= 3; ++k) CHECK(copy.vars[out].derivative(k) == ws.vars[out].derivative(k));
  CHECK(copy.pivots() == ws.pivots());
  // a workspace moved from takes an assignment and solves on, like the original
  kin::Workspace moved = std::move(copy);
  copy = ws;
  REQUIRE(kin::solve(mech, ws, 154 * camopt::rad_per_deg, {3, false}).ok());
  REQUIRE(kin::solve(mech, copy, 154 * camopt::rad_per_deg, {3, false}).ok());
  REQUIRE(kin::solve(mech, moved, 154 * camopt::rad_per_deg, {3, false}).ok());
  CHECK(copy.values() == ws.values());
  CHECK(moved.values() == ws.values());
  CHECK(ws.values()[out] == ws.vars[out].value());
}
