// the contact extremes of the summary (kin::summarize), refined between the grid points by
// solves of the mechanism, against closed forms at coarse steps where the grid values miss
// them: an eccentric disc on a translating roller follower (pressure angle, roller speed),
// a flat-faced follower on the polar-table lobe (its smallest convex radius against the
// polar radius of curvature of the same spline), and the CVVL swing cam's concave foot
// against a fine grid.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "oracles/oracles.hpp"

using namespace camopt;
using namespace camopt::kin_test;
namespace tol = camopt::test::tol;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;  // rad per deg (the oracles' own constant)

// the eccentric disc and its roller [mm]; the disc centre at e (cos phi, sin phi) with
// phi = theta + kPhase, so that no extreme falls on a 5 or 10 deg grid
constexpr double kR = 20.0, kE = 5.0, kRoller = 8.0, kL = kR + kRoller;
constexpr double kPhaseDeg = -1.2345;

// the grid values miss the closed forms by more than this (relative): the refinement matters
constexpr double kGridMissRel = 1e-5;

double rel(double value, double exact) { return std::abs(value - exact) / std::abs(exact); }

// the angle between two driver positions on a revolution [deg], 0..180
double angle_between(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

// roller centre on the y axis above the cam's axis at theta = 0
DesignSpec disc_on_roller() {
  DesignSpec d = design("extremes_disc_roller", "cam", "follower");
  const double phi0 = kPhaseDeg * kDeg;
  const double y0 = kE * std::sin(phi0) + std::sqrt(kL * kL - kE * kE * std::cos(phi0) * std::cos(phi0));
  d.nodes = {rotational("cam", {0, 0}), translational("follower", {0, y0}, {0, 1})};
  d.profiles = {eccentric_profile("disc", kR, kE)};
  d.connections = {contact("cam_roller", profile_surface("cam", "disc", {0, 0}, kPhaseDeg),
                           circle_surface("follower", {0, y0}, kRoller, true))};
  return d;
}

kin::SweepResult contact_sweep(const kin::Mechanism& m, double start, double stop, double step) {
  kin::SweepSpec spec;
  spec.start = start;
  spec.stop = stop;
  spec.step = step;
  spec.request = {3, true};
  kin::SweepResult r = kin::sweep(m, spec);
  REQUIRE(r.positions[0].status.ok());
  return r;
}

// the largest value of a contact quantity over the grid points (what the summary reported
// before the refinement)
template <class F>
double grid_max(const kin::SweepResult& r, const F& f) {
  double best = -INFINITY;
  for (std::size_t i = 0; i < r.driver.size(); ++i) best = std::max(best, f(r.positions[0].contacts[i]));
  return best;
}

}  // namespace

