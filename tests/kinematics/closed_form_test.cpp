// accuracy of the kinematics engine against closed forms (tests/oracles): each mechanism
// is built in code in realistic valvetrain dimensions, placed anywhere in the drawing,
// swept over a full revolution at 0.5 deg, and its displacement, velocity, acceleration
// and jerk compared with the oracle (displacement 1e-9, velocity and acceleration 1e-7,
// jerk 1e-5, each relative to its peak). where it means something the mechanism is also
// driven from the other end: any node can drive.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/spline.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"

using namespace camopt;
using namespace camopt::kin_test;
using camopt::oracles::wrap_angle;

namespace {

// contact outputs are positions (contact point, angles) or rates: same acceptance as the
// displacement and the velocity

// solve at each driver value in turn (warm starts chain along the sweep)
void run(const kin::Mechanism& m, const std::vector<double>& driver, bool contacts,
         const std::function<void(std::size_t, double, const kin::Workspace&)>& visit) {
  kin::Workspace ws(m);
  kin::Request rq;
  rq.contacts = contacts;
  for (std::size_t i = 0; i < driver.size(); ++i) {
    const Status st = kin::solve(m, ws, driver[i], rq);
    INFO(m.name << ": " << st.str());
    REQUIRE(st.ok());
    visit(i, driver[i], ws);
  }
}

std::vector<double> revolution() {
  std::vector<double> t;
  for (int i = 0; i < kSweepPoints; ++i) t.push_back(i * kSweepStepDeg * deg);
  return t;
}

std::vector<double> range(double a, double b, int n) {
  std::vector<double> t;
  for (int i = 0; i <= n; ++i) t.push_back(a + (b - a) * i / n);
  return t;
}

// a drawing point in the oracle's frame (inverse placement)
Vector2d local_point(const Placement& place, double x, double y) {
  const Vector2d d = Vector2d(x, y) - place.shift;
  return {d.dot(place.direction({1, 0})), d.dot(place.direction({0, 1}))};
}

Vector2d polar(double r, double a) { return {r * std::cos(a), r * std::sin(a)}; }

// ---- (a) ----
struct FlatCase {
  double R, e, phase;
  Placement place;
};

DesignSpec eccentric_flat(const FlatCase& c, double face_height) {
  DesignSpec d = design("eccentric_flat", "cam", "tappet");
  const Placement& p = c.place;
  d.nodes = {rotational("cam", p.pt({0, 0})), translational("tappet", p.pt({0, face_height}), p.dir({0, 1}))};
  d.profiles = {eccentric_profile("disc", c.R, c.e)};
  d.connections = {contact("cam_tappet", profile_surface("cam", "disc", p.pt({0, 0}), p.degrees(c.phase)),
                           line_surface("tappet", p.pt({0, face_height}), p.dir({0, -1})))};
  return d;
}

// ---- (b) ----
struct RollerCase {
  double R, e, phase, r, offset;
  Placement place;
};

DesignSpec eccentric_roller(const RollerCase& c, double centre_height) {
  DesignSpec d = design("eccentric_offset_roller", "cam", "tappet");
  const Placement& p = c.place;
  const Vector2d centre(c.offset, centre_height);
  d.nodes = {rotational("cam", p.pt({0, 0})), translational("tappet", p.pt(centre), p.dir({0, 1}))};
  d.profiles = {eccentric_profile("disc", c.R, c.e)};
  d.connections = {contact("cam_roller", profile_surface("cam", "disc", p.pt({0, 0}), p.degrees(c.phase)),
                           circle_surface("tappet", p.pt(centre), c.r, true))};
  return d;
}

// ---- (c) ----
DesignSpec eccentric_oscillating(const oracles::EccentricOscillatingRoller& o, const Placement& p) {
  DesignSpec d = design("eccentric_oscillating_roller", "cam", "arm");
  const Vector2d centre = o.arm_pivot + polar(o.arm_length, o.arm_angle(0)[0]);
  d.nodes = {rotational("cam", p.pt({0, 0})), rotational("arm", p.pt(o.arm_pivot))};
  d.profiles = {eccentric_profile("disc", o.disc_radius, o.eccentricity)};
  d.connections = {contact("cam_roller", profile_surface("cam", "disc", p.pt({0, 0}), p.degrees(o.phase)),
                           circle_surface("arm", p.pt(centre), o.roller_radius, true))};
  return d;
}

// ---- (d) ----
DesignSpec four_bar(const oracles::FourBar& f, double crank_angle, const std::string& driver,
                    const std::string& output) {
  DesignSpec d = design("four_bar", driver, output);
  const double th4 = f.solve(crank_angle).rocker_angle[0];
  const Vector2d A = f.crank_pivot + polar(f.crank, crank_angle), B = f.rocker_pivot + polar(f.rocker, th4);
  d.nodes = {rotational("crank", {f.crank_pivot.x(), f.crank_pivot.y()}),
             rotational("rocker", {f.rocker_pivot.x(), f.rocker_pivot.y()})};
  d.connections = {link("coupler", "crank", {A.x(), A.y()}, "rocker", {B.x(), B.y()})};
  return d;
}

// ---- (e) ----
DesignSpec slider_crank(const oracles::SliderCrank& s, double crank_angle, const std::string& driver,
                        const std::string& output) {
  DesignSpec d = design("slider_crank", driver, output);
  const double x = s.solve(crank_angle).slider[0];
  const Vector2d A = s.crank_pivot + polar(s.crank, crank_angle), B = s.slide_point + x * s.slide_direction;
  d.nodes = {rotational("crank", {s.crank_pivot.x(), s.crank_pivot.y()}),
             translational("slider", {B.x(), B.y()}, {s.slide_direction.x(), s.slide_direction.y()})};
  ConnectionSpec rod = link("rod", "crank", {A.x(), A.y()}, "slider", {B.x(), B.y()});
  rod.kind = ConnectionKind::crank_slider;
  d.connections = {rod};
  return d;
}

// ---- (g) ----
DesignSpec polar_flat(double orientation, double face_height, const Placement& p) {
  DesignSpec d = design("polar_flat", "cam", "tappet");
  d.nodes = {rotational("cam", p.pt({0, 0})), translational("tappet", p.pt({0, face_height}), p.dir({0, 1}))};
  d.profiles = {lobe_table("lobe")};
  d.connections = {contact("cam_tappet", profile_surface("cam", "lobe", p.pt({0, 0}), p.degrees(orientation)),
                           line_surface("tappet", p.pt({0, face_height}), p.dir({0, -1})))};
  return d;
}

}  // namespace

