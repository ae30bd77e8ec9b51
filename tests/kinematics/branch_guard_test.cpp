// assembly branches of the continuation (detail/branch_guard.hpp): a four-bar near its
// change point, crank 30, coupler 90, rocker 60.02, ground 120 mm (Grashof by 0.02 mm), whose
// coupler is a floating body held by two 10 mm links at each pin. At crank 180 deg the coupler
// and the rocker are 1.9 deg from stretched in line and the crossed branch passes close by.
// The rocker must follow the closed form on the drawing's branch over a full revolution at
// fine and coarse steps, with the same bits whatever outputs are requested, and the run must
// be flagged near toggle (a comfortable 80 mm rocker must not). Regression: with lift only
// requested, 5 deg steps landed on the crossed branch after 180 deg (rocker 141 deg off at
// 360 deg) with every output ok; with all outputs, 45 deg steps did.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;

namespace {

// the four-bar in closed form: crank pivot O = (0, 0), rocker pivot D = (ground, 0)
struct FourBarLengths {
  double crank = 30, coupler = 90, rocker = 60.02, ground = 120;  // [mm]

  Vector2d crank_pin(double theta) const { return {crank * std::cos(theta), crank * std::sin(theta)}; }
  // the rocker pin B on the drawing's branch: of the two intersections of the circles
  // |B - A| = coupler and |B - D| = rocker, the one left of A -> D (the upper one at theta 0)
  Vector2d rocker_pin(double theta) const {
    const Vector2d a = crank_pin(theta), d(ground, 0.0);
    const double dist = (d - a).norm();
    const double along = (coupler * coupler - rocker * rocker + dist * dist) / (2.0 * dist);
    const double across = std::sqrt(coupler * coupler - along * along);
    const Vector2d e = (d - a) / dist;
    return a + along * e + across * Vector2d(-e.y(), e.x());
  }
  // the absolute rocker angle [rad]
  double rocker_angle(double theta) const {
    const Vector2d b = rocker_pin(theta);
    return std::atan2(b.y(), b.x() - ground);
  }
  // the smallest sine of the transmission angle (between coupler and rocker) over a
  // revolution: at crank 180 deg, where |A - D| is largest (law of cosines)
  double min_transmission_sine() const {
    const double dist = crank + ground;
    const double c = (coupler * coupler + rocker * rocker - dist * dist) / (2.0 * coupler * rocker);
    return std::sqrt(1.0 - c * c);
  }
};

Vec2 v2(const Vector2d& p) { return {p.x(), p.y()}; }

// the four-bar with a floating coupler: each pin is two 10 mm links from the crank (rocker)
// pin to two coupler points, drawn at crank 0
DesignSpec floating_coupler(const FourBarLengths& f) {
  constexpr double kLink = 10.0;  // [mm]
  const Vector2d a = f.crank_pin(0.0), b = f.rocker_pin(0.0);
  DesignSpec d = design("floating_coupler_four_bar", "crank", "rocker");
  d.nodes = {rotational("crank", {0, 0}), rotational("rocker", {f.ground, 0}), floating("coupler")};
  d.connections = {link("crank_pin_1", "crank", v2(a), "coupler", v2(a + Vector2d(0, kLink))),
                   link("crank_pin_2", "crank", v2(a), "coupler", v2(a + Vector2d(kLink, 0))),
                   link("rocker_pin_1", "rocker", v2(b), "coupler", v2(b + Vector2d(0, kLink))),
                   link("rocker_pin_2", "rocker", v2(b), "coupler", v2(b + Vector2d(kLink, 0)))};
  return d;
}

kin::SweepResult revolution(const kin::Mechanism& m, double step_deg, const kin::Request& request) {
  kin::SweepSpec spec;
  spec.start = 0.0;
  spec.stop = 360.0;
  spec.step = step_deg;
  spec.request = request;
  return kin::sweep(m, spec);
}

constexpr kin::Request kLiftOnly{0, false};
constexpr kin::Request kAllOutputs{3, true};
constexpr double kStepsDeg[] = {5.0, 10.0, 20.0, 30.0, 45.0, 90.0};

}  // namespace

