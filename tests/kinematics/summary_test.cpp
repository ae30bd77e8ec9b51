// the per-position summary (kin::summarize) against closed forms: an eccentric disc on a
// flat-faced follower, lift s = e (cos d - cos(theta - d)) with its peak off the grid, swept
// at coarse steps; the refined extremes, durations and area match the closed forms where the
// grid values do not. The lash open span of a flat tappet on an eccentric disc. The radii of
// curvature named per contact surface on the bundled RFF and CVVL designs, against the polar
// radius of curvature of their profiles.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/grid_refine.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::kin_test;
namespace tol = camopt::test::tol;

namespace {

constexpr double kR = 20.0, kE = 5.0;  // disc radius, eccentricity [mm]
constexpr double kDelta = 1.2345 * deg;  // the lift's phase: its peak at 180 deg + kDelta, off every grid
constexpr double kPerDeg = deg;          // d theta [rad] per cam deg
// the refined summary against the closed forms: tol::kRefinedSummaryRel of each quantity's scale;
// the grid values miss the closed forms by more than this (relative): the refinement matters
constexpr double kGridMissRel = 1e-6;

// disc centre at e (cos phi, sin phi), phi = theta - 90 deg - kDelta; the face on top
DesignSpec disc_on_flat() {
  DesignSpec d = design("summary_disc_flat", "cam", "tappet");
  const double phase = -90 * deg - kDelta;
  const double y0 = kE * std::sin(phase) + kR;  // face height at theta = 0
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, y0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", kR, kE)};
  d.connections = {contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, phase / deg),
                           line_surface("tappet", {0, y0}, {0, -1}))};
  return d;
}

kin::SweepResult sweep(const kin::Mechanism& m, double step, int order) {
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = step;
  spec.request = {order, false};
  kin::SweepResult r = kin::sweep(m, spec);
  REQUIRE(r.positions[0].status.ok());
  return r;
}

// closed-form duration above h of e (cos d - cos(theta - d)) over 0..360 [deg]
double duration_closed_form(double h) { return 360.0 - 2.0 * std::acos(std::cos(kDelta) - h / kE) / deg; }

double rel(double value, double exact, double scale) { return std::abs(value - exact) / scale; }

}  // namespace

TEST_CASE("summary: refined lift extremes, durations and area of a disc on a flat follower match the closed forms",
          "[kinematics][summary]") {
  const auto m = kin::compile(disc_on_flat());
  const double lift_peak = kE * (1.0 + std::cos(kDelta));
  const double v = kE * kPerDeg, a = kE * kPerDeg * kPerDeg, j = a * kPerDeg;  // peaks per cam deg^k
  kin::SummaryOptions options;
  options.duration_heights = {1.0, 0.1, 9.0};
  for (double step : {2.5, 5.0}) {
    INFO("step " << step << " deg");
    const kin::PositionSummary s = kin::summarize(m, sweep(m, step, 3), 0, options);
    const kin::PositionSummary grid = kin::summarize(m, sweep(m, step, 0), 0, options);
    CHECK(s.refined);
    CHECK_FALSE(grid.refined);
    // the peak lift and where it is
    CHECK_REL(s.max_lift, lift_peak, tol::kRefinedSummaryRel);
    CHECK_ABS(s.max_lift_at, 180.0 + kDelta / deg, tol::kPeakAngleAbs);
    CHECK(rel(grid.max_lift, lift_peak, lift_peak) >= kGridMissRel);
    // durations above each height
    for (std::size_t k = 0; k < options.duration_heights.size(); ++k) {
      const double h = options.duration_heights[k], exact = duration_closed_form(h);
      INFO("height " << h << " mm: closed form " << exact << " deg, refined " << s.durations[k].span << ", grid "
                     << grid.durations[k].span);
      CHECK(s.durations[k].height == h);
      CHECK_REL(s.durations[k].span, exact, tol::kRefinedSummaryRel);
      CHECK(rel(grid.durations[k].span, exact, exact) >= kGridMissRel);
    }
    CHECK(s.duration_at(1.0) == s.durations[0].span);
    // the lift area over a whole revolution: 360 e cos d [mm deg]
    CHECK_ABS(s.lift_area, 360.0 * kE * std::cos(kDelta), tol::kRefinedSummaryRel * 360.0 * kE);
    // velocity e sin(theta - d), acceleration e cos(theta - d), jerk -e sin(theta - d) (per cam deg^k)
    CHECK_REL(s.max_velocity, v, tol::kRefinedSummaryRel);
    CHECK_REL(s.min_velocity, -v, tol::kRefinedSummaryRel);
    CHECK_ABS(s.max_velocity_at, 90.0 + kDelta / deg, tol::kRefinedExtremeAngleAbs);
    CHECK_ABS(s.min_velocity_at, 270.0 + kDelta / deg, tol::kRefinedExtremeAngleAbs);
    CHECK_REL(s.max_acceleration, a, tol::kRefinedSummaryRel);
    CHECK_REL(s.min_acceleration, -a, tol::kRefinedSummaryRel);
    CHECK_ABS(s.min_acceleration_at, 180.0 + kDelta / deg, tol::kRefinedExtremeAngleAbs);
    CHECK_REL(s.max_jerk_abs, j, tol::kRefinedSummaryRel);
  }
}