TEST_CASE("closed form (a): eccentric disc + centred flat-faced follower", "[kinematics][closed_form]") {
  const FlatCase cases[] = {
      {20.0, 4.0, -90 * deg, {0.0, {0, 0}}},
      {18.0, 3.0, 30 * deg, {25 * deg, {10, -5}}},
      {22.0, 5.0, 0.0, {-120 * deg, {-30, 40}}},
  };
  for (const auto& c : cases) {
    const oracles::EccentricFlatFollower o{c.R, c.e, c.phase};
    const double y0 = o.face_height(0)[0];
    const auto m = kin::compile(eccentric_flat(c, y0));
    const std::string name = "flat R " + std::to_string(c.R) + " e " + std::to_string(c.e);
    SweepCompare lift(name, false);
    ScalarCompare cx(name + " contact x"), cy(name + " contact y"), pa(name + " pressure angle"),
        sl(name + " sliding"), en(name + " entrainment");
    run(m, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
      lift.add(t, motion_of(node_jet(m, ws, "tappet")), o.lift(t));
      const auto& cs = ws.contacts[0];
      const Vector2d local = local_point(c.place, cs.x, cs.y);
      const auto y = o.face_height(t);
      cx.add(t, local.x(), o.contact_x(t));
      cy.add(t, local.y(), y[0]);
      pa.add(t, cs.pressure_angle, 0.0);
      // material points slide at the face height (cam at unit rate); the contact point runs
      // along the face at s'' and along the disc at R (derivation in derivatives_test.cpp)
      sl.add(t, cs.sliding, y[0]);
      en.add(t, cs.entrainment, 0.5 * y[0] + y[2]);
      CHECK_REL(cs.curvature_a, 1.0 / c.R, kCurvatureRel);
      CHECK(cs.curvature_b == 0.0);
      CHECK_FALSE(cs.open);
    });
    REQUIRE(lift.size() == kSweepPoints);
    CHECK_COMPARISONS(lift.compare());
    CHECK_SERIES(cx.compare(0.0, kContactPointRel * m.length_scale));
    CHECK_SERIES(cy.compare(0.0, kContactPointRel * m.length_scale));
    CHECK_SERIES(pa.compare(0.0, kPressureAngleAbs));
    CHECK_SERIES(sl.compare(kContactRateRel));
    CHECK_SERIES(en.compare(kContactRateRel));
  }
}

