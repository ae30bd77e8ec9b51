// where synthesis fails: every window where the profile folds, against the closed-form radius
// of curvature of a translating roller's centre path, and the swing cam's failure message.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "camopt/synthesis/swing_remedy.hpp"
#include "camopt/synthesis/undercut_windows.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::kin_test;
namespace tol = camopt::test::tol;

namespace {

// lift of smooth noses (periodic bumps H exp(k (cos(theta - c) - 1))) and its first two
// derivatives in theta [mm, mm/rad, mm/rad^2]
struct Noses {
  std::vector<double> centre_deg;
  double height = 6.0, sharpness = 20.0;
  void eval(double theta, double d[3]) const {
    d[0] = d[1] = d[2] = 0.0;
    for (double c : centre_deg) {
      const double u = theta - c * deg, b = height * std::exp(sharpness * (std::cos(u) - 1.0));
      d[0] += b;
      d[1] += -sharpness * std::sin(u) * b;
      d[2] += (sharpness * sharpness * std::sin(u) * std::sin(u) - sharpness * std::cos(u)) * b;
    }
  }
};

// a centred translating roller (radius roller) on a cam: its centre path in the cam frame is
// the polar curve R(theta) = y0 + s(theta), whose radius of curvature is
// (R^2 + R'^2)^1.5 / (R^2 + 2 R'^2 - R R'') (Chakraborty & Dhande ch. 3); the envelope cusps
// where it is convex and below the roller: g = (R^2 + R'^2)^1.5 - roller (R^2 + 2 R'^2 - R R'') <= 0
struct CentrePath {
  Noses lift;
  double y0, roller;
  double radius(double theta) const {
    double d[3];
    lift.eval(theta, d);
    const double r = y0 + d[0];
    return std::pow(r * r + d[1] * d[1], 1.5) / (r * r + 2 * d[1] * d[1] - r * d[2]);
  }
  double g(double theta) const {
    double d[3];
    lift.eval(theta, d);
    const double r = y0 + d[0];
    return std::pow(r * r + d[1] * d[1], 1.5) - roller * (r * r + 2 * d[1] * d[1] - r * d[2]);
  }
  // the roots of g by a 0.01 deg scan and bisection [deg, 0 .. 360)
  std::vector<double> roots() const {
    std::vector<double> out;
    for (int i = 0; i < 36000; ++i) {
      double a = i * 0.01 * deg, b = (i + 1) * 0.01 * deg;
      if ((g(a) > 0) == (g(b) > 0)) continue;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (a + b);
        ((g(mid) > 0) == (g(a) > 0) ? a : b) = mid;
      }
      out.push_back(0.5 * (a + b) / deg);
    }
    return out;
  }
};