TEST_CASE("contact extremes: the pressure angle and roller speed of an eccentric disc on a roller follower",
          "[kinematics][summary][contact_extremes]") {
  const auto m = kin::compile(disc_on_roller());
  // pressure angle: sin(alpha) = e cos(phi) / (R + r), largest at phi = 0 and 180 deg
  const double alpha_max = std::asin(kE / kL) / kDeg;
  // roller spin per rad of cam: -(R + e L sin(phi) / sqrt(L^2 - e^2 cos^2 phi)) / r, largest
  // in magnitude at phi = 90 deg: (R + e) / r
  const double spin_max = (kR + kE) / kRoller * kDeg;  // [rad per cam deg]
  const double spin_at = 90.0 - kPhaseDeg;
  for (double step : {5.0, 10.0}) {
    INFO("step " << step << " deg");
    const kin::SweepResult r = contact_sweep(m, 0, 360, step);
    const kin::PositionSummary s = kin::summarize(m, r, 0);
    REQUIRE(s.have_contacts);
    CHECK(s.contacts_refined);
    INFO("pressure angle: refined " << s.max_pressure_angle_deg << " deg at " << s.max_pressure_angle_at
                                    << ", closed form " << alpha_max);
    CHECK_REL(s.max_pressure_angle_deg, alpha_max, tol::kRefinedContactRel);
    CHECK_ABS(std::min(angle_between(s.max_pressure_angle_at, -kPhaseDeg),
                       angle_between(s.max_pressure_angle_at, 180.0 - kPhaseDeg)),
              0.0, tol::kRefinedLocationDeg);
    CHECK(s.max_pressure_angle_contact == "cam_roller");
    const double grid_alpha = grid_max(r, [](const kin::ContactState& c) { return c.pressure_angle; }) / kDeg;
    CHECK(rel(grid_alpha, alpha_max) >= kGridMissRel);
    INFO("roller speed: refined " << s.max_roller_speed << " rad/deg at " << s.max_roller_speed_at
                                  << ", closed form " << spin_max << " at " << spin_at);
    CHECK_REL(s.max_roller_speed, spin_max, tol::kRefinedContactRel);
    CHECK_ABS(angle_between(s.max_roller_speed_at, spin_at), 0.0, tol::kRefinedLocationDeg);
    const double grid_spin = grid_max(r, [](const kin::ContactState& c) { return std::abs(c.roller_speed); }) * kDeg;
    CHECK(rel(grid_spin, spin_max) >= kGridMissRel);
    // the disc's curvature is 1 / R everywhere
    REQUIRE(s.cam_surfaces.size() == 1);
    CHECK_REL(s.cam_surfaces[0].min_convex.value, kR, tol::kCircleRadiusRel);
  }
}

namespace {

// the lobe's radius of curvature is smallest at its base (phi = 0), on top at theta = 0; the
// sweep starts off that grid
constexpr double kLobeStartDeg = 2.345;

// the lobe's base circle on top at theta = 0, a flat face resting on it
DesignSpec lobe_on_flat() {
  DesignSpec d = design("extremes_lobe_flat", "cam", "tappet");
  const double y0 = lobe_radius(0.0);
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, y0}, {0, 1})};
  d.profiles = {lobe_table("lobe")};
  d.connections = {contact("cam_tappet", profile_surface("cam", "lobe", {0, 0}, 90.0),
                           line_surface("tappet", {0, y0}, {0, -1}))};
  return d;
}

// the smallest polar radius of curvature of the lobe's spline over a revolution: sampled
// every 0.01 deg, then golden section on the best sample's neighbourhood
double lobe_min_radius() {
  const PeriodicSpline spline = lobe_spline();
  auto rho = [&](double phi) {
    double d[PeriodicSpline::degree + 1];
    spline.evaluate(phi, PeriodicSpline::degree, d);
    return oracles::polar_radius_of_curvature(d[0], d[1], d[2]);
  };
  constexpr int kSamples = 36000;
  int best = 0;
  for (int i = 1; i < kSamples; ++i)
    if (rho(2 * kPi * i / kSamples) < rho(2 * kPi * best / kSamples)) best = i;
  double a = 2 * kPi * (best - 1) / kSamples, b = 2 * kPi * (best + 1) / kSamples;
  const double g = (std::sqrt(5.0) - 1) / 2;
  while (b - a > 1e-12) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (rho(c) < rho(d)) b = d;
    else a = c;
  }
  return rho(0.5 * (a + b));
}

}  // namespace