TEST_CASE("closed form (b): eccentric disc + offset translating roller follower, the disc as a profile and as a circle",
          "[kinematics][closed_form]") {
  // the disc also as a circle on the cam (circle-circle contact): the contact point then runs
  // along the centre line and its velocity comes from the centres (another path through the
  // contact outputs); its contact point, normal and entrainment equal the profile model's
  const RollerCase cases[] = {
      {18.0, 3.0, 0.3, 9.0, 3.0, {0.0, {0, 0}}},
      {16.0, 2.5, -1.0, 10.0, -4.0, {70 * deg, {12, 3}}},
      {20.0, 4.0, 2.0, 8.0, 5.0, {200 * deg, {-25, -8}}},
  };
  for (const auto& c : cases) {
    const oracles::EccentricOffsetRoller o{c.R, c.e, c.phase, c.r, c.offset};
    DesignSpec d = eccentric_roller(c, o.centre_height(0)[0]);
    const auto m_profile = kin::compile(d);
    d.profiles.clear();
    d.connections[0].surface_a = circle_surface("cam", c.place.pt({c.e * std::cos(c.phase), c.e * std::sin(c.phase)}),
                                                c.R, false);
    const auto m_circle = kin::compile(d);
    for (const kin::Mechanism* m : {&m_profile, &m_circle}) {
      const bool circle = m == &m_circle;
      const std::string name = (circle ? "circle-circle offset " : "roller offset ") + std::to_string(c.offset);
      SweepCompare lift(name, false);
      ScalarCompare pa(name + " pressure angle"), rs(name + " roller speed"), sl(name + " sliding"),
          en(name + " entrainment"), cx(name + " contact x"), cy(name + " contact y");
      kin::Workspace ws_profile(m_profile);
      run(*m, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
        lift.add(t, motion_of(node_jet(*m, ws, "tappet")), o.lift(t));
        const auto& cs = ws.contacts[0];
        pa.add(t, cs.pressure_angle, o.pressure_angle(t));
        rs.add(t, cs.roller_speed, o.roller_speed(t));
        sl.add(t, cs.sliding, 0.0);
        CHECK_REL(cs.curvature_a, 1.0 / c.R, kCurvatureRel);
        CHECK_REL(cs.curvature_b, 1.0 / c.r, kCurvatureRel);
        if (!circle) return;
        REQUIRE(kin::solve(m_profile, ws_profile, t, kin::Request{3, true}).ok());
        const auto& ref = ws_profile.contacts[0];
        en.add(t, cs.entrainment, ref.entrainment);
        cx.add(t, cs.x, ref.x);
        cy.add(t, cs.y, ref.y);
        CHECK_ABS(cs.normal_x, ref.normal_x, kContactPointRel);
        CHECK_ABS(cs.normal_y, ref.normal_y, kContactPointRel);
      });
      CHECK_COMPARISONS(lift.compare());
      CHECK_SERIES(pa.compare(0.0, kPressureAngleAbs));
      CHECK_SERIES(rs.compare(kContactRateRel));
      CHECK_SERIES(sl.compare(0.0, kContactRateRel * c.R));
      if (!circle) continue;
      CHECK_SERIES(en.compare(kContactRateRel));
      CHECK_SERIES(cx.compare(0.0, kContactPointRel * m->length_scale));
      CHECK_SERIES(cy.compare(0.0, kContactPointRel * m->length_scale));
    }
  }
}

