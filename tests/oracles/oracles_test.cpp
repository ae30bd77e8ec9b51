// the closed-form oracles checked against themselves: every analytic derivative against
// an 8th-order central finite difference of the oracle's own displacement, every position
// against its closure condition, and the oracles that describe the same mechanism in two
// ways against each other.
#include "oracles/oracles.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

namespace {

using namespace camopt::oracles;
using Eigen::Vector2d;
using camopt::test::Series;
namespace tol = camopt::test::tol;

constexpr double pi = std::numbers::pi;
constexpr double deg = pi / 180.0;

// finite differences of a smooth closed form: 8th-order stencils, steps balancing
// truncation (h^8) against round-off (eps / h^k) [rad or mm]
constexpr int kHalfWidth[4] = {0, 4, 4, 5};
constexpr double kStep[4] = {0.0, 1e-3, 1e-2, 2e-2};

// the polar table cam of the kinematics tests: r = 18 + 3 (1 - cos phi)^2 / 4 [mm]
void lobe_radius(double phi, double* r) {
  const double c = std::cos(phi), s = std::sin(phi), k = 1.0 - c;
  r[0] = 18.0 + 0.75 * k * k;
  r[1] = 1.5 * k * s;
  r[2] = 1.5 * (s * s + k * c);
  r[3] = 1.5 * (4.0 * s * c - s);  // d/dphi (s^2 + c - c^2)
}

// polar radius of a disc R centred at (e, 0): r = e cos phi + sqrt(R^2 - e^2 sin^2 phi),
// q = sqrt(f) differentiated through q^2 = f
void disc_radius(double R, double e, double phi, double* r) {
  const double s = std::sin(phi), c = std::cos(phi), s2 = std::sin(2 * phi), c2 = std::cos(2 * phi);
  const double f0 = R * R - e * e * s * s, f1 = -e * e * s2, f2 = -2 * e * e * c2, f3 = 4 * e * e * s2;
  const double q0 = std::sqrt(f0), q1 = f1 / (2 * q0), q2 = (f2 - 2 * q1 * q1) / (2 * q0),
               q3 = (f3 - 6 * q1 * q2) / (2 * q0);
  r[0] = e * c + q0;
  r[1] = -e * s + q1;
  r[2] = -e * c + q2;
  r[3] = e * s + q3;
}

// every analytic derivative of f over [t0, t1) against finite differences of f[0];
// angle: f[0] is an angle, differenced after unwrapping around the sample; input_scale:
// the steps are kStep * input_scale (10 for an input in mm on a ~50 mm mechanism)
void check_derivatives(const std::string& name, const std::function<Motion(double)>& f, double t0, double t1,
                       int samples, bool angle = false, double input_scale = 1.0) {
  // d^k analytic against its finite difference, within kOracleFdRel of the peak |d^k|
  std::vector<Series> derivative;
  for (int k = 1; k <= 3; ++k) derivative.emplace_back(name + ": d^" + std::to_string(k), "t");
  for (int i = 0; i < samples; ++i) {
    const double t = t0 + (t1 - t0) * static_cast<double>(i) / samples;
    const Motion exact = f(t);
    const double x0 = exact[0];
    auto value = [&](double x) {
      const double v = f(x)[0];
      return angle ? x0 + wrap_angle(v - x0) : v;
    };
    for (int k = 1; k <= 3; ++k)
      derivative[static_cast<std::size_t>(k - 1)].add(
          t, exact[static_cast<std::size_t>(k)], central_difference(value, t, k, kHalfWidth[k], kStep[k] * input_scale));
  }
  for (const Series& d : derivative) CHECK_SERIES(d.compare({.rel = tol::kOracleFdRel}));
}

}  // namespace

