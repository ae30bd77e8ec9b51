#include "camopt/synthesis/lever_path.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/detail/radial_probe.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"
#include "support/compare.hpp"

using namespace camopt;

namespace {

struct Upstream {
  DesignSpec spec;
  kin::Mechanism mech;
  int lever = -1;
  explicit Upstream(const std::string& design) {
    DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + design + ".toml");
    for (auto& c : d.connections) c.lash_mm = 0.0;
    const synthesis::MechanismCut cut = synthesis::cut_mechanism(d, "swing", d.output_node);
    spec = cut.upstream;
    mech = kin::compile(spec);
    lever = mech.node_index(cut.cam_node);
  }
};

}  // namespace

TEST_CASE("lever path: the Valvetronic lever moved by its input cam matches the solve of its whole contact cluster",
          "[synthesis][lever_path]") {
  // independent formulation: the kinematics solves the lever with its three contacts at
  // once (newton on the cluster, implicit jets); the lever path scans it once against a
  // probe on its cam roller and solves only the cam contact at each angle
  const Upstream v("valvetronic");
  for (double control : {0.0, 30.0, 60.0}) {
    synthesis::LeverPath path;
    REQUIRE(synthesis::build_lever_path(v.spec, v.mech, v.lever, std::vector<double>{control}, path).ok());
    REQUIRE(path.contact >= 0);
    kin::Workspace whole(v.mech);
    const std::vector<double> controls{control};
    whole.set_controls(controls);
    REQUIRE(kin::solve(v.mech, whole, 0.0, {3, false}).ok());
    synthesis::LeverState state;
    synthesis::lever_path_state(path, v.mech, whole, 0.0, state);
    const int first = v.mech.nodes[static_cast<std::size_t>(v.lever)].first_variable;
    // each order over the revolution and the lever's three variables [mm, rad]
    std::vector<test::Series> order;
    for (int d = 0; d < 4; ++d)
      order.emplace_back("lever d^" + std::to_string(d) + " at control " + std::to_string(control), "cam [deg]");
    for (int deg = 1; deg <= 360; ++deg) {
      const double theta = deg * pi / 180;
      INFO("control " << control << " deg, cam " << deg << " deg");
      REQUIRE(kin::solve(v.mech, whole, theta, {3, false}).ok());
      Jet<3> lever[3];
      REQUIRE(synthesis::lever_at(path, v.mech, whole, theta, state, lever).ok());
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 4; ++d)
          order[static_cast<std::size_t>(d)].add(deg, lever[k].derivative(d),
                                                 whole.vars[static_cast<std::size_t>(first + k)].derivative(d));
    }
    CHECK_SERIES(order[0].compare({.abs = test::tol::kLeverPoseAbs}));
    for (std::size_t d = 1; d <= 3; ++d) CHECK_SERIES(order[d].compare({.rel = test::tol::kLeverRateRel}));
  }
}

TEST_CASE("lever path: only a floating lever driven through one cam contact on a roller has one",
          "[synthesis][lever_path]") {
  // the CVVL's swing cam is a rotational node: solved by the kinematics as before
  const Upstream c("cvvl_swing_cam");
  synthesis::LeverPath path;
  REQUIRE(synthesis::build_lever_path(c.spec, c.mech, c.lever, {0.0}, path).ok());
  CHECK(path.contact == -1);
  // the Valvetronic lever held by an eccentric given as a profile table (the same disc,
  // sampled every 2 deg): its pose is only as smooth as the table's spline, too rough for
  // the path's 0.5 mm steps, so it is solved whole
  Upstream v("valvetronic");
  synthesis::LeverPath analytic;
  REQUIRE(synthesis::build_lever_path(v.spec, v.mech, v.lever, {0.0}, analytic).ok());
  CHECK(analytic.contact >= 0);
  for (auto& pr : v.spec.profiles) {
    if (pr.name != "ecc_disc") continue;
    const double R = pr.disc_radius_mm, e = pr.eccentricity_mm;
    pr.form = ProfileForm::polar;
    for (int k = 0; k < 180; ++k) {  // the disc about (e, 0): r(a) = e cos a + sqrt(R^2 - e^2 sin^2 a)
      const double a = 2.0 * k * pi / 180;
      pr.angle_deg.push_back(2.0 * k);
      pr.radius_mm.push_back(e * std::cos(a) + std::sqrt(R * R - e * e * std::sin(a) * std::sin(a)));
    }
  }
  v.mech = kin::compile(v.spec);
  synthesis::LeverPath tabled;
  REQUIRE(synthesis::build_lever_path(v.spec, v.mech, v.lever, {0.0}, tabled).ok());
  CHECK(tabled.contact == -1);
}

TEST_CASE("lever path: a design already using the probe's names has none (solved whole), without an exception",
          "[synthesis][lever_path]") {
  // the lever's gate contact renamed to the probe face's name: the probe spec would have two
  // connections of that name, so no lever path is built and the upstream is solved whole
  Upstream v("valvetronic");
  for (auto& c : v.spec.connections)
    if (c.name == "gate") c.name = synthesis::detail::kProbeFace;
  v.mech = kin::compile(v.spec);
  synthesis::LeverPath path;
  REQUIRE(synthesis::build_lever_path(v.spec, v.mech, v.lever, {0.0}, path).ok());
  CHECK(path.contact == -1);
}