TEST_CASE("closed form (a) and (b): the follower may be side a of the contact", "[kinematics][closed_form]") {
  // swapping the sides changes nothing physical: the lift, the pressure angle, the roller
  // spin and the sliding speed stay; the normal (from a into b) and with it the tangent
  // t = z x n flip, so the entrainment (measured along t) changes sign
  const FlatCase fc{20.0, 4.0, -90 * deg, {30 * deg, {4, 9}}};
  const oracles::EccentricFlatFollower fo{fc.R, fc.e, fc.phase};
  DesignSpec flat = eccentric_flat(fc, fo.face_height(0)[0]);
  std::swap(flat.connections[0].surface_a, flat.connections[0].surface_b);
  const auto mf = kin::compile(flat);
  SweepCompare flat_lift("swapped flat", false);
  ScalarCompare sl("swapped flat sliding"), en("swapped flat entrainment");
  run(mf, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
    flat_lift.add(t, motion_of(node_jet(mf, ws, "tappet")), fo.lift(t));
    const auto y = fo.face_height(t);
    sl.add(t, ws.contacts[0].sliding, y[0]);
    en.add(t, ws.contacts[0].entrainment, -(0.5 * y[0] + y[2]));
    CHECK_REL(ws.contacts[0].curvature_b, 1.0 / fc.R, kCurvatureRel);
  });
  CHECK_COMPARISONS(flat_lift.compare());
  CHECK_SERIES(sl.compare(kContactRateRel));
  CHECK_SERIES(en.compare(kContactRateRel));

  const RollerCase rc{18.0, 3.0, 0.3, 9.0, 3.0, {-50 * deg, {-6, 2}}};
  const oracles::EccentricOffsetRoller ro{rc.R, rc.e, rc.phase, rc.r, rc.offset};
  DesignSpec roller = eccentric_roller(rc, ro.centre_height(0)[0]);
  std::swap(roller.connections[0].surface_a, roller.connections[0].surface_b);
  const auto mr = kin::compile(roller);
  SweepCompare roller_lift("swapped roller", false);
  ScalarCompare pa("swapped roller pressure angle"), rs("swapped roller speed");
  run(mr, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
    roller_lift.add(t, motion_of(node_jet(mr, ws, "tappet")), ro.lift(t));
    pa.add(t, ws.contacts[0].pressure_angle, ro.pressure_angle(t));
    rs.add(t, ws.contacts[0].roller_speed, ro.roller_speed(t));
  });
  CHECK_COMPARISONS(roller_lift.compare());
  CHECK_SERIES(pa.compare(0.0, kPressureAngleAbs));
  CHECK_SERIES(rs.compare(kContactRateRel));
}

TEST_CASE("closed form (c): eccentric disc + oscillating roller follower", "[kinematics][closed_form]") {
  struct Case {
    oracles::EccentricOscillatingRoller o;
    Placement place;
  };
  const Case cases[] = {
      {{18.0, 3.0, 0.5, 9.0, Vector2d(-20, 38), 36.0, 1}, {0.0, {0, 0}}},
      {{18.0, 3.0, 0.5, 9.0, Vector2d(-20, 38), 36.0, -1}, {0.0, {0, 0}}},
      {{16.0, 3.5, -2.0, 10.0, Vector2d(42, 10), 32.0, 1}, {-35 * deg, {15, 20}}},
  };
  for (const auto& c : cases) {
    const auto& o = c.o;
    const auto m = kin::compile(eccentric_oscillating(o, c.place));
    const std::string name = "oscillating branch " + std::to_string(o.branch) + " pivot (" +
                             std::to_string(o.arm_pivot.x()) + ", " + std::to_string(o.arm_pivot.y()) + ")";
    SweepCompare lift(name, true);
    ScalarCompare rs(name + " roller speed"), pa(name + " pressure angle");
    run(m, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
      lift.add(t, motion_of(node_jet(m, ws, "arm")), o.lift(t));
      rs.add(t, ws.contacts[0].roller_speed, o.roller_speed(t));
      // at the roller centre (the trace point): a free roller transmits the force through
      // its pin, not through the arm's material point at the contact (up to atan(r/l) apart)
      pa.add(t, ws.contacts[0].pressure_angle, o.pressure_angle(t));
    });
    CHECK_COMPARISONS(lift.compare());
    CHECK_SERIES(rs.compare(kContactRateRel));
    CHECK_SERIES(pa.compare(0.0, kPressureAngleAbs));
  }
}