TEST_CASE("summary: the hermite interpolant reproduces a polynomial of its degree and places a stationary point",
          "[kinematics][summary]") {
  // p(x) = sum c_j x^j of degree 7 is reproduced exactly by the order-3 interpolant
  const double c[8] = {0.3, -1.1, 0.7, 2.0, -0.4, 0.25, -0.6, 0.15};
  auto jet = [&](double x) {
    kin::GridJet f{};
    for (int k = 0; k <= 3; ++k)
      for (int j = k; j < 8; ++j) {
        double fall = 1.0;
        for (int i = 0; i < k; ++i) fall *= j - i;
        f[k] += fall * c[j] * std::pow(x, j - k);
      }
    return f;
  };
  const double x0 = 0.4, x1 = 1.3;
  const auto p = kin::HermiteInterval::fit(x0, x1, jet(x0), jet(x1), 3);
  for (double x : {0.4, 0.55, 0.8, 1.1, 1.3, 1.6})
    for (int k = 0; k <= 3; ++k) CHECK_NEAR(p.derivative(k, x), jet(x)[k], tol::kHermitePolyRel, tol::kHermitePolyRel);
  // its integral: the antiderivative's difference
  double exact = 0.0;
  for (int j = 0; j < 8; ++j) exact += c[j] * (std::pow(x1, j + 1) - std::pow(x0, j + 1)) / (j + 1);
  CHECK_ABS(p.integral(), exact, tol::kHermiteIntegralAbs);
  // the stationary point of cos at pi on [3.05, 3.2] (an 8.6 deg step): each order more accurate,
  // order 3 to 1e-12 (measured: 1.5e-5, 4.0e-9 and 5.0e-13 for orders 1, 2, 3)
  auto cosine = [](double x) { return kin::GridJet{std::cos(x), -std::sin(x), -std::cos(x), std::sin(x)}; };
  double last = INFINITY;
  for (int order = 1; order <= 3; ++order) {
    const auto q = kin::HermiteInterval::fit(3.05, 3.2, cosine(3.05), cosine(3.2), order);
    std::vector<double> at;
    q.stationary(0, at);
    REQUIRE(at.size() == 1);
    const camopt::test::Comparison point = camopt::test::compare_abs(
        "stationary point of order " + std::to_string(order), at[0], std::numbers::pi, tol::kHermiteStationaryAbs);
    INFO("order " << order << ": stationary point off by " << point.error);
    CHECK(point.error < last);
    last = point.error;
    if (order == 3) CHECK_COMPARISON(point);
  }
}

