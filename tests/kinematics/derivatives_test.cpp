// the kernel's exact derivatives (jets through an implicit contact on a spline table cam)
// against high-order central differences of its own solutions, and the per-contact outputs
// against independent geometric closed forms.
//
// cam: the polar table r(phi) = 18 + 3 (1 - cos phi)^2 / 4 [mm] at 1 deg, interpolated by
// the kernel's periodic quintic spline; the same spline, built here from the same table,
// gives the reference geometry. the cam turns counter-clockwise about the origin; every
// rate is per rad of cam.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/core/spline.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "oracles/finite_difference.hpp"

using namespace camopt;
using namespace camopt::kin_test;

namespace {

// central differences of solved quantities: step ~1e-3 rad, 8th- and 6th-order stencils;
// the solver's round-off (~1e-13 mm) over h = 1e-3 stays far below the tolerance
constexpr double kStep = 1e-3;         // [rad]
constexpr int kHalfWidth8 = 4;         // 9 points, 8th order
constexpr int kHalfWidth6 = 3;         // 7 points, 6th order

constexpr double kRoller = 9.0;  // roller radius [mm]
constexpr int kSamples = 36;     // driver samples over a revolution
constexpr double kSampleOffset = 3.7 * deg;

// the profile's polar angle 0 points along `orientation` in the drawing, where r' = 0:
// the contact normal there is radial, so each drawing below is assembled exactly at theta = 0
//
// oscillating roller: roller centre on the ray at 90 deg, arm pivot 36 mm away at 160 deg
DesignSpec table_oscillating_roller() {
  DesignSpec d = design("table_oscillating_roller", "cam", "arm");
  const double o = 90 * deg;
  const Vector2d centre = (18.0 + kRoller) * Vector2d(std::cos(o), std::sin(o));
  const Vector2d pivot = centre + 36.0 * Vector2d(std::cos(160 * deg), std::sin(160 * deg));
  d.nodes = {rotational("cam", {0, 0}), rotational("arm", {pivot.x(), pivot.y()})};
  d.profiles = {lobe_table("lobe")};
  d.connections = {contact("cam_roller", profile_surface("cam", "lobe", {0, 0}, o / deg),
                           circle_surface("arm", {centre.x(), centre.y()}, kRoller, true))};
  return d;
}

// offset translating roller: follower axis x = offset moving along +y; the profile's 0 axis
// points at the roller centre (offset, Y0)
constexpr double kOffset = 4.0;  // [mm]
double roller_orientation() { return std::acos(kOffset / (18.0 + kRoller)); }
double roller_rest_height() { return (18.0 + kRoller) * std::sin(roller_orientation()); }
DesignSpec table_offset_roller() {
  DesignSpec d = design("table_offset_roller", "cam", "tappet");
  const Vec2 centre{kOffset, roller_rest_height()};
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", centre, {0, 1})};
  d.profiles = {lobe_table("lobe")};
  d.connections = {contact("cam_roller", profile_surface("cam", "lobe", {0, 0}, roller_orientation() / deg),
                           circle_surface("tappet", centre, kRoller, true))};
  return d;
}

// flat-faced translating tappet, face normal to its travel (+y), resting on r(0) = 18
DesignSpec table_flat() {
  DesignSpec d = design("table_flat", "cam", "tappet");
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, 18}, {0, 1})};
  d.profiles = {lobe_table("lobe")};
  d.connections = {
      contact("cam_tappet", profile_surface("cam", "lobe", {0, 0}, 90), line_surface("tappet", {0, 18}, {0, -1}))};
  return d;
}

// what a stencil needs from one solve
struct Point {
  Jet<3> follower, parameter;
  kin::ContactState contact;
};

// solve at theta0 + j h, j = -m..m, in order (warm starts chain through the stencil)
std::vector<Point> stencil(const kin::Mechanism& m, const std::string& follower, double theta0, int half) {
  kin::Workspace ws(m);
  kin::Request rq;
  rq.contacts = true;
  const int u = m.connections[0].surface_a.variable;
  REQUIRE(u >= 0);
  std::vector<Point> out;
  for (int j = -half; j <= half; ++j) {
    const Status st = kin::solve(m, ws, theta0 + j * kStep, rq);
    INFO(st.str());
    REQUIRE(st.ok());
    out.push_back({node_jet(m, ws, follower), ws.vars[static_cast<std::size_t>(u)], ws.contacts[0]});
  }
  return out;
}