TEST_CASE("closed form (d): grashof four-bar, both assembly branches, driven by the crank",
          "[kinematics][closed_form]") {
  struct Case {
    Vector2d O2, O4;
    double a, b, c, crank_drawing;
  };
  // crank-rocker: shortest + longest < sum of the other two, the crank shortest
  const Case cases[] = {
      {{0, 0}, polar(60, 10 * deg), 20, 55, 45, 30 * deg},
      {{-10, 5}, Vector2d(-10, 5) + polar(45, -35 * deg), 15, 50, 40, 200 * deg},
  };
  for (const auto& c : cases)
    for (const int branch : {1, -1}) {
      const oracles::FourBar f{c.O2, c.O4, c.a, c.b, c.c, branch};
      const auto m = kin::compile(four_bar(f, c.crank_drawing, "crank", "rocker"));
      const double th4_0 = f.solve(c.crank_drawing).rocker_angle[0];
      // through sweep(): angles in deg, derivatives per driver deg
      kin::SweepSpec spec;
      spec.start = 0;
      spec.stop = 360;
      spec.step = kSweepStepDeg;
      const kin::SweepResult r = kin::sweep(m, spec);
      REQUIRE(r.positions.size() == 1);
      INFO(r.positions[0].status.str());
      REQUIRE(r.positions[0].status.ok());
      REQUIRE(r.driver.size() == static_cast<std::size_t>(kSweepPoints));
      const int v = m.nodes[static_cast<std::size_t>(m.node_index("rocker"))].first_variable;
      SweepCompare rocker("four-bar a " + std::to_string(c.a) + " branch " + std::to_string(branch), true);
      for (std::size_t i = 0; i < r.driver.size(); ++i) {
        Motion k;
        for (int o = 0; o <= 3; ++o) k[static_cast<std::size_t>(o)] = r.positions[0].value(i, v, o) * std::pow(deg, 1 - o);
        auto ref = f.solve(c.crank_drawing + r.driver[i] * deg).rocker_angle;
        ref[0] = wrap_angle(ref[0] - th4_0);
        rocker.add(r.driver[i], k, ref);
      }
      CHECK_COMPARISONS(rocker.compare());
      // the compiled plan keeps the branch of the drawing
      REQUIRE(m.plan.size() == 1);
      CHECK(m.plan[0].method == kin::StepMethod::link_closed_form);
    }
}

TEST_CASE("closed form (d): four-bar driven by the rocker (any node can drive)", "[kinematics][closed_form]") {
  const Vector2d O2(0, 0), O4 = polar(60, 10 * deg);
  for (const int branch : {1, -1}) {
    const oracles::FourBar f{O2, O4, 20, 55, 45, branch};
    // the rocker's swing over a crank revolution
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i < 3600; ++i) {
      const double th4 = f.solve(i * 0.1 * deg).rocker_angle[0];
      lo = std::min(lo, th4);
      hi = std::max(hi, th4);
    }
    // drawing with the rocker mid-swing; the crank follows on the branch of the drawing
    double crank0 = 0.0;
    for (int i = 0; i < 3600; ++i)
      if (std::abs(f.solve(i * 0.1 * deg).rocker_angle[0] - 0.5 * (lo + hi)) <
          std::abs(f.solve(crank0).rocker_angle[0] - 0.5 * (lo + hi)))
        crank0 = i * 0.1 * deg;
    const double th4_0 = f.solve(crank0).rocker_angle[0];
    oracles::FourBar inv{O4, O2, 45, 55, 20, 1};
    inv.branch = inv.branch_through(th4_0, crank0);
    const auto m = kin::compile(four_bar(f, crank0, "rocker", "crank"));
    // stay 10 % of the swing away from the dead points (crank and coupler in line)
    const double margin = 0.1 * (hi - lo);
    SweepCompare crank("four-bar driven by the rocker, branch " + std::to_string(branch), true);
    run(m, range(lo + margin - th4_0, hi - margin - th4_0, 400), false,
        [&](std::size_t, double q, const kin::Workspace& ws) {
          auto ref = inv.solve(th4_0 + q).rocker_angle;
          ref[0] = wrap_angle(ref[0] - crank0);
          crank.add(q, motion_of(node_jet(m, ws, "crank")), ref);
        });
    CHECK_COMPARISONS(crank.compare());
  }
}