TEST_CASE("summary: the lash open span of a flat tappet on an eccentric disc is refined to its closed form",
          "[kinematics][summary][lash]") {
  // disc 0 axis at -90 deg: closed lift e (1 - cos theta) - L, open while cos theta > 1 - L/e
  constexpr double kLash = 0.2;
  DesignSpec d = design("summary_lash", "cam", "tappet");
  const double y0 = kR - kE;
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, y0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", kR, kE)};
  ConnectionSpec c = contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, -90),
                             line_surface("tappet", {0, y0}, {0, -1}));
  c.lash_mm = kLash;
  d.connections = {c};
  const auto m = kin::compile(d);
  const double half = std::acos(1.0 - kLash / kE) / deg;  // open over [0, half] and [360 - half, 360]
  for (double step : {2.5, 5.0}) {
    INFO("step " << step << " deg");
    const kin::PositionSummary s = kin::summarize(m, sweep(m, step, 3), 0);
    const kin::PositionSummary grid = kin::summarize(m, sweep(m, step, 0), 0);
    REQUIRE(s.separations.size() == 1);
    CHECK(s.separations[0].contact == "cam_tappet");
    CHECK_REL(s.separations[0].open_span, 2 * half, tol::kRefinedSummaryRel);
    REQUIRE(s.separations[0].intervals.size() == 2);
    CHECK(s.separations[0].intervals[0].first == 0.0);
    CHECK_REL(s.separations[0].intervals[0].second, half, tol::kRefinedSummaryRel);
    CHECK_ABS(s.separations[0].intervals[1].first, 360.0 - half, tol::kRefinedSummaryRel * half);
    CHECK(s.separations[0].intervals[1].second == 360.0);
    REQUIRE(grid.separations.size() == 1);
    CHECK(rel(grid.separations[0].open_span, 2 * half, 2 * half) >= kGridMissRel);
    // the peak 2e - L, and the duration at 1 mm: e (1 - cos theta) - L > 1
    CHECK_ABS(s.max_lift, 2 * kE - kLash, tol::kRefinedSummaryRel * kE);
    const double exact = 360.0 - 2.0 * std::acos(1.0 - (1.0 + kLash) / kE) / deg;
    CHECK_REL(s.duration_at(1.0), exact, tol::kRefinedSummaryRel);
  }
}

namespace {

// the polar radius of curvature of a bundled design's profile over the parameters its contact
// touches in a sweep, sampled finely: the smallest convex and the sharpest concave radius
struct ProfileRadii {
  double min_convex = INFINITY, sharpest_concave = -INFINITY;
};
ProfileRadii profile_radii(const DesignSpec& design, const kin::Mechanism& m, const kin::SweepResult& r,
                          const std::string& contact) {
  std::size_t c = 0;
  while (m.connections[c].name != contact) ++c;
  const kin::Surface& sf = m.connections[c].surface_a;
  REQUIRE(sf.kind == kin::SurfaceKind::curve);
  const auto& p = r.positions[0];
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    const double u = p.contacts[i * m.connections.size() + c].polar_angle_a;
    lo = std::min(lo, u), hi = std::max(hi, u);
  }
  ProfileRadii out;
  // the profile's polar table as the design gives it, interpolated as the kernel does
  const ProfileSpec& table = design.profiles[static_cast<std::size_t>(sf.profile)];
  REQUIRE(table.form == ProfileForm::polar);
  std::vector<double> angle;
  for (double a : table.angle_deg) angle.push_back(a * deg);
  const PeriodicSpline spline = PeriodicSpline::interpolate(angle, table.radius_mm, 2.0 * pi);
  constexpr int kSamples = 200000;
  for (int i = 0; i <= kSamples; ++i) {
    double d[PeriodicSpline::degree + 1];
    spline.evaluate(lo + (hi - lo) * i / kSamples, PeriodicSpline::degree, d);
    const double rho = oracles::polar_radius_of_curvature(d[0], d[1], d[2]);
    if (rho > 0) out.min_convex = std::min(out.min_convex, rho);
    if (rho < 0) out.sharpest_concave = std::max(out.sharpest_concave, rho);
  }
  return out;
}