template <class F>
std::vector<double> map(const std::vector<Point>& pts, F f) {
  std::vector<double> v;
  for (const auto& p : pts) v.push_back(f(p));
  return v;
}


double sample(int i) { return kSampleOffset + 2.0 * pi * i / kSamples; }

// the driver angle near theta whose contact parameter u lies mid-way between two knots of
// the table (knots every 1 deg): the quintic spline is C4, r^(5) jumps at the knots, and the
// contact parameter's k-th derivative involves r^(k+1), so its jerk has a kink at every knot
// that a stencil straddling one would smear (the follower's own jerk involves r''' only)
double centred_in_piece(const kin::Mechanism& m, double theta) {
  kin::Workspace ws(m);
  const int u = m.connections[0].surface_a.variable;
  for (int it = 0; it < 4; ++it) {
    REQUIRE(kin::solve(m, ws, theta, {}).ok());
    const Jet<3>& j = ws.vars[static_cast<std::size_t>(u)];
    const double target = (std::floor(j.value() / deg) + 0.5) * deg;
    REQUIRE(std::abs(j.derivative(1)) > 0.1);
    theta += (target - j.value()) / j.derivative(1);
  }
  REQUIRE(kin::solve(m, ws, theta, {}).ok());
  const Jet<3>& j = ws.vars[static_cast<std::size_t>(u)];
  // the stencil's reach in u stays inside the piece
  CHECK_ABS(j.value() / deg - std::floor(j.value() / deg), 0.5, kNewtonCentringAbs);
  CHECK(kHalfWidth8 * kStep * std::abs(j.derivative(1)) < 0.5 * deg);
  return theta;
}

// the polar angle phi of the cam point nearest the oscillating roller's centre, in the
// profile's frame (its 0 axis along `orientation`): the centre C turned by the arm angle q
// about the arm pivot, then taken into the cam's frame (turned back by theta), and
// (C - p(phi)) . p'(phi) = 0 for p(phi) = r(phi) (cos(phi + o), sin(phi + o)), by Newton from
// the centre's own polar angle
double contact_polar_angle(const PeriodicSpline& r, double orientation, double theta, double q) {
  const double o = orientation;
  const Vector2d centre = (18.0 + kRoller) * Vector2d(std::cos(o), std::sin(o));
  const Vector2d pivot = centre + 36.0 * Vector2d(std::cos(160 * deg), std::sin(160 * deg));
  const Vector2d a = centre - pivot;
  const Vector2d C = pivot + Vector2d(std::cos(q) * a.x() - std::sin(q) * a.y(), std::sin(q) * a.x() + std::cos(q) * a.y());
  const Vector2d Cc(std::cos(theta) * C.x() + std::sin(theta) * C.y(), -std::sin(theta) * C.x() + std::cos(theta) * C.y());
  double phi = std::atan2(Cc.y(), Cc.x()) - o;
  for (int it = 0; it < 30; ++it) {
    double d[4];
    r.evaluate(phi, 3, d);
    const Vector2d e(std::cos(phi + o), std::sin(phi + o)), n(-e.y(), e.x());
    const Vector2d p = d[0] * e, p1 = d[1] * e + d[0] * n, p2 = (d[2] - d[0]) * e + 2.0 * d[1] * n;
    const double f = (Cc - p).dot(p1), f1 = (Cc - p).dot(p2) - p1.dot(p1);
    const double step = f / f1;
    phi -= step;
    if (std::abs(step) < 1e-15) break;
  }
  return phi;
}

}  // namespace