TEST_CASE("closed form (e): offset slider-crank, driven by the crank and by the slider",
          "[kinematics][closed_form]") {
  struct Case {
    Vector2d O2;
    double a, b, offset, slide_angle, crank_drawing;
  };
  const Case cases[] = {
      {{0, 0}, 20, 70, 5, 90 * deg, 10 * deg},
      {{8, -4}, 16, 55, -3, 200 * deg, 250 * deg},
  };
  for (const auto& c : cases)
    for (const int branch : {1, -1}) {
      const Vector2d u = polar(1, c.slide_angle), normal(-u.y(), u.x());
      oracles::SliderCrank s{c.O2, c.a, c.b, c.O2 + c.offset * normal, u, branch, 1};
      const std::string name = "slider-crank a " + std::to_string(c.a) + " branch " + std::to_string(branch);
      {
        const auto m = kin::compile(slider_crank(s, c.crank_drawing, "crank", "slider"));
        const double x0 = s.solve(c.crank_drawing).slider[0];
        SweepCompare slider(name, false);
        run(m, revolution(), false, [&](std::size_t, double t, const kin::Workspace& ws) {
          auto ref = s.solve(c.crank_drawing + t).slider;
          ref[0] -= x0;
          slider.add(t, motion_of(node_jet(m, ws, "slider")), ref);
        });
        CHECK_COMPARISONS(slider.compare());
      }
      {
        // drawing at mid-stroke (crank normal to the slide), slider driven +-12 mm: the
        // crank stays well away from the dead centres
        const double mid = c.slide_angle + pi / 2;
        const double x0 = s.solve(mid).slider[0];
        s.crank_branch = s.crank_branch_through(x0, mid);
        const auto m = kin::compile(slider_crank(s, mid, "slider", "crank"));
        SweepCompare crank(name + " driven by the slider", true);
        run(m, range(-12, 12, 480), false, [&](std::size_t, double q, const kin::Workspace& ws) {
          auto ref = s.invert(x0 + q).slider;
          ref[0] = wrap_angle(ref[0] - mid);
          crank.add(q, motion_of(node_jet(m, ws, "crank")), ref);
        });
        CHECK_COMPARISONS(crank.compare());
      }
    }
}

