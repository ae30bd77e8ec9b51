// the optimiser's closed-form contact quantities (envelope theory on the valve motion)
// against the kinematic solver's contact outputs on the same design (an independent
// formulation: the solver intersects the actual profile with the follower), and their
// gradients against central finite differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/opt/cam_contact.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

DesignSpec load(const std::string& name) {
  DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name);
  for (auto& c : d.connections) c.lash_mm = 0.0;
  return d;
}

struct Case {
  const char* design;
  double tol_angle;  // [rad]
};

}  // namespace

TEST_CASE("cam contact quantities from the valve motion match the kinematic solver", "[opt][contact]") {
  for (const char* name : {"roller_finger_follower.toml", "bucket_tappet.toml", "rocker_arm.toml",
                           "eccentric_offset_roller.toml", "eccentric_oscillating_roller.toml",
                           "eccentric_flat_follower.toml"}) {
    INFO(name);
    const DesignSpec d = load(name);
    const kin::Mechanism mech = kin::compile(d);
    kin::Workspace ws(mech);
    opt::CamContactModel model(d, {});
    auto mws = model.make_workspace();
    const int valve = mech.node_index(d.output_node);
    int conn = -1;
    for (int i = 0; i < static_cast<int>(d.connections.size()); ++i)
      if (d.connections[i].name == model.connection()) conn = i;
    REQUIRE(conn >= 0);
    const bool profile_on_a = d.connections[conn].surface_a.shape == SurfaceShape::profile;
    double checked = 0;
    for (double deg = 0.0; deg < 360.0; deg += 2.5) {
      const double th = deg * std::numbers::pi / 180.0;
      REQUIRE(kin::solve(mech, ws, th, {3, true}).ok());
      const auto& v = ws.vars[mech.nodes[valve].first_variable];
      const double lift[3] = {v.derivative(0), v.derivative(1), v.derivative(2)};
      opt::ContactQuantities q;
      REQUIRE(model.evaluate(th, lift, mws, q).ok());
      const kin::ContactState& cs = ws.contacts[conn];
      INFO("cam " << deg << " deg");
      CHECK_ABS(q.pressure_angle.v, cs.pressure_angle, tol::kOptPressureAngleAbs);
      const double cam_curv = profile_on_a ? cs.curvature_a : cs.curvature_b;
      // radius of curvature of the cam: compare curvatures (flat parts give 1/rho ~ 0)
      CHECK_NEAR(1.0 / q.cam_radius.v, cam_curv, tol::kOptContactRel, tol::kOptContactRel);
      if (model.follower_shape() == opt::FollowerShape::roller) {
        CHECK_ABS(q.roller_speed.v, cs.roller_speed, tol::kOptRollerSpeedAbs);
      } else {
        CHECK_ABS(std::abs(q.sliding.v), std::abs(cs.sliding), tol::kOptContactRel);
      }
      // the solver's entrainment is measured along its own tangent: compare magnitudes, and
      // the sign relative to the sliding speed (pads, flat faces)
      CHECK_NEAR(std::abs(q.entrainment.v), std::abs(cs.entrainment), tol::kOptContactRel, tol::kOptContactRel);
      if (model.follower_shape() != opt::FollowerShape::roller && std::abs(cs.sliding) > 1e-6 && std::abs(cs.entrainment) > 1e-6)
        CHECK((q.entrainment.v * q.sliding.v > 0) == ((profile_on_a ? 1.0 : -1.0) * cs.entrainment * cs.sliding > 0));
      ++checked;
    }
    CHECK(checked == 144);
  }
}

TEST_CASE("cam contact gradients match central finite differences", "[opt][contact]") {
  for (const char* name : {"roller_finger_follower.toml", "bucket_tappet.toml", "eccentric_oscillating_roller.toml"}) {
    INFO(name);
    const DesignSpec d = load(name);
    const kin::Mechanism mech = kin::compile(d);
    kin::Workspace ws(mech);
    opt::CamContactModel model(d, {});
    auto mws = model.make_workspace();
    const int valve = mech.node_index(d.output_node);
    for (double deg : {95.0, 140.0, 170.0, 215.0}) {
      const double th = deg * std::numbers::pi / 180.0;
      REQUIRE(kin::solve(mech, ws, th, {3, false}).ok());
      const auto& v = ws.vars[mech.nodes[valve].first_variable];
      const double lift[3] = {v.derivative(0), v.derivative(1), v.derivative(2)};
      opt::ContactQuantities q;
      REQUIRE(model.evaluate(th, lift, mws, q).ok());
      const double scale[3] = {1e-4, 1e-4, 1e-4};
      for (int k = 0; k < 3; ++k) {
        double lp[3] = {lift[0], lift[1], lift[2]}, lm[3] = {lift[0], lift[1], lift[2]};
        lp[k] += scale[k];
        lm[k] -= scale[k];
        opt::ContactQuantities qp, qm;
        REQUIRE(model.evaluate(th, lp, mws, qp).ok());
        REQUIRE(model.evaluate(th, lm, mws, qm).ok());
        auto fd = [&](auto field) { return ((qp.*field).v - (qm.*field).v) / (2 * scale[k]); };
        INFO("cam " << deg << " deg, direction " << k);
        for (auto field : {&opt::ContactQuantities::pressure_angle, &opt::ContactQuantities::cam_radius,
                           &opt::ContactQuantities::inverse_radius_sum, &opt::ContactQuantities::roller_speed,
                           &opt::ContactQuantities::sliding, &opt::ContactQuantities::force_ratio}) {
          const double exact = (q.*field).d[k];
          CHECK_NEAR(exact, fd(field), tol::kOptContactFdAbs * (1.0 + std::abs((q.*field).v)), tol::kOptContactFdRel);
        }
      }
    }
  }
}