TEST_CASE("derivatives: oscillating roller on a table cam, jets against central differences",
          "[kinematics][derivatives]") {
  const auto m = kin::compile(table_oscillating_roller());
  for (const char* quantity : {"arm angle", "contact parameter"}) {
    const bool arm = std::string(quantity) == "arm angle";
    ScalarCompare v8{std::string(quantity) + " velocity, 8th order from displacement"};
    ScalarCompare v6{std::string(quantity) + " velocity, 6th order from displacement"};
    ScalarCompare a8{std::string(quantity) + " acceleration, 8th order from velocity"};
    ScalarCompare a6{std::string(quantity) + " acceleration, 6th order from velocity"};
    ScalarCompare a2{"arm angle acceleration, 8th-order second difference of displacement"};
    ScalarCompare j8{std::string(quantity) + " jerk, 8th order from acceleration"};
    ScalarCompare j6{std::string(quantity) + " jerk, 6th order from acceleration"};
    for (int i = 0; i < kSamples; ++i) {
      const double t = arm ? sample(i) : centred_in_piece(m, sample(i));
      const auto pts = stencil(m, "arm", t, kHalfWidth8);
      auto order = [&](int k) {
        return map(pts, [&](const Point& p) { return (arm ? p.follower : p.parameter).derivative(k); });
      };
      auto inner = [](std::vector<double> v) {  // the 6th-order stencil's central samples
        constexpr int trim = kHalfWidth8 - kHalfWidth6;
        return std::vector<double>(v.begin() + trim, v.end() - trim);
      };
      const Jet<3>& centre = arm ? pts[kHalfWidth8].follower : pts[kHalfWidth8].parameter;
      v8.add(t, centre.derivative(1), oracles::central_difference(order(0), 1, kStep));
      v6.add(t, centre.derivative(1), oracles::central_difference(inner(order(0)), 1, kStep));
      a8.add(t, centre.derivative(2), oracles::central_difference(order(1), 1, kStep));
      a6.add(t, centre.derivative(2), oracles::central_difference(inner(order(1)), 1, kStep));
      // a second difference of the displacement itself amplifies its round-off by 1/h^2:
      // only for the arm angle, whose samples are not tied to the spline pieces
      if (arm) a2.add(t, centre.derivative(2), oracles::central_difference(order(0), 2, kStep));
      j8.add(t, centre.derivative(3), oracles::central_difference(order(2), 1, kStep));
      j6.add(t, centre.derivative(3), oracles::central_difference(inner(order(2)), 1, kStep));
    }
    for (const ScalarCompare* w : {&v8, &v6, &a8, &a6, &j8, &j6}) CHECK_SERIES(w->compare(kKernelFdRel));
    if (arm) CHECK_SERIES(a2.compare(kKernelFdRel));
  }
}