TEST_CASE("closed form (f): gear pair and rack-pinion, driven from either end", "[kinematics][closed_form]") {
  const oracles::GearPair g{-0.5};
  for (const bool from_output : {false, true}) {
    DesignSpec d = design("gears", from_output ? "cam" : "crank", from_output ? "crank" : "cam");
    d.nodes = {rotational("crank", {0, 0}), rotational("cam", {0, 120})};
    ConnectionSpec c;
    c.name = "timing";
    c.kind = ConnectionKind::gear;
    c.node_a = "crank";
    c.node_b = "cam";
    c.ratio = g.ratio;
    d.connections = {c};
    const auto m = kin::compile(d);
    SweepCompare cmp(from_output ? "gear driven by its output" : "gear", false);
    run(m, revolution(), false, [&](std::size_t, double t, const kin::Workspace& ws) {
      cmp.add(t, motion_of(node_jet(m, ws, from_output ? "crank" : "cam")), from_output ? g.input(t) : g.output(t));
    });
    CHECK_COMPARISONS(cmp.compare());
  }
  const oracles::RackPinion rp{12.0};
  for (const bool from_rack : {false, true}) {
    DesignSpec d = design("rack", from_rack ? "rack" : "pinion", from_rack ? "pinion" : "rack");
    d.nodes = {rotational("pinion", {0, 0}), translational("rack", {0, -12}, {1, 0})};
    ConnectionSpec c;
    c.name = "mesh";
    c.kind = ConnectionKind::rack_pinion;
    c.node_a = "pinion";
    c.node_b = "rack";
    c.pitch_radius_mm = rp.pitch_radius;
    d.connections = {c};
    const auto m = kin::compile(d);
    SweepCompare cmp(from_rack ? "rack driving the pinion" : "pinion driving the rack", false);
    const auto drive = from_rack ? range(-30, 30, 600) : revolution();
    run(m, drive, false, [&](std::size_t, double t, const kin::Workspace& ws) {
      cmp.add(t, motion_of(node_jet(m, ws, from_rack ? "pinion" : "rack")), from_rack ? rp.pinion(t) : rp.rack(t));
    });
    CHECK_COMPARISONS(cmp.compare());
  }
}

TEST_CASE("closed form (g): flat tappet on a polar table cam (support function)", "[kinematics][closed_form]") {
  const PeriodicSpline spline = lobe_spline();
  struct Case {
    double orientation;
    Placement place;
  };
  const Case cases[] = {{90 * deg, {0.0, {0, 0}}}, {0.0, {15 * deg, {5, -5}}}, {-150 * deg, {-100 * deg, {-20, 10}}}};
  for (const auto& c : cases) {
    const oracles::FlatFollowerPolarCam o{[&](double phi, double* r) { spline.evaluate(phi, 3, r); }, c.orientation};
    const double y0 = o.face_height(0)[0];
    const auto m = kin::compile(polar_flat(c.orientation, y0, c.place));
    const std::string name = "polar flat orientation " + std::to_string(c.orientation / deg);
    SweepCompare lift(name, false);
    ScalarCompare curvature(name + " curvature"), cx(name + " contact x");
    run(m, revolution(), true, [&](std::size_t, double t, const kin::Workspace& ws) {
      lift.add(t, motion_of(node_jet(m, ws, "tappet")), o.lift(t));
      const auto& cs = ws.contacts[0];
      // radius of curvature = s + s'' + face height at rest [norton]
      curvature.add(t, cs.curvature_a, 1.0 / o.radius_of_curvature(t));
      cx.add(t, local_point(c.place, cs.x, cs.y).x(), o.contact_x(t));
    });
    CHECK_COMPARISONS(lift.compare());
    CHECK_SERIES(curvature.compare(kCurvatureRel));
    CHECK_SERIES(cx.compare(0.0, kContactPointRel * m.length_scale));
  }
}

TEST_CASE("closed form (g): pressure angle of a flat tappet normal to its travel is zero",
          "[kinematics][closed_form]") {
  // acos(|dir . n|) would lose half the digits near 0 (acos(1 - eps) = sqrt(2 eps) = 1.5e-8
  // rad); the kernel takes atan2(|dir x n|, |dir . n|), exact to round-off there
  const PeriodicSpline spline = lobe_spline();
  for (const double orientation : {90 * deg, 0.0}) {
    const oracles::FlatFollowerPolarCam o{[&](double phi, double* r) { spline.evaluate(phi, 3, r); }, orientation};
    const auto m = kin::compile(polar_flat(orientation, o.face_height(0)[0], {}));
    ScalarCompare pa("polar flat pressure angle, orientation " + std::to_string(orientation / deg));
    run(m, revolution(), true,
        [&](std::size_t, double t, const kin::Workspace& ws) { pa.add(t, ws.contacts[0].pressure_angle, 0.0); });
    CHECK_SERIES(pa.compare(0.0, kPressureAngleAbs));
  }
}