TEST_CASE("contact extremes: the smallest convex radius under a flat-faced follower is the lobe spline's",
          "[kinematics][summary][contact_extremes]") {
  const auto m = kin::compile(lobe_on_flat());
  // the kernel's geometry is the periodic quintic spline of the table (lobe_spline builds
  // the same one): its radius of curvature is smooth, and the summary meets the spline's
  // smallest radius to round-off, while the analytic r(phi) the table samples differs from
  // the spline by the interpolation error (not what the summary is checked against)
  const double exact = lobe_min_radius();
  for (double step : {5.0, 10.0}) {
    INFO("step " << step << " deg");
    // the smallest radius, on the base circle's top (theta = 0 and 360 deg), between grid points
    const kin::SweepResult r = contact_sweep(m, kLobeStartDeg, kLobeStartDeg + 360, step);
    const kin::PositionSummary s = kin::summarize(m, r, 0);
    CHECK(s.contacts_refined);
    REQUIRE(s.cam_surfaces.size() == 1);
    const kin::SurfaceRadii& lobe = s.cam_surfaces[0];
    REQUIRE(lobe.convex);
    INFO("refined " << lobe.min_convex.value << " mm at " << lobe.min_convex.at << " deg, spline " << exact);
    CHECK_REL(lobe.min_convex.value, exact, tol::kRefinedContactRel);
    CHECK(s.min_convex_cam_radius_mm == lobe.min_convex.value);
    const double grid_k = grid_max(r, [](const kin::ContactState& c) { return c.curvature_a; });
    CHECK(rel(1.0 / grid_k, exact) >= kGridMissRel);
  }
}

TEST_CASE("contact extremes: the CVVL swing cam's concave foot at a 1 deg step agrees with a 0.01 deg grid",
          "[kinematics][summary][contact_extremes]") {
  const auto m = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml"));
  std::size_t c = 0;
  while (m.connections[c].name != "swing_roller") ++c;
  auto concave = [&](const kin::ContactState& cs) { return cs.open || cs.curvature_a >= 0 ? -INFINITY : -cs.curvature_a; };
  // refined at 1 deg
  const kin::SweepResult coarse = contact_sweep(m, 0, 360, 1.0);
  const kin::PositionSummary s = kin::summarize(m, coarse, 0);
  CHECK(s.contacts_refined);
  const kin::SurfaceRadii* swing = nullptr;
  for (const auto& sf : s.cam_surfaces)
    if (sf.contact == "swing_roller" && sf.surface == "swing_cam") swing = &sf;
  REQUIRE(swing != nullptr);
  REQUIRE(swing->concave);
  const double refined = swing->sharpest_concave.value, at = swing->sharpest_concave.at;
  // a 0.01 deg grid around it, and that grid's own error: on a parabola the extreme within a
  // step of a grid-local extreme is beyond it by at most a quarter of its larger difference
  // to a neighbour (the whole difference taken here)
  const kin::SweepResult fine = contact_sweep(m, at - 1.0, at + 1.0, 0.01);
  const std::size_t nc = m.connections.size();
  std::size_t best = 0;
  std::vector<double> k(fine.driver.size());
  for (std::size_t i = 0; i < k.size(); ++i) {
    k[i] = concave(fine.positions[0].contacts[i * nc + c]);
    if (k[i] > k[best]) best = i;
  }
  REQUIRE(best > 0);
  REQUIRE(best + 1 < k.size());
  const double fine_radius = -1.0 / k[best];
  const double fine_error = std::abs(-1.0 / std::min(k[best - 1], k[best + 1]) - fine_radius);
  double coarse_k = -INFINITY;
  for (std::size_t i = 0; i < coarse.driver.size(); ++i)
    coarse_k = std::max(coarse_k, concave(coarse.positions[0].contacts[i * nc + c]));
  const double coarse_radius = -1.0 / coarse_k;
  INFO("refined " << refined << " mm at " << at << " deg; 0.01 deg grid " << fine_radius << " mm at "
                  << fine.driver[best] << " (its error <= " << fine_error << "); 1 deg grid " << coarse_radius);
  // never short of a grid value, within the fine grid's error of it, far from the coarse grid
  CHECK(refined >= fine_radius);
  CHECK(refined - fine_radius <= fine_error);
  CHECK_ABS(fine.driver[best], at, tol::kFineGridStepDeg);
  CHECK(refined - coarse_radius >= 100 * fine_error);
  CHECK_ABS(refined, -14.7, tol::kPrintedFootRadiusAbs);
}
