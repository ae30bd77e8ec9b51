// the optimiser's loads from the valve motion (virtual work on the downstream part, driven
// by the valve) against the rigid model of camopt dynamics (Lagrange multipliers of the
// whole mechanism driven by the cam: an independent formulation) on bundled designs, case
// by case (springs, dampers, inertia, gas), and their gradients against central differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/opt/cam_contact.hpp"
#include "camopt/opt/downstream_loads.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

// a bundled design without friction (the optimiser's loads leave it out), with lash closed,
// spring dampers and a gas force on the valve so every load case is exercised
DesignSpec frictionless(const std::string& name) {
  DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name);
  for (auto& c : d.connections) {
    c.lash_mm = 0.0;
    c.friction_coefficient.reset();
  }
  for (auto& s : d.springs) s.damping_N_s_per_m = 40.0;
  GasForceSpec gas;
  gas.node = d.output_node;
  gas.crank_angle_deg = {0, 200, 260, 400, 720};
  gas.force_N = {0, 0, 180, 20, 0};
  d.gas_forces = {gas};
  return d;
}

int connection_index(const DesignSpec& d, const std::string& name) {
  for (int i = 0; i < static_cast<int>(d.connections.size()); ++i)
    if (d.connections[static_cast<std::size_t>(i)].name == name) return i;
  return -1;
}

}  // namespace

TEST_CASE("downstream loads from the valve motion match the rigid model case by case", "[opt][loads]") {
  for (const char* name : {"roller_finger_follower.toml", "bucket_tappet.toml", "rocker_arm.toml"}) {
    INFO(name);
    const DesignSpec d = frictionless(name);
    const kin::Mechanism mech = kin::compile(d);
    const dynamics::Model model = dynamics::compile_dynamics(d, mech);
    dynamics::RigidWorkspace rws(mech, model);
    opt::CamContactModel contact(d, {});
    auto cws = contact.make_workspace();
    opt::DownstreamLoads loads(d, "rotational");
    auto lws = loads.make_workspace(contact.controls());
    REQUIRE(loads.contact_names().front() == contact.connection());
    REQUIRE(loads.spring_names().size() == d.springs.size());
    const int valve = mech.node_index(d.output_node);
    std::vector<opt::ContactLoad> out;
    int checked = 0;
    double largest = 0;
    for (double deg = 0.0; deg < 360.0; deg += 2.5) {
      const double th = deg * std::numbers::pi / 180.0;
      REQUIRE(dynamics::solve_rigid(mech, model, rws, th).ok());
      const auto& v = rws.kin.vars[static_cast<std::size_t>(mech.nodes[static_cast<std::size_t>(valve)].first_variable)];
      const double lift[3] = {v.derivative(0), v.derivative(1), v.derivative(2)};
      if (lift[0] < 1e-6) continue;  // on the seat the valve's load goes to the seat
      opt::ContactQuantities q;
      REQUIRE(contact.evaluate(th, lift, cws, q).ok());
      REQUIRE(loads.evaluate(th, lift, lws, out).ok());
      REQUIRE(out.size() == loads.contact_names().size());
      INFO("cam " << deg << " deg, lift " << lift[0]);
      for (std::size_t k = 0; k < out.size(); ++k) {
        const int c = connection_index(d, loads.contact_names()[k]);
        // the cam contact: normal force = force ratio x generalized force; a contact behind
        // it on a flat valve tip normal to the valve: its normal force is the valve's load
        const double ratio = k == 0 ? q.force_ratio.v : 1.0;
        const double scale = std::max(1.0, std::abs(rws.force(c, 2)));
        CHECK_ABS(ratio * out[k].inertia.v, rws.force(c, 0), tol::kOptLoadRel * scale);
        CHECK_ABS(ratio * out[k].damping.v, rws.force(c, rws.damping_case()), tol::kOptLoadRel * scale);
        double springs = 0;
        for (std::size_t s = 0; s < out[k].spring.size(); ++s) {
          CHECK_ABS(ratio * out[k].spring[s].v, rws.force(c, 2 + static_cast<int>(s)), tol::kOptLoadRel * scale);
          springs += out[k].spring[s].v;
        }
        CHECK_ABS(ratio * (out[k].statics.v - springs), rws.force(c, 1), tol::kOptLoadRel * scale);
        largest = std::max(largest, std::abs(rws.force(c, 1)));
      }
      ++checked;
    }
    CHECK(checked > 20);
    CHECK(largest > 10.0);  // the gas case was exercised
  }
}

TEST_CASE("downstream load gradients match central differences", "[opt][loads]") {
  const DesignSpec d = frictionless("roller_finger_follower.toml");
  opt::DownstreamLoads loads(d, "rotational");
  auto lws = loads.make_workspace({});
  std::vector<opt::ContactLoad> a, b, c0;
  const double th = 2.9;
  const double lift[3] = {4.1, 6.3, -21.0};
  REQUIRE(loads.evaluate(th, lift, lws, c0).ok());
  const double h[3] = {1e-5, 1e-4, 1e-3};
  for (int k = 0; k < 3; ++k) {
    double lp[3] = {lift[0], lift[1], lift[2]}, lm[3] = {lift[0], lift[1], lift[2]};
    lp[k] += h[k];
    lm[k] -= h[k];
    REQUIRE(loads.evaluate(th, lp, lws, a).ok());
    REQUIRE(loads.evaluate(th, lm, lws, b).ok());
    for (std::size_t j = 0; j < c0.size(); ++j) {
      INFO("direction " << k << ", contact " << j);
      auto fd = [&](const opt::Grad3 opt::ContactLoad::*f) { return ((a[j].*f).v - (b[j].*f).v) / (2 * h[k]); };
      CHECK_ABS(c0[j].statics.d[k], fd(&opt::ContactLoad::statics), tol::kOptStaticsFdAbs);
      CHECK_ABS(c0[j].damping.d[k], fd(&opt::ContactLoad::damping), tol::kOptDampingFdAbs);
      CHECK_ABS(c0[j].inertia.d[k], fd(&opt::ContactLoad::inertia), tol::kOptInertiaFdAbs);
    }
  }
  CHECK(1e3 * c0[0].inertia.d[2] > 0.02);  // the generalized mass at the valve [kg]: valve + finger
}
