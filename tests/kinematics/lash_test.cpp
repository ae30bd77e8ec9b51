// valve lash: a one-sided contact holds its follower at rest while the clearance is open.
//
// flat tappet on an eccentric disc (R, e), cam pivot at the origin, the disc's 0 axis at
// -90 deg so the base circle (radius R - e) faces the tappet at theta = 0; the face drawn
// touching the base circle at height y0 = R - e; lash L, rest 0. the disc's top is at
// R - e cos(theta), and the closure "face - top + L = 0" gives the closed lift
//   s_c(theta) = e (1 - cos theta) - L,
// so the tappet displacement is s = max(0, s_c): at rest (all derivatives zero) while the
// gap g = -s_c = L - e (1 - cos theta) is open, i.e. cos(theta) > 1 - L/e, and
// e sin, e cos, -e sin once it closes. the peak lift is 2e - L: the lash is lost exactly.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;

namespace {

constexpr double kR = 20.0, kE = 4.0;  // disc radius, eccentricity [mm]
constexpr double kLash = 0.2;          // [mm]

DesignSpec flat_with_lash(double lash, const Placement& p) {
  DesignSpec d = design("lash_flat", "cam", "tappet");
  const double y0 = kR - kE;
  d.nodes = {rotational("cam", p.pt({0, 0})), translational("tappet", p.pt({0, y0}), p.dir({0, 1}))};
  d.profiles = {eccentric_profile("disc", kR, kE)};
  ConnectionSpec c = contact("cam_tappet", profile_surface("cam", "disc", p.pt({0, 0}), p.degrees(-90 * deg)),
                             line_surface("tappet", p.pt({0, y0}), p.dir({0, -1})));
  c.lash_mm = lash;
  d.connections = {c};
  return d;
}

}  // namespace

TEST_CASE("lash: flat tappet on an eccentric disc is held at rest while the clearance is open",
          "[kinematics][lash]") {
  for (const Placement& place : {Placement{}, Placement{35 * deg, {8, -12}}}) {
    const auto m = kin::compile(flat_with_lash(kLash, place));
    REQUIRE(m.plan.size() == 1);
    CHECK(m.plan[0].one_sided);
    kin::Workspace ws(m);
    kin::Request rq;
    rq.contacts = true;
    SweepCompare lift("lash flat, placement " + std::to_string(place.angle / deg), false);
    int open_points = 0;
    for (int i = 0; i < kSweepPoints; ++i) {
      const double t = i * kSweepStepDeg * deg;
      const Status st = kin::solve(m, ws, t, rq);
      INFO(st.str());
      REQUIRE(st.ok());
      const double closed = kE * (1.0 - std::cos(t)) - kLash;
      const bool open = closed < 0.0;
      const Jet<3>& s = node_jet(m, ws, "tappet");
      const auto& cs = ws.contacts[0];
      INFO("theta " << t / deg << " deg, closed-form lift " << closed);
      REQUIRE(cs.open == open);
      if (open) {
        // at rest, exactly, with zero rates; the gap is the clearance left
        CHECK(s.value() == 0.0);
        for (int k = 1; k <= 3; ++k) CHECK(s.derivative(k) == 0.0);
        CHECK_ABS(cs.gap, -closed, kGapAbs);
        ++open_points;
        lift.add(t, motion_of(s), {0, 0, 0, 0});
      } else {
        CHECK(cs.gap == 0.0);
        lift.add(t, motion_of(s), {closed, kE * std::sin(t), kE * std::cos(t), -kE * std::sin(t)});
      }
    }
    // open for cos(theta) > 1 - L/e: 2 acos(0.95) = 36.4 deg of the revolution
    const double open_span = 2.0 * std::acos(1.0 - kLash / kE) / deg;
    CHECK_ABS(open_points, open_span / kSweepStepDeg, kSweepCountAbs);
    CHECK_COMPARISONS(lift.compare());
  }
}

TEST_CASE("lash: the lift lost is exactly the lash", "[kinematics][lash]") {
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = kSweepStepDeg;
  spec.request.contacts = true;
  const auto with = kin::compile(flat_with_lash(kLash, {}));
  const auto without = kin::compile(flat_with_lash(0.0, {}));
  const auto rw = kin::sweep(with, spec), rn = kin::sweep(without, spec);
  REQUIRE(rw.positions[0].status.ok());
  REQUIRE(rn.positions[0].status.ok());
  const auto sw = kin::summarize(with, rw, 0), sn = kin::summarize(without, rn, 0);
  CHECK_ABS(sn.max_lift, 2.0 * kE, kLiftLossAbs);
  CHECK_ABS(sn.max_lift - sw.max_lift, kLash, kLiftLossAbs);
  CHECK_ABS(sw.max_lift_at, 180.0, kPeakAngleAbs);
  // the lash contact reports its separation; the closed contact does not
  CHECK(sw.separations.size() == 1);
  CHECK(sn.separations.empty());
  // point by point: with lash = max(0, without - lash)
  const int v = with.nodes[static_cast<std::size_t>(with.node_index("tappet"))].first_variable;
  std::vector<double> with_lash, expected;
  for (std::size_t i = 0; i < rw.driver.size(); ++i) {
    with_lash.push_back(rw.positions[0].value(i, v, 0));
    expected.push_back(std::max(0.0, rn.positions[0].value(i, v, 0) - kLash));
  }
  CHECK_SERIES(camopt::test::compare_series("lift with lash [mm]", with_lash, expected,
                                            {.abs = kDisplacementRel * 2.0 * kE}, rw.driver, "driver [deg]"));
}