TEST_CASE("oracles: fornberg weights reproduce the classical stencils", "[oracles]") {
  const auto d1 = central_weights(1, 1);
  CHECK_REL(d1[0], -0.5, tol::kUlpRel);
  CHECK_ABS(d1[1], 0.0, tol::kUlpAbs);
  CHECK_REL(d1[2], 0.5, tol::kUlpRel);
  const auto d2 = central_weights(2, 1);
  CHECK_REL(d2[0], 1.0, tol::kUlpRel);
  CHECK_REL(d2[1], -2.0, tol::kUlpRel);
  CHECK_REL(d2[2], 1.0, tol::kUlpRel);
  // 8th-order first derivative: 1/280, -4/105, 1/5, -4/5, 0, ...
  const auto d8 = central_weights(1, 4);
  CHECK_REL(d8[0], 1.0 / 280, tol::kUlpRel);
  CHECK_REL(d8[1], -4.0 / 105, tol::kUlpRel);
  CHECK_REL(d8[2], 1.0 / 5, tol::kUlpRel);
  CHECK_REL(d8[3], -4.0 / 5, tol::kUlpRel);
  CHECK_REL(d8[5], 4.0 / 5, tol::kUlpRel);
  CHECK_REL(d8[8], -1.0 / 280, tol::kUlpRel);
  // a 9th-degree polynomial is differentiated exactly by the 11-point third-derivative stencil
  auto p = [](double x) { return std::pow(x, 9) - 2 * std::pow(x, 5) + x; };
  const double x0 = 0.3, h = 0.05;
  const double exact = 504 * std::pow(x0, 6) - 120 * x0 * x0;
  CHECK_REL(central_difference(p, x0, 3, 5, h), exact, tol::kExactStencilRel);
}

TEST_CASE("oracles: (a) eccentric disc + flat follower is simple harmonic", "[oracles]") {
  for (const double phase : {0.0, 0.4, -pi / 2}) {
    const EccentricFlatFollower o{20.0, 4.0, phase};
    check_derivatives("flat phase " + std::to_string(phase), [&](double t) { return o.lift(t); }, 0, 2 * pi, 48);
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg;
      CHECK_ABS(o.lift(t)[0], 4.0 * (std::sin(t + phase) - std::sin(phase)), tol::kOracleRoundOffAbs);
      CHECK_ABS(o.contact_x(t), o.lift(t)[1], tol::kOracleRoundOffAbs);
    }
  }
}

TEST_CASE("oracles: (b) eccentric disc + offset translating roller", "[oracles]") {
  for (const double offset : {3.0, -4.0, 0.0}) {
    const EccentricOffsetRoller o{18.0, 3.0, 0.3, 9.0, offset};
    const std::string name = "roller offset " + std::to_string(offset);
    check_derivatives(name, [&](double t) { return o.lift(t); }, 0, 2 * pi, 48);
    // closure: roller centre at distance R + r from the disc centre
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg, phi = t + o.phase;
      const Vector2d centre(offset, o.centre_height(t)[0]);
      const Vector2d disc = 3.0 * Vector2d(std::cos(phi), std::sin(phi));
      CHECK_ABS((centre - disc).norm(), 27.0, tol::kClosureAbs);
      // the same mechanism as the slider-crank {crank e, rod R + r, slide x = offset along +y}
      const SliderCrank sc{Vector2d(0, 0), 3.0, 27.0, Vector2d(offset, 0), Vector2d(0, 1), 1, 1};
      const auto s = sc.solve(phi).slider;
      const auto y = o.centre_height(t);
      for (std::size_t k = 0; k <= 3; ++k) CHECK_NEAR(s[k], y[k], tol::kOracleTwoFormsRel, tol::kOracleTwoFormsRel);
      // pressure angle: instant-centre form equals the angle of the normal to the follower axis
      const Vector2d n = (centre - disc).normalized();
      // (atan2 rather than acos(|n.y|): acos near 1 would lose ~eps / angle)
      CHECK_ABS(o.pressure_angle(t), std::atan2(std::abs(n.x()), std::abs(n.y())), tol::kOraclePressureAngleAbs);
    }
  }
}