TEST_CASE("derivatives: contact point velocity and cam curvature on the table cam", "[kinematics][derivatives]") {
  const auto m = kin::compile(table_oscillating_roller());
  const PeriodicSpline r = lobe_spline();
  const double o = 90 * deg;
  ScalarCompare vx{"contact point x velocity"}, vy{"contact point y velocity"}, vt{"contact point tangential velocity"};
  ScalarCompare curvature{"cam curvature"}, roller{"roller speed"}, sliding{"sliding of a roller"};
  ScalarCompare polar{"contact polar angle"};
  for (int i = 0; i < kSamples; ++i) {
    const double t = sample(i);
    const auto pts = stencil(m, "arm", t, kHalfWidth8);
    const Point& c = pts[kHalfWidth8];
    const auto& cs = c.contact;
    // contact point velocity: finite differences of the solved contact point against
    // d/dtheta [Rot(theta + o) p(u(theta))] = z x P + Rot(theta + o) p_u(u) u'
    const double fx = oracles::central_difference(map(pts, [](const Point& p) { return p.contact.x; }), 1, kStep);
    const double fy = oracles::central_difference(map(pts, [](const Point& p) { return p.contact.y; }), 1, kStep);
    double d[4];
    const double u = c.parameter.value(), du = c.parameter.derivative(1);
    r.evaluate(u, 3, d);
    const double px = d[1] * std::cos(u) - d[0] * std::sin(u), py = d[1] * std::sin(u) + d[0] * std::cos(u);
    const double a = t + o;
    const double ex = -cs.y + (std::cos(a) * px - std::sin(a) * py) * du;
    const double ey = cs.x + (std::sin(a) * px + std::cos(a) * py) * du;
    vx.add(t, ex, fx);
    vy.add(t, ey, fy);
    // the tangential part from the kernel's own rates: u_a = entrainment + sliding / 2 is the
    // cam surface speed relative to the contact point, so v_c . t = v_cam . t - u_a
    const Vector2d n(cs.normal_x, cs.normal_y), tangent(-n.y(), n.x());
    const Vector2d v_cam(-cs.y, cs.x);
    vt.add(t, v_cam.dot(tangent) - (cs.entrainment + 0.5 * cs.sliding), Vector2d(fx, fy).dot(tangent));
    // the contact's polar angle against the foot of the roller centre on the cam, solved here
    // from the arm angle alone (Newton on the normal condition, see contact_polar_angle)
    const double foot = contact_polar_angle(r, o, t, c.follower.value());
    polar.add(t, oracles::wrap_angle(cs.polar_angle_a - foot), 0.0);
    // curvature of the interpolated polar curve (r^2 + 2 r'^2 - r r'') / (r^2 + r'^2)^1.5
    // at the contact's polar angle
    r.evaluate(cs.polar_angle_a, 3, d);
    curvature.add(t, cs.curvature_a, 1.0 / oracles::polar_radius_of_curvature(d[0], d[1], d[2]));
    // perfect rolling: omega = 1 + (alpha' - 1)(rho + r)/r - psi' with alpha the direction
    // of the normal (its rate by differences), rho the cam's radius of curvature
    const double n_angle = std::atan2(n.y(), n.x());
    const double alpha1 = oracles::central_difference(map(pts,
                                                           [&](const Point& p) {
                                                             const double a_p = std::atan2(p.contact.normal_y,
                                                                                           p.contact.normal_x);
                                                             return n_angle + oracles::wrap_angle(a_p - n_angle);
                                                           }),
                                                       1, kStep);
    const double rho = oracles::polar_radius_of_curvature(d[0], d[1], d[2]);
    roller.add(t, cs.roller_speed, 1.0 + (alpha1 - 1.0) * (rho + kRoller) / kRoller - c.follower.derivative(1));
    sliding.add(t, cs.sliding, 0.0);
  }
  CHECK_SERIES(vx.compare(kKernelFdRel));
  CHECK_SERIES(vy.compare(kKernelFdRel));
  CHECK_SERIES(vt.compare(kKernelFdRel));
  CHECK_SERIES(polar.compare(0.0, kPressureAngleAbs));
  CHECK_SERIES(curvature.compare(kCurvatureRel));
  CHECK_SERIES(roller.compare(kKernelFdRel));
  CHECK_SERIES(sliding.compare(0.0, kContactRateRel * 20.0));
}

TEST_CASE("derivatives: offset translating roller on the table cam, pressure angle and rolling",
          "[kinematics][derivatives]") {
  // the common normal passes through the roller centre (offset, Y) and through the instant
  // centre of cam and follower, the point (s', 0) of the line through the cam pivot normal
  // to the travel (its cam velocity, z x (s', 0) = (0, s'), is the follower's); so
  //   tan(alpha) = |s' - offset| / Y,   Y = Y0 + s    (norton, offset roller follower)
  // and the normal's direction angle is atan2(Y, offset - s'), turning at
  //   alpha' = (s' (offset - s') + Y s'') / ((offset - s')^2 + Y^2).
  // perfect rolling of the roller (no carrier rotation): omega = 1 + (alpha' - 1)(rho + r)/r.
  const auto m = kin::compile(table_offset_roller());
  const PeriodicSpline r = lobe_spline();
  const double Y0 = roller_rest_height();
  ScalarCompare pressure{"pressure angle"}, roller{"roller speed"}, v8{"lift velocity"}, a8{"lift acceleration"},
      j8{"lift jerk"};
  for (int i = 0; i < kSamples; ++i) {
    const double t = sample(i);
    const auto pts = stencil(m, "tappet", t, kHalfWidth8);
    const Point& c = pts[kHalfWidth8];
    const double s = c.follower.value(), s1 = c.follower.derivative(1), s2 = c.follower.derivative(2);
    const double Y = Y0 + s;
    pressure.add(t, c.contact.pressure_angle, std::atan(std::abs(s1 - kOffset) / Y));
    double d[4];
    r.evaluate(c.contact.polar_angle_a, 3, d);
    const double rho = oracles::polar_radius_of_curvature(d[0], d[1], d[2]);
    const double alpha1 = (s1 * (kOffset - s1) + Y * s2) / ((kOffset - s1) * (kOffset - s1) + Y * Y);
    roller.add(t, c.contact.roller_speed, 1.0 + (alpha1 - 1.0) * (rho + kRoller) / kRoller);
    auto order = [&](int k) { return map(pts, [&](const Point& p) { return p.follower.derivative(k); }); };
    v8.add(t, s1, oracles::central_difference(order(0), 1, kStep));
    a8.add(t, s2, oracles::central_difference(order(1), 1, kStep));
    j8.add(t, c.follower.derivative(3), oracles::central_difference(order(2), 1, kStep));
  }
  CHECK_SERIES(pressure.compare(0.0, kPressureAngleAbs));
  CHECK_SERIES(roller.compare(kContactRateRel));
  CHECK_SERIES(v8.compare(kKernelFdRel));
  CHECK_SERIES(a8.compare(kKernelFdRel));
  CHECK_SERIES(j8.compare(kKernelFdRel));
}