DesignSpec translating_roller(double roller, double& y0) {
  const double R = 20, e = 1;
  DesignSpec d = design("noses", "cam", "follower");
  d.nodes = {rotational("cam", {0, 0}), translational("follower", {0, 0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", R, e)};
  y0 = std::sqrt((R + roller) * (R + roller) - e * e);
  d.nodes[1].origin_mm = {0, y0};
  d.connections = {contact("cam_follower", profile_surface("cam", "disc", {0, 0}, 0),
                           circle_surface("follower", {0, y0}, roller, true))};
  return d;
}

PeriodicSpline sampled(const std::function<double(double)>& f, double step_deg = 0.25) {
  std::vector<double> x, y;
  for (int i = 0; i * step_deg < 360.0 - 1e-9; ++i) {
    x.push_back(i * step_deg * deg);
    y.push_back(f(x.back()));
  }
  return PeriodicSpline::interpolate(x, y, 2 * pi);
}

// the windows of the message "N windows: a-b deg (...), c-d deg (...)" as (a, b) pairs
std::vector<std::pair<double, double>> windows_in(const std::string& message) {
  std::vector<std::pair<double, double>> out;
  std::size_t at = message.find(": ", message.find(" window"));
  if (at == std::string::npos) return out;
  at += 2;
  for (;;) {
    std::size_t used_a = 0, used_b = 0;
    const double a = std::stod(message.substr(at), &used_a);
    const double b = std::stod(message.substr(at + used_a + 1), &used_b);
    out.push_back({a, b});
    at = message.find("), ", at);
    if (at == std::string::npos || !std::isdigit(static_cast<unsigned char>(message[at + 3]))) break;
    at += 3;
  }
  return out;
}

// the undercut of noses centred at `centres` under a 15 mm roller, checked window by window
// against the closed form
void check_noses(const std::vector<double>& centres) {
  const double roller = 15.0;
  double y0 = 0;
  const DesignSpec d = translating_roller(roller, y0);
  CentrePath path{Noses{centres}, y0, roller};
  const PeriodicSpline target = sampled([&](double t) {
    double v[3];
    path.lift.eval(t, v);
    return v[0];
  });
  synthesis::SynthesisOptions o;
  synthesis::SynthesisResult res;
  const Status st = synthesis::synthesize(d, target, o, res);
  INFO(st.str());
  REQUIRE(st.code == StatusCode::undercut);
  CHECK_THAT(st.message, Catch::Contains("centre path curves tighter than the 15 mm roller"));
  // the closed form's roots pair up into windows (g <= 0 between a falling and a rising root)
  std::vector<double> roots = path.roots();
  REQUIRE(roots.size() == 2 * centres.size());
  if (path.g(0.0) <= 0) std::rotate(roots.begin(), roots.begin() + 1, roots.end());  // a window across 0
  const auto reported = windows_in(st.message);
  REQUIRE(reported.size() == centres.size());
  CHECK_THAT(st.message, Catch::Contains(std::to_string(centres.size()) + (centres.size() == 1 ? " window: " : " windows: ")));
  for (std::size_t k = 0; k < centres.size(); ++k) {
    INFO("window " << k << ": reported " << reported[k].first << "-" << reported[k].second << ", closed form "
                   << roots[2 * k] << "-" << roots[2 * k + 1]);
    CHECK_ABS(reported[k].first, roots[2 * k], tol::kWindowEndAbs);
    CHECK_ABS(reported[k].second, roots[2 * k + 1], tol::kWindowEndAbs);
    // the smallest centre radius over the samples inside it (0.25 deg), against the closed form
    double smallest = 1e300;
    for (int i = 0; i < 1440; ++i) {
      const double a = i * 0.25;
      const bool inside = roots[2 * k] < roots[2 * k + 1] ? a > roots[2 * k] && a < roots[2 * k + 1]
                                                          : a > roots[2 * k] || a < roots[2 * k + 1];
      if (inside) smallest = std::min(smallest, path.radius(a * deg));
    }
    const std::string text = "centre path radius of curvature down to " + format_value(smallest, 3) + " mm";
    INFO("closed form: " << smallest << " mm");
    CHECK_THAT(st.message, Catch::Contains(text));
  }
}

}  // namespace

TEST_CASE("undercut windows: two noses too sharp for the roller are both reported, against the closed-form "
          "radius of the centre path",
          "[synthesis][undercut]") {
  check_noses({100.0, 230.0});
}

TEST_CASE("undercut windows: a nose across 0 deg is one window that wraps through 0/360", "[synthesis][undercut]") {
  check_noses({0.0});
}

TEST_CASE("undercut windows: runs of a sampled margin, refined to the root of the straight line or the hermite",
          "[synthesis][undercut]") {
  // margin cos(a) on a 10 deg grid: fails on (90, 270) deg; linear ends within the chord's
  // error, hermite ends (slope -sin a per deg) within 1e-4 deg
  std::vector<double> a, m, slope, value;
  for (int i = 0; i < 36; ++i) {
    a.push_back(i * 10.0);
    m.push_back(std::cos(a.back() * deg));
    slope.push_back(-std::sin(a.back() * deg) * deg);
    value.push_back(m.back());
  }
  const auto hermite = synthesis::failing_windows(a, m, slope, value, true, true);
  REQUIRE(hermite.size() == 1);
  CHECK_ABS(hermite[0].start_deg, 90.0, tol::kHermiteRootAbs);
  CHECK_ABS(hermite[0].end_deg, 270.0, tol::kHermiteRootAbs);
  CHECK_ABS(hermite[0].worst, -1.0, tol::kUlpAbs);  // the sample at 180 deg: cos(pi) = -1 exactly
  CHECK_ABS(hermite[0].worst_at_deg, 180.0, tol::kUlpAbs);
  // on a grid offset by 3 deg the roots are not midpoints of samples symmetric about them:
  // the hermite's ends within its interpolation error of 90 and 270 deg, the chord's at the
  // chord's own roots, 4.3e-3 deg away
  std::vector<double> b, mb, sb;
  for (int i = 0; i < 36; ++i) {
    b.push_back(3.0 + i * 10.0);
    mb.push_back(std::cos(b.back() * deg));
    sb.push_back(-std::sin(b.back() * deg) * deg);
  }
  const auto offset_hermite = synthesis::failing_windows(b, mb, sb, mb, true, true);
  const auto offset_chord = synthesis::failing_windows(b, mb, {}, mb, true, true);
  REQUIRE(offset_hermite.size() == 1);
  REQUIRE(offset_chord.size() == 1);
  CHECK_ABS(offset_hermite[0].start_deg, 90.0, tol::kHermiteRootAbs);
  CHECK_ABS(offset_hermite[0].end_deg, 270.0, tol::kHermiteRootAbs);
  const auto chord_root = [](double left, double m_left, double m_right) { return left + 10.0 * m_left / (m_left - m_right); };
  CHECK_ABS(offset_chord[0].start_deg, chord_root(83.0, mb[8], mb[9]), tol::kChordRootAbs);
  CHECK_ABS(offset_chord[0].end_deg, chord_root(263.0, mb[26], mb[27]), tol::kChordRootAbs);
  const auto linear = synthesis::failing_windows(a, m, {}, value, true, true);
  REQUIRE(linear.size() == 1);
  // the chord from cos 80 to cos 100 deg crosses 0 at 90 exactly (odd symmetry)
  CHECK_ABS(linear[0].start_deg, 90.0, tol::kChordRootAbs);
  // negated, it fails on (270, 90) deg: one run through 0/360
  for (auto& v : m) v = -v;
  const auto wrapped = synthesis::failing_windows(a, m, {}, m, true, true);
  REQUIRE(wrapped.size() == 1);
  CHECK_ABS(wrapped[0].start_deg, 270.0, tol::kChordRootAbs);
  CHECK_ABS(wrapped[0].end_deg, 90.0, tol::kChordRootAbs);
  CHECK_ABS(wrapped[0].worst, -1.0, tol::kUlpAbs);
  CHECK_ABS(wrapped[0].worst_at_deg, 0.0, tol::kUlpAbs);
}

TEST_CASE("undercut windows: a polynomial-4567 lift on the CVVL swing cam names the cause, a bound and the optimiser",
          "[synthesis][undercut][swing]") {
  DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
  for (auto& c : d.connections) c.lash_mm = 0.0;
  // 9.5 mm of lift, rise and fall over 65 deg each (polynomial 4-5-6-7), peak at `peak` deg
  auto law = [](double peak) {
    return sampled([peak](double t) {
      double u = 1.0 - std::abs(std::remainder(t / deg - peak, 360.0)) / 65.0;
      if (u <= 0) return 0.0;
      return 9.5 * u * u * u * u * (35 - 84 * u + 70 * u * u - 20 * u * u * u);
    });
  };
  synthesis::SynthesisOptions o;
  o.cam = "swing";
  o.controls = {0.0};
  synthesis::SynthesisResult res;
  // the swing cam turns back at cam 179.5 deg (its input lobe's nose): a lift peaking at 180
  // still rises there, so no scale of it synthesizes; and over the swing's last 2.2 deg before
  // it turns back the lift rises 1.3 mm
  const Status st = synthesis::synthesize(d, law(180.0), o, res);
  INFO(st.str());
  REQUIRE(st.code == StatusCode::undercut);
  CHECK_THAT(st.message, Catch::Contains("centre path curves tighter than the 8 mm roller"));
  CHECK_THAT(st.message, Catch::Contains("it turns back at cam 179.5"));
  CHECK_THAT(st.message, Catch::Contains("but the target peaks at cam 180 deg"));
  CHECK_THAT(st.message, Catch::Contains("a roller of radius below"));
  CHECK_THAT(st.message, Catch::Contains("camopt optimize --cam swing"));
  // peaking where the swing turns back, the lift still bends too fast; its scale bound holds:
  // the lift scaled to it synthesizes, and the bisection's upper end does not
  const PeriodicSpline aligned = law(179.5);
  const synthesis::LiftScaleBound bound = synthesis::largest_synthesizable_scale(d, aligned, o);
  REQUIRE(bound.found);
  CHECK_REL(bound.peak_mm, 9.5, tol::kPeakAtSiteRel);
  INFO("bound " << bound.scale * bound.peak_mm << " mm .. " << bound.failing_scale * bound.peak_mm << " mm");
  CHECK(bound.failing_scale - bound.scale < 1.0 / 256);
  auto scaled = [&](double s) {
    return sampled([&](double t) { return s * aligned(t); });
  };
  o.remedies = false;
  CHECK(synthesis::synthesize(d, scaled(bound.scale), o, res).ok());
  CHECK_FALSE(synthesis::synthesize(d, scaled(bound.failing_scale), o, res).ok());
  o.remedies = true;
  const Status aligned_st = synthesis::synthesize(d, aligned, o, res);
  CHECK_THAT(aligned_st.message, Catch::Contains("lower the peak lift below " +
                                                 format_value(bound.failing_scale * bound.peak_mm, 3) + " mm"));
  CHECK(aligned_st.message.find("it turns back at cam") == std::string::npos);
}