const kin::SurfaceRadii& find_surface(const std::vector<kin::SurfaceRadii>& list, const std::string& contact,
                                      const std::string& surface) {
  for (const auto& s : list)
    if (s.contact == contact && s.surface == surface) return s;
  FAIL("no surface " << surface << " at contact " << contact);
  return list.front();
}

kin::SweepResult contact_sweep(const kin::Mechanism& m) {
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = 0.5;
  spec.request = {3, true};
  kin::SweepResult r = kin::sweep(m, spec);
  REQUIRE(r.positions[0].status.ok());
  return r;
}

// the summary's refined radius against the profile's sampled one (tol::kRadiusSampledRel):
// 200000 samples over the touched arc (spacing below 3e-5 rad) miss the smooth extreme by about
// rho'' (spacing / 2)^2 / 2, below 1e-9 rho here; the refined one is the true extreme
// itself, so it is at or beyond the sampled one

}  // namespace

TEST_CASE("summary: the RFF's smallest cam radius is the lobe's, not the finger pad's", "[kinematics][summary]") {
  const DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/roller_finger_follower.toml");
  const auto m = kin::compile(d);
  const auto r = contact_sweep(m);
  const kin::PositionSummary s = kin::summarize(m, r, 0);
  REQUIRE(s.cam_surfaces.size() == 1);
  const auto& lobe = s.cam_surfaces[0];
  CHECK(lobe.contact == "cam_roller");
  CHECK(lobe.body == "cam");
  CHECK(lobe.surface == "lobe");
  REQUIRE(lobe.convex);
  const ProfileRadii exact = profile_radii(d, m, r, "cam_roller");
  INFO("lobe: summary " << lobe.min_convex.value << " mm, profile " << exact.min_convex << " mm");
  CHECK_REL(lobe.min_convex.value, exact.min_convex, tol::kRadiusSampledRel);
  CHECK(lobe.min_convex.value <= exact.min_convex);
  CHECK(lobe.concave == (exact.sharpest_concave > -INFINITY));
  // the old key's value, over cam surfaces only
  REQUIRE(s.have_convex_cam);
  CHECK(s.min_convex_cam_radius_mm == lobe.min_convex.value);
  CHECK(s.min_convex_cam_radius_contact == "cam_roller");
  // the follower surfaces: the pad (12 mm) and the roller (8.5 mm), never a cam
  const auto& pad = find_surface(s.follower_surfaces, "pad_valve", "circle");
  CHECK(pad.body == "finger");
  CHECK_REL(pad.min_convex.value, 12.0, tol::kUlpRel);
  CHECK_REL(find_surface(s.follower_surfaces, "cam_roller", "roller").min_convex.value, 8.5, tol::kUlpRel);
}

TEST_CASE("summary: the CVVL swing cam's concave foot is reported with its surface", "[kinematics][summary]") {
  const DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
  const auto m = kin::compile(d);
  const auto r = contact_sweep(m);
  const kin::PositionSummary s = kin::summarize(m, r, 0);
  CHECK(s.cam_surfaces.size() == 2);
  const auto& swing = find_surface(s.cam_surfaces, "swing_roller", "swing_cam");
  CHECK(swing.body == "swing");
  REQUIRE(swing.concave);
  const ProfileRadii exact = profile_radii(d, m, r, "swing_roller");
  INFO("swing cam: summary concave " << swing.sharpest_concave.value << " mm, profile " << exact.sharpest_concave
                                     << " mm; convex " << swing.min_convex.value << " / " << exact.min_convex);
  CHECK_REL(swing.sharpest_concave.value, exact.sharpest_concave, tol::kRadiusSampledRel);
  CHECK(swing.sharpest_concave.value >= exact.sharpest_concave);
  // the design's own figure: the foot keeps a concave radius >= 14.7 mm
  CHECK_ABS(swing.sharpest_concave.value, -14.7, tol::kDocumentedRadiusAbs);
  const auto& input = find_surface(s.cam_surfaces, "cam_roller", "input_lobe");
  CHECK(input.body == "cam");
  CHECK(input.convex);
}
