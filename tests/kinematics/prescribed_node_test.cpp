// kin::solve_prescribed: a node's variables given as jets in the driver instead of solved.
// The Valvetronic's floating lever is given its pose from solves of the whole mechanism; the
// finger and valve after it must then come out as in those solves (values and taylor
// coefficients), also when the given jets are in another parameter than the driver (the
// steps after the lever see only its pose), and a step beyond the predictor is refused
// without losing the workspace's last point.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "kinematics/workspace_state.hpp"  // private to src/kinematics (tests/CMakeLists.txt adds src/)
#include "kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;
using camopt::kin::Jet3;

namespace {


kin::Mechanism valvetronic() {
  return kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/valvetronic.toml"));
}

// the variables solved after the lever (finger, valve and their contacts' parameters)
std::vector<int> after_lever(const kin::Mechanism& m, int lever) {
  std::vector<int> out;
  bool past = false;
  for (const auto& step : m.plan) {
    const bool has_lever = std::find(step.unknowns.begin(), step.unknowns.end(),
                                     m.nodes[static_cast<std::size_t>(lever)].first_variable) != step.unknowns.end();
    if (past) out.insert(out.end(), step.unknowns.begin(), step.unknowns.end());
    past |= has_lever;
  }
  return out;
}

// every variable after the lever, solved with the lever given in `scale` x the driver
// (its jets' coefficient k divided by scale^k), against solves of the whole mechanism
void compare(double control, double scale) {
  const kin::Mechanism m = valvetronic();
  const int lever = m.node_index("lever");
  REQUIRE(kin::can_prescribe(m, lever));
  const kin::Node& lv = m.nodes[static_cast<std::size_t>(lever)];
  kin::Workspace whole(m), given(m);
  whole.set_controls(std::vector<double>{control});
  given.set_controls(std::vector<double>{control});
  const std::vector<int> checked = after_lever(m, lever);
  REQUIRE(checked.size() >= 3);  // finger, its contact parameter, the valve
  // the prescribed solve against the whole one, every order over the sweep
  std::vector<ScalarCompare> order;
  for (int o = 0; o <= 3; ++o) order.emplace_back("order " + std::to_string(o) + " of the nodes after the lever");
  double peak[4] = {};
  INFO("control " << control << " deg, lever given in " << scale << " x the driver");
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    const Status a = kin::solve(m, whole, t, {3, false});
    INFO(a.str());
    REQUIRE(a.ok());
    if (i == 0) {
      REQUIRE(kin::solve(m, given, scale * t, {3, false}).ok());  // the start: a solved point
      continue;
    }
    Jet3 pose[3];
    for (int k = 0; k < 3; ++k) {
      pose[k] = whole.vars[static_cast<std::size_t>(lv.first_variable + k)];
      for (int o = 1; o <= 3; ++o) pose[k].c[o] /= std::pow(scale, o);
    }
    const Status b = kin::solve_prescribed(m, given, scale * t, {3, false}, lever, pose);
    INFO("driver " << t / deg << " deg: " << b.str());
    REQUIRE(b.ok());
    for (int k = 0; k < 3; ++k)
      for (int o = 0; o <= 3; ++o)
        REQUIRE(given.vars[static_cast<std::size_t>(lv.first_variable + k)].c[o] == pose[k].c[o]);
    for (int v : checked)
      for (int o = 0; o <= 3; ++o)
        order[o].add(t, given.vars[static_cast<std::size_t>(v)].c[o] * std::pow(scale, o),
                     whole.vars[static_cast<std::size_t>(v)].c[o]),
            peak[o] = std::max(peak[o], std::abs(whole.vars[static_cast<std::size_t>(v)].c[o]));
  }
  for (std::size_t o = 0; o <= 3; ++o) {
    CHECK(peak[o] > 0.0);
    CHECK_SERIES(order[o].compare(kPrescribedRel[o]));
  }
}

}  // namespace

TEST_CASE("a lever given its pose moves the valve train after it as the whole solve does", "[kinematics][prescribed]") {
  compare(0.0, 1.0);
  compare(30.0, 1.0);
  compare(60.0, 1.0);
}

TEST_CASE("the lever's jets may be in another parameter than the driver", "[kinematics][prescribed]") {
  // the steps after the lever take its pose and its jets, not the driver's value: the
  // finger's jets come out in the lever's parameter
  compare(30.0, 2.0);
  compare(30.0, 3.0);
}