TEST_CASE("lash: offset roller on an eccentric disc closes along the contact normal", "[kinematics][lash]") {
  // the closure |roller centre - disc centre| = R + r - L: the lift with lash is oracle (b)
  // with the roller radius r - L, measured from the drawing (radius r), floored at rest;
  // the gap at rest is |(offset, Y0) - disc centre| - (R + r) + L
  const double R = 18, e = 3, phase = -90 * deg, r = 9, offset = 3;
  const oracles::EccentricOffsetRoller drawn{R, e, phase, r, offset}, closed{R, e, phase, r - kLash, offset};
  const double Y0 = drawn.centre_height(0)[0];
  DesignSpec d = design("lash_roller", "cam", "tappet");
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {offset, Y0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", R, e)};
  ConnectionSpec c =
      contact("cam_roller", profile_surface("cam", "disc", {0, 0}, phase / deg), circle_surface("tappet", {offset, Y0}, r, true));
  c.lash_mm = kLash;
  d.connections = {c};
  const auto m = kin::compile(d);
  kin::Workspace ws(m);
  kin::Request rq;
  rq.contacts = true;
  SweepCompare lift("lash roller", false);
  for (int i = 0; i < kSweepPoints; ++i) {
    const double t = i * kSweepStepDeg * deg;
    REQUIRE(kin::solve(m, ws, t, rq).ok());
    const Vector2d disc = e * Vector2d(std::cos(t + phase), std::sin(t + phase));
    const double gap = (Vector2d(offset, Y0) - disc).norm() - (R + r) + kLash;
    const auto& cs = ws.contacts[0];
    INFO("theta " << t / deg << " deg, gap at rest " << gap);
    REQUIRE(cs.open == (gap > 0));
    if (gap > 0) {
      CHECK_ABS(cs.gap, gap, kGapAbs);
      lift.add(t, motion_of(node_jet(m, ws, "tappet")), {0, 0, 0, 0});
    } else {
      auto ref = closed.centre_height(t);
      ref[0] -= Y0;
      lift.add(t, motion_of(node_jet(m, ws, "tappet")), ref);
    }
  }
  CHECK_COMPARISONS(lift.compare());
}

TEST_CASE("lash: flat tappet on a polar table cam (implicit solve) is held at rest while the clearance is open",
          "[kinematics][lash]") {
  // a table cam has no closed form in the kernel: the contact is solved by Newton (the
  // implicit path) and the gap at rest by the tangency block alone. reference: oracle (g),
  // the support function of the same interpolated table (the kernel's periodic quintic
  // spline through the same sites), lash-free lift s0(theta). the closure
  // "face - support + L = 0" gives the lift with lash s = max(0, s0 - L), at rest while the
  // gap L - s0 is open. both sides evaluate one spline, so the tolerances are the solver's
  // acceptance (displacement 1e-9 of the peak, the gap being a displacement), not the
  // table's interpolation error against the analytic lobe.
  const PeriodicSpline spline = lobe_spline();
  for (const double orientation : {90 * deg, -150 * deg}) {
    const oracles::FlatFollowerPolarCam o{[&](double phi, double* r) { spline.evaluate(phi, 3, r); }, orientation};
    const double y0 = o.face_height(0)[0];
    DesignSpec d = design("lash_table_flat", "cam", "tappet");
    d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, y0}, {0, 1})};
    d.profiles = {lobe_table("lobe")};
    ConnectionSpec c = contact("cam_tappet", profile_surface("cam", "lobe", {0, 0}, orientation / deg),
                               line_surface("tappet", {0, y0}, {0, -1}));
    c.lash_mm = kLash;
    d.connections = {c};
    const auto m = kin::compile(d);
    REQUIRE(m.plan.size() == 1);
    REQUIRE(m.plan[0].method == kin::StepMethod::implicit);
    REQUIRE(m.plan[0].one_sided);
    kin::Workspace ws(m);
    kin::Request rq;
    rq.contacts = true;
    const std::string name = "lash table flat, orientation " + std::to_string(orientation / deg);
    SweepCompare lift(name, false);
    ScalarCompare gap(name + " gap at rest");
    int open_points = 0, closed_points = 0;
    for (int i = 0; i < kSweepPoints; ++i) {
      const double t = i * kSweepStepDeg * deg;
      const Status st = kin::solve(m, ws, t, rq);
      INFO(st.str());
      REQUIRE(st.ok());
      const Motion s0 = o.lift(t);
      const double closed = s0[0] - kLash;
      const auto& cs = ws.contacts[0];
      INFO("theta " << t / deg << " deg, lash-free lift " << s0[0] << " mm");
      REQUIRE(cs.open == (closed < 0.0));
      if (cs.open) {
        ++open_points;
        gap.add(t, cs.gap, -closed);
        lift.add(t, motion_of(node_jet(m, ws, "tappet")), {0, 0, 0, 0});
      } else {
        ++closed_points;
        CHECK(cs.gap == 0.0);
        lift.add(t, motion_of(node_jet(m, ws, "tappet")), {closed, s0[1], s0[2], s0[3]});
      }
    }
    // the lobe lifts 3 mm; it is below the lash (0.2 mm) for about 120 deg around its base
    CHECK(open_points > 100);
    CHECK(closed_points > 100);
    CHECK_COMPARISONS(lift.compare());
    CHECK_SERIES(gap.compare(0.0, kDisplacementRel * 3.0));
  }
}