TEST_CASE("oracles: (d) four-bar position, derivatives and inversion, both branches", "[oracles]") {
  // grashof crank-rocker: s + l = 20 + 60 < p + q = 55 + 45, ground tilted 10 deg
  const Vector2d O2(5, -3), O4 = O2 + 60 * Vector2d(std::cos(10 * deg), std::sin(10 * deg));
  for (const int branch : {1, -1}) {
    const FourBar fb{O2, O4, 20, 55, 45, branch};
    const std::string name = "four-bar branch " + std::to_string(branch);
    check_derivatives(name + " rocker", [&](double t) { return fb.solve(t).rocker_angle; }, 0, 2 * pi, 48, true);
    check_derivatives(name + " coupler", [&](double t) { return fb.solve(t).coupler_angle; }, 0, 2 * pi, 48, true);
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg;
      REQUIRE(fb.assembles(t));
      const auto s = fb.solve(t);
      const Vector2d A = O2 + 20 * Vector2d(std::cos(t), std::sin(t));
      const Vector2d B = O4 + 45 * Vector2d(std::cos(s.rocker_angle[0]), std::sin(s.rocker_angle[0]));
      CHECK_ABS((B - A).norm(), 55.0, tol::kClosureAbs);
      CHECK_ABS(wrap_angle(std::atan2(B.y() - A.y(), B.x() - A.x()) - s.coupler_angle[0]), 0.0,
                tol::kCouplerDirectionAbs);
      CHECK(fb.branch_through(t, s.rocker_angle[0]) == branch);
      // inversion: the rocker drives, the crank follows; derivatives of an inverse function
      // x(y): x' = 1/y', x'' = -y''/y'^3, x''' = (3 y''^2 - y' y''')/y'^5
      const FourBar inv{O4, O2, 45, 55, 20, 1};
      FourBar inv_b = inv;
      inv_b.branch = inv.branch_through(s.rocker_angle[0], t);
      const auto back = inv_b.solve(s.rocker_angle[0]).rocker_angle;
      CHECK_ABS(wrap_angle(back[0] - t), 0.0, tol::kFourBarInverseAbs);
      const auto& y = s.rocker_angle;
      if (std::abs(y[1]) > 0.05) {  // away from the rocker's dead points
        const double (&r)[4] = tol::kInverseRateRel;
        CHECK_NEAR(back[1], 1 / y[1], r[1], r[1]);
        CHECK_NEAR(back[2], -y[2] / std::pow(y[1], 3), r[2], r[2]);
        const double x3 = (3 * y[2] * y[2] - y[1] * y[3]) / std::pow(y[1], 5);
        CHECK_NEAR(back[3], x3, r[3], r[3]);
      }
    }
  }
  // a crank too long for coupler + rocker does not assemble everywhere
  const FourBar bad{Vector2d(0, 0), Vector2d(60, 0), 30, 40, 25, 1};
  CHECK(bad.assembles(0.0));
  CHECK_FALSE(bad.assembles(pi));
}

TEST_CASE("oracles: (c) eccentric disc + oscillating roller follower", "[oracles]") {
  for (const int branch : {1, -1}) {
    const EccentricOscillatingRoller o{18.0, 3.0, 0.5, 9.0, Vector2d(-20, 38), 36.0, branch};
    const std::string name = "oscillating branch " + std::to_string(branch);
    check_derivatives(name, [&](double t) { return o.lift(t); }, 0, 2 * pi, 48, true);
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg, phi = t + o.phase;
      const double psi = o.arm_angle(t)[0];
      const Vector2d centre = o.arm_pivot + 36.0 * Vector2d(std::cos(psi), std::sin(psi));
      const Vector2d disc = 3.0 * Vector2d(std::cos(phi), std::sin(phi));
      CHECK_ABS((centre - disc).norm(), 27.0, tol::kClosureAbs);
      // pressure angle from the geometry: normal (disc -> roller) against the roller
      // centre's velocity (normal to the arm)
      const Vector2d n = (centre - disc).normalized();
      const Vector2d v = Vector2d(-(centre - o.arm_pivot).y(), (centre - o.arm_pivot).x()).normalized();
      CHECK_ABS(o.pressure_angle(t), std::atan2(std::abs(n.x() * v.y() - n.y() * v.x()), std::abs(n.dot(v))),
                tol::kOraclePressureAngleAbs);
    }
  }
}