TEST_CASE("only a node solved on its own with its contacts' parameters can be given", "[kinematics][prescribed]") {
  const kin::Mechanism m = valvetronic();
  CHECK(kin::can_prescribe(m, m.node_index("lever")));
  CHECK(kin::can_prescribe(m, m.node_index("finger")));
  CHECK_FALSE(kin::can_prescribe(m, m.node_index("cam")));              // the driver
  CHECK_FALSE(kin::can_prescribe(m, m.node_index("eccentric_shaft")));  // set by its control
  CHECK_FALSE(kin::can_prescribe(m, m.node_index("valve")));            // its step holds it at rest on lash
  CHECK_FALSE(kin::can_prescribe(m, -1));
  CHECK_FALSE(kin::can_prescribe(m, static_cast<int>(m.nodes.size())));
}

TEST_CASE("solve_prescribed: a node that cannot be given, or a bad call, is an InputError", "[kinematics][prescribed]") {
  const kin::Mechanism m = valvetronic();
  kin::Workspace ws(m);
  const int lever = m.node_index("lever");
  const std::vector<kin::Jet3> jets(static_cast<std::size_t>(m.nodes[static_cast<std::size_t>(lever)].dof), kin::Jet3(0.0));
  // no solved point yet
  CHECK_THROWS_AS((void)kin::solve_prescribed(m, ws, 0.0, {3, false}, lever, jets), InputError);
  CHECK_THROWS_WITH((void)kin::solve_prescribed(m, ws, 0.0, {3, false}, lever, jets),
                    Catch::Contains("the workspace has no solved point"));
  REQUIRE(kin::solve(m, ws, 0.0, {3, false}).ok());
  CHECK_THROWS_WITH((void)kin::solve_prescribed(m, ws, 0.0, {3, false}, m.node_index("valve"), jets),
                    Catch::Contains("node 'valve' cannot be prescribed"));
  CHECK_THROWS_WITH((void)kin::solve_prescribed(m, ws, 0.0, {3, false}, lever, std::span(jets).first(0)),
                    Catch::Contains("node_vars has 0 jet(s)"));
  CHECK_THROWS_WITH((void)kin::solve_prescribed(m, ws, 0.0, {3, true}, lever, jets),
                    Catch::Contains("request.contacts = true: must be false"));
  CHECK_THROWS_WITH((void)kin::solve_prescribed(m, ws, 0.0, {3, false}, 99, jets),
                    Catch::Contains("node = 99 must be a node index"));
}

TEST_CASE("a given step beyond the predictor is refused and the workspace keeps its point", "[kinematics][prescribed]") {
  const kin::Mechanism m = valvetronic();
  const int lever = m.node_index("lever");
  const kin::Node& lv = m.nodes[static_cast<std::size_t>(lever)];
  kin::Workspace whole(m), given(m);
  whole.set_controls(std::vector<double>{0.0});
  given.set_controls(std::vector<double>{0.0});
  const double far = 180.0 * deg;  // the lobe's peak, from the base circle
  REQUIRE(kin::solve(m, whole, far, {3, false}).ok());
  REQUIRE(kin::solve(m, given, 0.0, {3, false}).ok());
  const std::vector<Jet3> at_start = given.vars;
  Jet3 pose[3];
  for (int k = 0; k < 3; ++k) pose[k] = whole.vars[static_cast<std::size_t>(lv.first_variable + k)];
  const Status refused = kin::solve_prescribed(m, given, far, {3, false}, lever, pose);
  INFO(refused.str());
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.message.find("trust radius") != std::string::npos);
  CHECK(kin::detail::state(given).prev_driver == 0.0);
  CHECK(kin::detail::state(given).prev_jets[static_cast<std::size_t>(m.nodes[static_cast<std::size_t>(m.node_index("finger"))].first_variable)]
            .value() == at_start[static_cast<std::size_t>(m.nodes[static_cast<std::size_t>(m.node_index("finger"))].first_variable)]
                            .value());
  // the full solve from there takes the step (continuation) and lands where the whole did
  REQUIRE(kin::solve(m, given, far, {3, false}).ok());
  const int valve = m.nodes[static_cast<std::size_t>(m.node_index("valve"))].first_variable;
  CHECK_ABS(given.vars[static_cast<std::size_t>(valve)].value(), whole.vars[static_cast<std::size_t>(valve)].value(),
            kPrescribedAbs);
}
