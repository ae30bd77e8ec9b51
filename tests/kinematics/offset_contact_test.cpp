// the one-equation form of a curve-circle contact (the circle centre on the curve's offset,
// Workspace::Block::OffsetContact) against the general 2 x 2 block solver on the same
// designs: every variable's value and taylor coefficients, every contact quantity and the
// block condition number must agree, and the one-equation form must carry every point but
// the first (which scans for the contact with the general solver).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "kinematics/workspace_state.hpp"  // private to src/kinematics (tests/CMakeLists.txt adds src/)
#include "kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;

namespace {

// file: relative to the source directory
void compare(const std::string& file, double control) {
  const auto m = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/" + file));
  kin::Workspace fast(m), general(m);
  std::vector<double> controls;
  for (const auto& c : m.controls) controls.push_back(c.default_value);
  if (!controls.empty()) controls[0] = control;
  fast.set_controls(controls);
  general.set_controls(controls);
  kin::detail::state(general).offset_contacts = false;
  int offset_blocks = 0;
  for (const auto& b : kin::detail::state(fast).full_blocks) offset_blocks += b.offset.active ? 1 : 0;
  INFO(file << " at control " << control);
  REQUIRE(offset_blocks > 0);
  // the fast formulation against the general one, point by point over the sweep
  std::vector<ScalarCompare> order, contact;
  for (int k = 0; k <= 3; ++k) order.emplace_back("taylor order " + std::to_string(k));
  for (const char* q : {"contact x, y", "pressure angle", "curvatures", "entrainment", "sliding", "roller speed", "gap",
                        "polar angle"})
    contact.emplace_back(q);
  ScalarCompare condition("max condition");
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    const Status a = kin::solve(m, fast, t, {3, true});
    const Status b = kin::solve(m, general, t, {3, true});
    INFO(a.str() << " / " << b.str());
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    for (std::size_t v = 0; v < m.variables.size(); ++v)
      for (int k = 0; k <= 3; ++k) order[k].add(t, fast.vars[v].c[k], general.vars[v].c[k]);
    for (std::size_t c = 0; c < m.connections.size(); ++c) {
      const auto& p = fast.contacts[c];
      const auto& q = general.contacts[c];
      contact[0].add(t, p.x, q.x);
      contact[0].add(t, p.y, q.y);
      contact[1].add(t, p.pressure_angle, q.pressure_angle);
      contact[2].add(t, p.curvature_a, q.curvature_a);
      contact[2].add(t, p.curvature_b, q.curvature_b);
      contact[3].add(t, p.entrainment, q.entrainment);
      contact[4].add(t, p.sliding, q.sliding);
      contact[5].add(t, p.roller_speed, q.roller_speed);
      contact[6].add(t, p.gap, q.gap);
      contact[7].add(t, p.polar_angle_a, q.polar_angle_a);
      CHECK(p.open == q.open);
    }
    condition.add(t, fast.max_condition, general.max_condition);
  }
  for (std::size_t k = 0; k <= 3; ++k) CHECK_SERIES(order[k].compare(kFastGeneralRel[k]));
  for (const ScalarCompare& q : contact) CHECK_SERIES(q.compare(kFastGeneralContactRel));
  CHECK_SERIES(condition.compare(kFastGeneralContactRel));
  // the general solver ran on the first point only (one newton fallback per block)
  CHECK(fast.stats.broyden_iterations == 0);
  CHECK(fast.stats.newton_fallbacks == offset_blocks);
  CHECK(general.stats.broyden_iterations > 0);
}
}  // namespace

TEST_CASE("one-equation curve-circle contacts agree with the general block solver", "[kinematics][offset]") {
  compare("tests/data/kinematics/mbsim_roller.toml", 0.0);  // translating roller follower
  compare("designs/roller_finger_follower.toml", 0.0);     // rotational finger
  compare("designs/rocker_arm.toml", 0.0);
  compare("designs/cvvl_swing_cam.toml", 0.0);  // two chained contacts, rotational followers
  compare("designs/cvvl_swing_cam.toml", 8.0);
  compare("designs/cvvl_swing_cam.toml", 16.0);
}