TEST_CASE("oracles: (e) offset slider-crank and its inversion", "[oracles]") {
  const Vector2d dir = Vector2d(std::cos(100 * deg), std::sin(100 * deg));
  for (const int branch : {1, -1}) {
    SliderCrank sc{Vector2d(2, 1), 20.0, 70.0, Vector2d(2, 1) + 5.0 * Vector2d(-dir.y(), dir.x()), dir, branch, 1};
    const std::string name = "slider-crank branch " + std::to_string(branch);
    check_derivatives(name + " slider", [&](double t) { return sc.solve(t).slider; }, 0, 2 * pi, 48);
    check_derivatives(name + " rod", [&](double t) { return sc.solve(t).rod_angle; }, 0, 2 * pi, 48, true);
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg;
      const auto s = sc.solve(t);
      const Vector2d A = sc.crank_pivot + 20.0 * Vector2d(std::cos(t), std::sin(t));
      const Vector2d B = sc.slide_point + s.slider[0] * dir;
      CHECK_ABS((B - A).norm(), 70.0, tol::kClosureAbs);
      // inversion from the slider position gives the crank angle back
      SliderCrank inv = sc;
      inv.crank_branch = sc.crank_branch_through(s.slider[0], t);
      const auto back = inv.invert(s.slider[0]);
      CHECK_ABS(wrap_angle(back.slider[0] - t), 0.0, tol::kSliderCrankInverseAbs);
      CHECK_ABS(wrap_angle(back.rod_angle[0] - s.rod_angle[0]), 0.0, tol::kSliderCrankInverseAbs);
    }
    // derivatives of the inversion over a stroke away from the dead centres
    // (mid-stroke: crank normal to the slide)
    const double t_mid = 190 * deg, x_mid = sc.solve(t_mid).slider[0];
    sc.crank_branch = sc.crank_branch_through(x_mid, t_mid);
    check_derivatives(name + " inverse crank", [&](double x) { return sc.invert(x).slider; }, x_mid - 12,
                      x_mid + 12, 40, true, 10.0);
  }
}

TEST_CASE("oracles: (f) gear pair and rack-pinion from either end", "[oracles]") {
  const GearPair g{-0.5};
  CHECK_REL(g.output(1.2)[0], -0.6, tol::kUlpRel);
  CHECK_REL(g.output(1.2)[1], -0.5, tol::kUlpRel);
  CHECK_REL(g.input(-0.6)[0], 1.2, tol::kUlpRel);
  CHECK_REL(g.input(0.0)[1], -2.0, tol::kUlpRel);
  const RackPinion rp{12.0};
  CHECK_REL(rp.rack(0.5)[0], 6.0, tol::kUlpRel);
  CHECK_REL(rp.pinion(6.0)[0], 0.5, tol::kUlpRel);
  CHECK_REL(rp.pinion(6.0)[1], 1.0 / 12.0, tol::kUlpRel);
  for (int k = 2; k <= 3; ++k) {
    CHECK(g.output(0.3)[static_cast<std::size_t>(k)] == 0.0);
    CHECK(rp.pinion(0.3)[static_cast<std::size_t>(k)] == 0.0);
  }
}

TEST_CASE("oracles: (g) flat tappet on a polar cam by its support function", "[oracles]") {
  for (const double orientation : {0.0, 0.7, -2.0}) {
    FlatFollowerPolarCam o{lobe_radius, orientation};
    const std::string name = "polar flat orientation " + std::to_string(orientation);
    check_derivatives(name, [&](double t) { return o.lift(t); }, 0, 2 * pi, 48);
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg, psi = pi / 2 - orientation - t;
      const double phi = o.contact_polar_angle(t);
      double r[4];
      lobe_radius(phi, r);
      const Motion y = o.face_height(t);
      // the contact point (profile angle phi, turned by orientation + theta) lies on the face
      const double a = phi + orientation + t;
      CHECK_REL(r[0] * std::sin(a), y[0], tol::kSupportPointRel);
      CHECK_ABS(r[0] * std::cos(a), o.contact_x(t), tol::kSupportContactAbs);
      // and it is the farthest point along the face normal
      for (int j = 0; j < 360; ++j) {
        double q[4];
        lobe_radius(j * deg, q);
        CHECK(q[0] * std::cos(j * deg - psi) <= y[0] + tol::kSupportContactAbs);
      }
      // radius of curvature = face height + its second derivative [norton]
      CHECK_REL(o.radius_of_curvature(t), y[0] + y[2], tol::kOracleTwoFormsRel);
    }
  }
  // a disc as a polar curve has the support function of (a)
  const double R = 20, e = 4;
  for (const double orientation : {0.0, 1.1}) {
    FlatFollowerPolarCam o{[&](double phi, double* r) { disc_radius(R, e, phi, r); }, orientation};
    const EccentricFlatFollower a{R, e, orientation};
    for (int i = 0; i < 24; ++i) {
      const double t = i * 15 * deg;
      const Motion g = o.face_height(t), h = a.face_height(t);
      for (std::size_t k = 0; k <= 3; ++k) CHECK_ABS(g[k], h[k], tol::kOracleTwoFormsRel * R);
      CHECK_REL(o.radius_of_curvature(t), R, tol::kOracleTwoFormsRel);
    }
  }
}