TEST_CASE("derivatives: flat-faced translating tappet on the table cam, sliding and contact travel",
          "[kinematics][derivatives]") {
  // face normal to the travel d = +y at height y = 18 + s above the cam pivot O, cam at unit
  // rate. the contact sits where the face touches the cam's support point; its offset along
  // the face is x_c = s' (envelope of the face lines; norton's face-width rule). with the
  // kernel's tangent t = z x n = z x d = (-1, 0):
  //   cam material at P:      (z x (P - O)) . t = (P - O) . d = y
  //   follower material:      s' d . t = 0
  //   contact point:          d/dtheta (P . t) = d/dtheta (-x_c) = -s''
  // so the material points slide at (v_cam - v_tappet) . t = y (the face height), the
  // contact point runs along the face at s'' relative to the tappet (u_b = (v_tappet - v_c) . t)
  // and along the cam at y + s'' = rho, the cam's radius of curvature (u_a).
  const auto m = kin::compile(table_flat());
  const PeriodicSpline r = lobe_spline();
  ScalarCompare sliding{"sliding velocity"}, along_face{"contact travel along the face"}, along_cam{"contact travel along the cam"},
      offset{"contact offset along the face"}, travel_fd{"contact point velocity along the face"},
      curvature{"cam curvature"};
  for (int i = 0; i < kSamples; ++i) {
    const double t = sample(i);
    const auto pts = stencil(m, "tappet", t, kHalfWidth8);
    const Point& c = pts[kHalfWidth8];
    const auto& cs = c.contact;
    const double y = 18.0 + c.follower.value(), s1 = c.follower.derivative(1), s2 = c.follower.derivative(2);
    const double ua = cs.entrainment + 0.5 * cs.sliding, ub = cs.entrainment - 0.5 * cs.sliding;
    sliding.add(t, cs.sliding, y);
    along_face.add(t, ub, s2);
    along_cam.add(t, ua, y + s2);
    offset.add(t, cs.x, s1);
    travel_fd.add(t, oracles::central_difference(map(pts, [](const Point& p) { return p.contact.x; }), 1, kStep), s2);
    // rho = s + s'' + base: the curvature output against the follower's own motion
    double d[4];
    r.evaluate(cs.polar_angle_a, 3, d);
    curvature.add(t, cs.curvature_a, 1.0 / (y + s2));
    CHECK_REL(1.0 / (y + s2), 1.0 / oracles::polar_radius_of_curvature(d[0], d[1], d[2]), kCurvatureRel);
  }
  CHECK_SERIES(sliding.compare(kContactRateRel));
  CHECK_SERIES(along_face.compare(kContactRateRel));
  CHECK_SERIES(along_cam.compare(kContactRateRel));
  CHECK_SERIES(offset.compare(0.0, kCurvatureRel * m.length_scale));
  CHECK_SERIES(travel_fd.compare(kKernelFdRel));
  CHECK_SERIES(curvature.compare(kCurvatureRel));
}