TEST_CASE("branch: a near-change-point four-bar with a floating coupler follows its closed form at any step",
          "[kinematics][branch]") {
  const FourBarLengths f;
  const auto m = kin::compile(floating_coupler(f));
  REQUIRE(m.plan.size() == 1);
  REQUIRE(m.plan[0].unknowns.size() == 4);
  const int rocker = m.nodes[static_cast<std::size_t>(m.node_index("rocker"))].first_variable;
  const double rest = f.rocker_angle(0.0);
  for (double step : kStepsDeg) {
    for (const kin::Request& rq : {kLiftOnly, kAllOutputs}) {
      INFO("step " << step << " deg, derivative order " << rq.derivative_order);
      const auto r = revolution(m, step, rq);
      const auto& p = r.positions[0];
      INFO(p.status.str());
      REQUIRE(p.status.ok());
      ScalarCompare rocker_angle("rocker angle [rad]");
      for (std::size_t i = 0; i < r.driver.size(); ++i) {
        const double reference = oracles::wrap_angle(f.rocker_angle(r.driver[i] * deg) - rest);
        const double kernel = p.value(i, rocker, 0) * deg;
        // compared modulo 2 pi
        rocker_angle.add(r.driver[i], reference + oracles::wrap_angle(kernel - reference), reference);
      }
      CHECK_SERIES(rocker_angle.compare(kDisplacementRel));
    }
  }
}

TEST_CASE("branch: the step control and the results do not depend on the requested outputs",
          "[kinematics][branch]") {
  for (double rocker_mm : {60.02, 80.0}) {
    FourBarLengths f;
    f.rocker = rocker_mm;
    const auto m = kin::compile(floating_coupler(f));
    const std::size_t nv = m.variables.size();
    for (double step : kStepsDeg) {
      INFO("rocker " << rocker_mm << " mm, step " << step << " deg");
      const auto lift = revolution(m, step, kLiftOnly), all = revolution(m, step, kAllOutputs);
      const auto &pl = lift.positions[0], &pa = all.positions[0];
      REQUIRE(pl.status.ok());
      REQUIRE(pa.status.ok());
      // the same continuation: the same points, halved steps and bits
      CHECK(pl.stats.points == pa.stats.points);
      CHECK(pl.stats.rejected_steps == pa.stats.rejected_steps);
      for (std::size_t i = 0; i < lift.driver.size(); ++i) {
        for (std::size_t v = 0; v < nv; ++v) CHECK(pl.value(i, static_cast<int>(v), 0) == pa.value(i, static_cast<int>(v), 0));
        CHECK(pl.toggle_margin[i] == pa.toggle_margin[i]);
      }
      const auto sl = kin::summarize(m, lift, 0), sa = kin::summarize(m, all, 0);
      CHECK(sl.near_toggle == sa.near_toggle);
      CHECK(sl.min_toggle_margin == sa.min_toggle_margin);
      CHECK(sl.min_toggle_margin_at == sa.min_toggle_margin_at);
    }
  }
}

TEST_CASE("branch: a run passing close to toggle is flagged, a comfortable one is not", "[kinematics][branch]") {
  FourBarLengths close_call, comfortable;
  comfortable.rocker = 80.0;
  // transmission angles from the closed form: 1.9 deg against 56 deg at crank 180 deg
  REQUIRE_ABS(close_call.min_transmission_sine(), 0.0333, kTransmissionSineAbs);
  REQUIRE_ABS(comfortable.min_transmission_sine(), 0.8315, kTransmissionSineAbs);
  for (double step : kStepsDeg) {
    for (const kin::Request& rq : {kLiftOnly, kAllOutputs}) {
      INFO("step " << step << " deg, derivative order " << rq.derivative_order);
      const auto near = kin::compile(floating_coupler(close_call));
      const auto r = revolution(near, step, rq);
      REQUIRE(r.positions[0].status.ok());
      const auto s = kin::summarize(near, r, 0);
      INFO("closest approach: margin " << s.min_toggle_margin << " at " << s.min_toggle_margin_at << " deg");
      CHECK(s.near_toggle);
      CHECK(s.min_toggle_margin < kin::near_singular_margin);
      // the closest approach is at crank 180 deg, a point of every one of these grids
      CHECK_ABS(s.min_toggle_margin_at, 180.0, kPeakAngleAbs);

      const auto far = kin::compile(floating_coupler(comfortable));
      const auto rf = revolution(far, step, rq);
      REQUIRE(rf.positions[0].status.ok());
      const auto sf = kin::summarize(far, rf, 0);
      INFO("comfortable: margin " << sf.min_toggle_margin << " at " << sf.min_toggle_margin_at << " deg");
      CHECK(!sf.near_toggle);
      CHECK(sf.min_toggle_margin > 3.0 * kin::near_singular_margin);
    }
  }
}
