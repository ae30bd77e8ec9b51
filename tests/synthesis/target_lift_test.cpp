// target lift input: exact interpolation of clean tables, closure on the base circle, the
// bundled real tables (a partial tappet table, a full-cycle crank-angle valve table),
// input validation, and least-squares smoothing of a noisy cycloidal rise-fall.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/synthesis/target_lift.hpp"
#include "support/compare.hpp"

namespace {

using namespace camopt::synthesis;
using camopt::InputError;
using Catch::Matchers::Contains;

using camopt::pi;
using camopt::rad_per_deg;
namespace test = camopt::test;
namespace tol = camopt::test::tol;

constexpr double kJoinEps = 1e-9;         // [rad] one-sided offset at a knot
constexpr double kNoiseSigma = 0.01;      // [mm]
constexpr std::uint32_t kSeed = 20240611;

const std::string kTappet = std::string(CAMOPT_SHARED_DATA_DIR) + "/ehl_cam_tappet_asfand/CamAngle_vs_Lift_smooth.csv";
const std::string kIcesym = std::string(CAMOPT_SHARED_DATA_DIR) + "/icesym_boscarol/Lv_I-mb.csv";

// 9 mm cycloidal rise over 120 deg, cycloidal fall over 120 deg, dwell 120 deg [mm]
double cycloidal_rise_fall(double deg) {
  const double t = deg - 360.0 * std::floor(deg / 360.0);
  const auto unit = [](double x) { return x - std::sin(2 * pi * x) / (2 * pi); };
  if (t < 120.0) return 9.0 * unit(t / 120.0);
  if (t < 240.0) return 9.0 * (1.0 - unit((t - 120.0) / 120.0));
  return 0.0;
}

// standard normal by box-muller from mt19937 words (portable, unlike std::normal_distribution)
double normal(std::mt19937& gen) {
  const double u1 = (static_cast<double>(gen()) + 0.5) / 4294967296.0;
  const double u2 = (static_cast<double>(gen()) + 0.5) / 4294967296.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * pi * u2);
}

// f^(k) for k = 0..4 continuous at every breakpoint (left limit at x - eps vs the right piece)
void require_c4(const camopt::PeriodicSpline& s) {
  const auto knots = s.knots();
  double scale[6] = {};
  for (double x : knots) {
    double d[6];
    s.evaluate(x, 5, d);
    for (int k = 0; k <= 5; ++k) scale[k] = std::max(scale[k], std::abs(d[k]));
  }
  for (double x : knots) {
    double right[6], left[6];
    s.evaluate(x, 5, right);
    s.evaluate(x - kJoinEps, 5, left);
    for (int k = 0; k <= 4; ++k) {
      INFO("knot " << x / rad_per_deg << " deg, derivative " << k);
      REQUIRE_ABS(left[k], right[k], tol::kTargetContinuityRel * scale[k] + 2 * kJoinEps * scale[k + 1]);
    }
  }
}

// the target at the table's first `rows` sites against the table [mm]
test::Comparison at_sites(const TargetLift& t, const std::vector<double>& deg, const std::vector<double>& lift,
                          std::size_t rows) {
  test::Series s("target lift at the table's sites [mm]", "cam [deg]");
  for (std::size_t i = 0; i < rows; ++i) s.add(deg[i], t.lift_at(deg[i]), lift[i]);
  return s.compare({.abs = tol::kSplineNodeAbs});
}

std::string error_of(const std::vector<double>& deg, const std::vector<double>& lift, const std::vector<int>& lines,
                     const TargetLiftOptions& opt) {
  try {
    (void)fit_target_lift(deg, lift, lines, opt);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("target lift: clean full-cycle table is interpolated exactly", "[synthesis][target_lift]") {
  std::vector<double> deg, lift;
  for (int i = 0; i < 180; ++i) {
    deg.push_back(2.0 * i);
    lift.push_back(cycloidal_rise_fall(2.0 * i));
  }
  TargetLiftOptions opt;
  opt.source = "clean.csv";
  const TargetLift t = fit_target_lift(deg, lift, {}, opt);
  CHECK_FALSE(t.closed_on_base_circle);
  CHECK_THAT(t.closure_message, Contains("covers the full cycle"));
  REQUIRE_SERIES(at_sites(t, deg, lift, deg.size()));
  CHECK(t.residual_rms_mm == 0.0);
  CHECK(t.residual_max_mm == 0.0);
  // peak of the cycloidal rise-fall: 9 mm at 120 deg
  CHECK_ABS(t.max_lift_mm, 9.0, tol::kInterpolatedPeakLiftAbs);
  CHECK_ABS(t.max_lift_at_deg, 120.0, tol::kInterpolatedPeakAngleAbs);
  // between the sites the interpolant follows the law (2-deg sites, c2 law with jerk steps)
  test::Series law("target lift against the law [mm]", "cam [deg]");
  for (double d = 0.0; d < 360.0; d += 0.1) law.add(d, t.lift_at(d), cycloidal_rise_fall(d));
  CHECK_SERIES(law.compare({.abs = tol::kBetweenSitesAbs}));
  require_c4(t.lift);

  SECTION("a 0 .. 360 table drops its repeated last row") {
    deg.push_back(360.0);
    lift.push_back(lift.front());
    const TargetLift t2 = fit_target_lift(deg, lift, {}, opt);
    CHECK_THAT(t2.closure_message, Contains("was dropped"));
    CHECK(t2.lift.knots().size() == 180);
    CHECK_ABS(t2.lift_at(100.0), t.lift_at(100.0), tol::kSplineNodeAbs);
  }
}

TEST_CASE("target lift: the largest slope step of a table is its lash take-up", "[synthesis][target_lift]") {
  // the cycloidal rise-fall (9 mm, 120 + 120 deg) at 0.25 deg is smooth; less 0.3 mm of
  // lash, max(0, L - 0.3), the valve starts and seats with the law's slope where L = 0.3:
  // 9/120 (1 - cos 2 pi u), u - sin(2 pi u) / (2 pi) = 0.3 / 9
  std::vector<double> deg, smooth, lashed;
  for (int i = 0; i < 1440; ++i) {
    deg.push_back(0.25 * i);
    smooth.push_back(cycloidal_rise_fall(0.25 * i));
    lashed.push_back(std::max(0.0, smooth.back() - 0.3));
  }
  double u = 0.3;  // newton on the unit cycloid
  for (int it = 0; it < 50; ++it) u -= (u - std::sin(2 * pi * u) / (2 * pi) - 0.3 / 9) / (1 - std::cos(2 * pi * u));
  const double take_up_deg = 120 * u, take_up_slope = 9.0 / 120 * (1 - std::cos(2 * pi * u));  // [mm/deg]
  TargetLiftOptions opt;
  const TargetLift clean = fit_target_lift(deg, smooth, {}, opt);
  INFO("smooth: " << clean.slope_step_ratio << " at " << clean.slope_step_at_deg << " deg");
  CHECK_ABS(clean.slope_step_ratio, 0.0, tol::kSmoothSlopeStepRatioAbs);
  const TargetLift step = fit_target_lift(deg, lashed, {}, opt);
  INFO("lashed: " << step.slope_step_mm_per_deg << " mm/deg (" << step.slope_step_ratio << ") at "
                  << step.slope_step_at_deg << " deg; take-up " << take_up_slope << " mm/deg at " << take_up_deg
                  << " deg");
  CHECK_REL(std::abs(step.slope_step_mm_per_deg), take_up_slope, tol::kTakeUpSlopeRel);
  // at the opening or the closing take-up
  const double nearer_take_up_deg = std::abs(step.slope_step_at_deg - take_up_deg) <
                                            std::abs(step.slope_step_at_deg - (240 - take_up_deg))
                                        ? take_up_deg
                                        : 240 - take_up_deg;
  CHECK_ABS(step.slope_step_at_deg, nearer_take_up_deg, tol::kTakeUpAngleAbs);
  CHECK_REL(step.slope_step_ratio, std::abs(step.slope_step_mm_per_deg) / (2 * 9.0 / 120), tol::kSlopeStepRatioRel);
}

TEST_CASE("target lift: real tappet table (-84 .. 80 cam deg) is closed on the base circle",
          "[synthesis][target_lift][real]") {
  const camopt::io::CsvTable csv = camopt::io::read_csv(kTappet);
  const std::vector<double>& deg = csv.column("cam_angle_deg");
  const std::vector<double>& lift = csv.column("tappet_lift_mm");
  REQUIRE(deg.front() == -84.0);
  REQUIRE(deg.back() == 80.0);
  REQUIRE(lift.front() == 0.00035);
  REQUIRE(lift.back() == 0.09362);  // the closing flank stops above the default tolerance

  TargetLiftOptions opt;
  opt.source = "CamAngle_vs_Lift_smooth.csv";
  SECTION("with the default tolerance (0.05 mm) the 0.094 mm end is a step and is rejected") {
    const std::string e = error_of(deg, lift, csv.lines, opt);
    CHECK_THAT(e, Contains("CamAngle_vs_Lift_smooth.csv:" + std::to_string(csv.lines.back())));
    CHECK_THAT(e, Contains("ends at 80 cam deg with lift 0.09362 mm"));
    CHECK_THAT(e, Contains("a table that does not cover the cycle must end on the base circle (lift <= 0.05 mm); "
                           "give the full cycle or a table that returns to zero lift"));
  }
  SECTION("with a 0.1 mm tolerance it is closed with zero lift over the remaining 196 deg") {
    opt.closure_tolerance_mm = 0.1;
    const TargetLift t = fit_target_lift(deg, lift, csv.lines, opt);
    CHECK(t.closed_on_base_circle);
    CHECK_THAT(t.closure_message, Contains("table covers 164 deg (-84 .. 80 cam deg); closed on the base circle "
                                           "(zero lift) over the remaining 196 deg"));
    REQUIRE_SERIES(at_sites(t, deg, lift, deg.size()));
    // the fill points (0.5 deg spacing) are on the base circle
    test::Series fill("target lift at the fill points [mm]", "cam [deg]");
    for (double d = 80.5; d < 276.0; d += 0.5) fill.add(d, t.lift_at(d), 0.0);
    REQUIRE_SERIES(fill.compare({.abs = tol::kSplineNodeAbs}));
    const auto peak = std::max_element(lift.begin(), lift.end());
    CHECK(t.max_lift_mm >= *peak);
    CHECK_ABS(t.max_lift_mm, *peak, tol::kTablePeakLiftAbs);
    CHECK_ABS(t.max_lift_at_deg, deg[static_cast<std::size_t>(peak - lift.begin())], tol::kTablePeakAngleAbs);
    require_c4(t.lift);
  }
}

TEST_CASE("target lift: real icesym valve table (0 .. 720 crank deg) covers the cycle",
          "[synthesis][target_lift][real]") {
  const camopt::io::CsvTable csv = camopt::io::read_csv(kIcesym);
  std::vector<double> deg = csv.column("crank_angle_deg");
  const std::vector<double>& lift = csv.column("valve_lift_mm");
  for (double& d : deg) d /= 2.0;  // crank -> cam
  REQUIRE(deg.front() == 0.0);
  REQUIRE(deg.back() == 360.0);
  // the 720 crank deg row does not repeat the 0 row: 5.44694 vs 5.50348 mm
  REQUIRE(lift.front() == 5.50348);
  REQUIRE(lift.back() == 5.44694);

  TargetLiftOptions opt;
  opt.source = "Lv_I-mb.csv";
  SECTION("the 0.057 mm step at the seam exceeds the default tolerance") {
    const std::string e = error_of(deg, lift, csv.lines, opt);
    CHECK_THAT(e, Contains("Lv_I-mb.csv:" + std::to_string(csv.lines.back())));
    CHECK_THAT(e, Contains("does not repeat its first"));
    CHECK_THAT(e, Contains("a step of 0.0565 mm at the seam"));
  }
  SECTION("interpolated with a 0.1 mm tolerance: duplicate dropped, base-circle gap filled") {
    opt.closure_tolerance_mm = 0.1;
    const TargetLift t = fit_target_lift(deg, lift, csv.lines, opt);
    CHECK_FALSE(t.closed_on_base_circle);
    CHECK_THAT(t.closure_message, Contains("table covers the full cycle (0 .. 360 cam deg)"));
    CHECK_THAT(t.closure_message, Contains("was dropped"));
    CHECK_THAT(t.closure_message, Contains("gaps on the base circle filled with zero lift: 127.5 .. 337.5 cam deg"));
    REQUIRE_SERIES(at_sites(t, deg, lift, deg.size() - 1));
    CHECK_ABS(t.max_lift_mm, 14.195, tol::kSeamTablePeakLiftAbs);
    CHECK_ABS(t.max_lift_at_deg, 52.5, tol::kSeamTablePeakAngleAbs);
    CHECK_ABS(t.lift_at(230.0), 0.0, tol::kSplineNodeAbs);  // a fill point in the dwell
    require_c4(t.lift);
  }
  SECTION("smoothed: both seam rows enter the fit, the residual is reported") {
    opt.smooth = true;
    const TargetLift t = fit_target_lift(deg, lift, csv.lines, opt);
    CHECK_FALSE(t.closed_on_base_circle);
    CHECK(t.residual_rms_mm > 0.0);
    CHECK(t.residual_max_mm >= t.residual_rms_mm);
    require_c4(t.lift);
  }
}

TEST_CASE("target lift: input errors name the file, the row and the rule", "[synthesis][target_lift][errors]") {
  std::vector<double> deg, lift;
  std::vector<int> lines;
  for (int i = 0; i <= 100; ++i) {  // a rise to 2 mm over 0 .. 100 deg that never returns
    deg.push_back(i);
    lift.push_back(2.0 * cycloidal_rise_fall(1.2 * i) / 9.0);
    lines.push_back(i + 2);
  }
  TargetLiftOptions opt;
  opt.source = "open.csv";

  SECTION("a table ending at 2 mm lift") {
    const std::string e = error_of(deg, lift, lines, opt);
    CHECK_THAT(e, Contains("open.csv:102"));
    CHECK_THAT(e, Contains("ends at 100 cam deg with lift 2 mm"));
    CHECK_THAT(e, Contains("must end on the base circle (lift <= 0.05 mm)"));
  }
  SECTION("a table spanning more than one cycle") {
    deg.back() = 400.0;
    const std::string e = error_of(deg, lift, lines, opt);
    CHECK_THAT(e, Contains("open.csv"));
    CHECK_THAT(e, Contains("spans 400 cam deg (0 .. 400), more than one cycle"));
  }
  SECTION("negative lift names the line and the value; rounding negatives are clamped") {
    lift[40] = -0.2;
    const std::string e = error_of(deg, lift, lines, opt);
    CHECK_THAT(e, Contains("open.csv:42: lift -0.2 mm at 40 cam deg: lift must be >= 0 (base circle)"));
    lift[40] = 0.5;
    lift[0] = -5e-4;  // 0.5 um below zero: exported rounding, clamped
    for (int i = 51; i <= 100; ++i) lift[static_cast<std::size_t>(i)] = lift[static_cast<std::size_t>(100 - i)];
    const TargetLift t = fit_target_lift(deg, lift, lines, opt);
    CHECK_ABS(t.lift_at(0.0), 0.0, tol::kSplineNodeAbs);
  }
  SECTION("a full cycle that never comes down to the base circle names its lowest row") {
    std::vector<double> d2, l2;
    std::vector<int> n2;
    for (int i = 0; i < 360; i += 2) {  // a 0.5 mm event on 4.5 mm: the cam would have no base circle
      d2.push_back(i);
      l2.push_back(4.5 + cycloidal_rise_fall(i) / 18.0);
      n2.push_back(i / 2 + 2);
    }
    const std::string e = error_of(d2, l2, n2, opt);
    CHECK_THAT(e, Contains("open.csv:2: the lift never comes down to the base circle: its smallest value is 4.5 mm "
                           "(at 0 cam deg), above the closure tolerance 0.05 mm"));
    for (auto& y : l2) y -= 4.5;  // measured from the base circle: accepted
    CHECK_NOTHROW(fit_target_lift(d2, l2, n2, opt));
  }
  SECTION("a gap above the base circle") {
    std::vector<double> d2, l2;
    for (std::size_t i = 0; i < deg.size(); ++i) {
      if (i > 10 && i < 30) continue;
      d2.push_back(deg[i]);
      l2.push_back(i < 50 ? lift[i] : 0.0);
    }
    const std::string e = error_of(d2, l2, {}, opt);
    CHECK_THAT(e, Contains("gap from 10 to 30 cam deg"));
  }
}

TEST_CASE("target lift: a step inside a table meant for interpolation names its row and suggests --smooth",
          "[synthesis][target_lift][errors]") {
  std::vector<double> deg, lift;
  std::vector<int> lines;
  for (int i = 0; i < 360; ++i) {
    deg.push_back(i);
    lift.push_back(cycloidal_rise_fall(i) + (i >= 60 && i < 100 ? 1.0 : 0.0));  // +1 mm over 60 .. 99 deg
    lines.push_back(i + 2);
  }
  TargetLiftOptions opt;
  opt.source = "step.csv";
  const std::string e = error_of(deg, lift, lines, opt);
  CHECK_THAT(e, Contains("step.csv:62: lift 5.5 mm at 60 cam deg follows 4.35003 mm at 59 cam deg"));
  CHECK_THAT(e, Contains("a step of 1.15 mm"));
  CHECK_THAT(e, Contains("--smooth"));
  // the same table without the step is clean; with smoothing the step is a measurement
  opt.smooth = true;
  CHECK_NOTHROW(fit_target_lift(deg, lift, lines, opt));
  opt.smooth = false;
  for (int i = 60; i < 100; ++i) lift[static_cast<std::size_t>(i)] -= 1.0;
  CHECK_NOTHROW(fit_target_lift(deg, lift, lines, opt));
}

TEST_CASE("target lift: noise in a table meant for interpolation names the worst row and suggests --smooth",
          "[synthesis][target_lift][errors]") {
  std::mt19937 gen(kSeed);
  std::vector<double> deg, lift, clean;
  std::vector<int> lines;
  for (int i = 0; i < 360; ++i) {
    deg.push_back(i);
    clean.push_back(cycloidal_rise_fall(i));
    // noise on the event only (lift > 5 sigma), so no row goes below the base circle
    lift.push_back(clean.back() + (clean.back() > 5 * kNoiseSigma ? kNoiseSigma * normal(gen) : 0.0));
    lines.push_back(i + 2);
  }
  TargetLiftOptions opt;
  opt.source = "noisy.csv";
  const std::string e = error_of(deg, lift, lines, opt);
  INFO(e);
  CHECK_THAT(e, Contains("noisy.csv:"));
  CHECK_THAT(e, Contains("the table is noisy"));
  CHECK_THAT(e, Contains("mm/deg^2"));
  CHECK_THAT(e, Contains("--smooth"));
  // the line named is the row whose value is quoted
  const int line = std::stoi(e.substr(e.find(':') + 1));
  const std::size_t row = static_cast<std::size_t>(line - 2);
  REQUIRE(row < lift.size());
  CHECK_THAT(e, Contains("at " + std::to_string(static_cast<int>(deg[row])) + " cam deg"));
  opt.smooth = true;
  CHECK_NOTHROW(fit_target_lift(deg, lift, lines, opt));
  // clean tables pass, down to a coarse 10 deg table of the same law (ratio about 0.16)
  opt.smooth = false;
  CHECK_NOTHROW(fit_target_lift(deg, clean, lines, opt));
  std::vector<double> coarse_deg, coarse;
  for (int i = 0; i < 36; ++i) coarse_deg.push_back(10.0 * i), coarse.push_back(cycloidal_rise_fall(10.0 * i));
  CHECK_NOTHROW(fit_target_lift(coarse_deg, coarse, {}, opt));
}

TEST_CASE("target lift: a measured table at 10 um resolution is noisy for interpolation (real ICESym data)",
          "[synthesis][target_lift][errors][real]") {
  const camopt::io::CsvTable csv =
      camopt::io::read_csv(std::string(CAMOPT_SHARED_DATA_DIR) + "/icesym_boscarol/Lv_I-bounous.csv");
  std::vector<double> deg = csv.column("crank_angle_deg");
  const std::vector<double>& lift = csv.column("valve_lift_mm");
  for (double& d : deg) d /= 2.0;  // crank -> cam
  TargetLiftOptions opt;
  opt.source = "Lv_I-bounous.csv";
  opt.closure_tolerance_mm = 0.1;
  const std::string e = error_of(deg, lift, csv.lines, opt);
  CHECK_THAT(e, Contains("Lv_I-bounous.csv:"));
  CHECK_THAT(e, Contains("the table is noisy"));
  opt.smooth = true;
  CHECK_NOTHROW(fit_target_lift(deg, lift, csv.lines, opt));
}

TEST_CASE("target lift: smoothing recovers a noisy cycloidal rise-fall", "[synthesis][target_lift][smooth]") {
  // n = 360 sites, m = 45 knots (8 deg): the residual rms is about sigma sqrt(1 - m/n)
  // = 0.0094 mm and the noise left in the fit about sigma sqrt(m/n) = 0.0035 mm rms. (with
  // the default 4 deg knots these are 0.0087 and 0.005 mm, and the worst deviation over a
  // cycle is above 0.01 mm for most seeds.) the bounds below hold for every one of 200
  // seeds tried (rms 0.0082 .. 0.0103, worst deviation <= 0.0147 mm, bias 4e-4 mm).
  std::mt19937 gen(kSeed);
  std::vector<double> deg, lift;
  for (int i = 0; i < 360; ++i) {
    deg.push_back(i);
    lift.push_back(cycloidal_rise_fall(i) + kNoiseSigma * normal(gen));
  }
  TargetLiftOptions opt;
  opt.smooth = true;
  opt.smoothing_knot_spacing_deg = 8.0;
  opt.source = "noisy.csv";
  const TargetLift t = fit_target_lift(deg, lift, {}, opt);
  INFO("residual rms " << t.residual_rms_mm << " max " << t.residual_max_mm << " at " << t.residual_max_at_deg);
  CHECK(t.residual_rms_mm > 0.008);
  CHECK(t.residual_rms_mm < 0.012);
  CHECK(t.residual_max_mm < 5 * kNoiseSigma);
  CHECK(t.closure_message.find("covers the full cycle") != std::string::npos);
  test::Series law("smoothed lift against the clean law [mm]", "cam [deg]");
  double sum2 = 0.0;
  int count = 0;
  for (double d = 0.0; d < 360.0; d += 0.25, ++count) {
    const double e = t.lift_at(d) - cycloidal_rise_fall(d);
    law.add(d, t.lift_at(d), cycloidal_rise_fall(d));
    sum2 += e * e;
  }
  const double rms_deviation = std::sqrt(sum2 / count);
  CHECK_ABS(rms_deviation, 0.0, tol::kSmoothedRmsAbs);
  CHECK_SERIES(law.compare({.abs = tol::kSmoothedLawAbs}));
  CHECK_ABS(t.max_lift_mm, 9.0, tol::kSmoothedPeakLiftAbs);
  CHECK_ABS(t.max_lift_at_deg, 120.0, tol::kSmoothedPeakAngleAbs);
  require_c4(t.lift);

  // the conversion to PeriodicSpline reproduces the fitted b-spline
  PeriodicBSpline fit;
  REQUIRE(fit_periodic_bspline(deg, lift, opt.smoothing_knot_spacing_deg, fit).ok());
  test::Series conversion("smoothed lift against the fitted b-spline [mm]", "cam [deg]");
  for (double d = 0.0; d < 360.0; d += 0.05) conversion.add(d, t.lift_at(d), fit(d));
  CHECK_SERIES(conversion.compare({.abs = tol::kBSplineConversionAbs}));
}

TEST_CASE("target lift: periodic b-spline fit reproduces a spline in its space", "[synthesis][target_lift][smooth]") {
  PeriodicBSpline s;
  s.spacing_deg = 10.0;
  for (int j = 0; j < 36; ++j) s.coef.push_back(std::sin(j * 0.7) + 0.1 * j);
  std::vector<double> deg, lift;
  for (double d = -180.0; d < 180.0; d += 1.3) {
    deg.push_back(d);
    lift.push_back(s(d));
  }
  PeriodicBSpline fit;
  REQUIRE(fit_periodic_bspline(deg, lift, 10.0, fit).ok());
  REQUIRE_SERIES(test::compare_series("fitted coefficient", fit.coef, s.coef, {.abs = tol::kSplineSpaceFitAbs}));
  // derivatives against central differences
  for (double d = 3.3; d < 360.0; d += 17.0) {
    for (int k = 1; k <= 4; ++k) {
      const double h = 1e-3;
      const double fd = (s.derivative(d + h, k - 1) - s.derivative(d - h, k - 1)) / (2 * h);
      INFO("cam " << d << " deg, derivative " << k);
      REQUIRE_NEAR(fd, s.derivative(d, k), tol::kBSplineFdRel, tol::kBSplineFdRel);
    }
  }
  // a knot interval without data is rejected
  std::vector<double> sparse = {0.0, 100.0, 200.0};
  std::vector<double> vals = {1.0, 2.0, 3.0};
  PeriodicBSpline unfitted;
  CHECK_THROWS_AS((void)fit_periodic_bspline(sparse, vals, 10.0, unfitted, "sparse.csv"), InputError);
  // so is a knot spacing giving fewer than 6 knots, and a derivative order beyond 5
  CHECK_THROWS_WITH((void)fit_periodic_bspline(deg, lift, 61.0, unfitted, "wide.csv"),
                    Contains("smoothing knot spacing 61 cam deg: must be > 0 and <= 60 cam deg"));
  CHECK_THROWS_AS(s.derivative(10.0, 6), InputError);
  CHECK_THROWS_WITH(s.derivative(10.0, 6), Contains("order k = 6 must be in 0 .. 5"));
  CHECK_THROWS_WITH(unfitted.derivative(10.0, 0), Contains("must be >= 6 at a spacing > 0"));
}

TEST_CASE("target lift: each option and argument rule is an input error naming the field, the value and the rule",
          "[synthesis][target_lift][errors]") {
  const std::vector<double> deg = {0, 90, 180, 270}, lift = {0, 1, 2, 1};
  const std::vector<int> lines = {2, 3, 4, 5};
  TargetLiftOptions opt;
  opt.source = "t.csv";
  CHECK_NOTHROW(opt.validate());
  SECTION("closure_tolerance_mm") {
    for (const double bad : {-0.1, std::nan("")}) {
      opt.closure_tolerance_mm = bad;
      CHECK_THROWS_AS(opt.validate(), InputError);
      const std::string e = error_of(deg, lift, lines, opt);
      CHECK_THAT(e, Contains("t.csv: target lift option closure_tolerance_mm = "));
      CHECK_THAT(e, Contains(" mm must be finite and >= 0"));
    }
  }
  SECTION("smoothing_knot_spacing_deg, when smoothing") {
    opt.smoothing_knot_spacing_deg = 0.0;
    CHECK_NOTHROW(opt.validate());  // not used without smoothing
    opt.smooth = true;
    for (const double bad : {0.0, -4.0, 61.0}) {
      opt.smoothing_knot_spacing_deg = bad;
      CHECK_THROWS_AS(opt.validate(), InputError);
      CHECK_THAT(error_of(deg, lift, lines, opt),
                 Contains("target lift option smoothing_knot_spacing_deg = " + camopt::format_value(bad) +
                          " cam deg must be > 0 and <= 60 cam deg when smoothing"));
    }
  }
  SECTION("one lift per angle") {
    CHECK_THAT(error_of(deg, {0, 1, 2}, {}, opt), Contains("lift_mm has 3 rows, must have as many as cam_deg (4)"));
  }
  SECTION("one line per row, or none") {
    CHECK_THAT(error_of(deg, lift, {2, 3}, opt), Contains("lines has 2 entries, must be empty or one per row (4)"));
  }
  SECTION("finite rows") {
    CHECK_THAT(error_of(deg, {0, 1, std::nan(""), 1}, lines, opt), Contains("t.csv:4: angle 180 cam deg and lift nan mm must both be finite"));
    CHECK_THAT(error_of({0, 90, INFINITY, 270}, lift, lines, opt), Contains("angle inf cam deg and lift 2 mm must both be finite"));
  }
  SECTION("strictly increasing angles") {
    const std::string e = error_of({0, 90, 90, 270}, lift, lines, opt);
    CHECK_THAT(e, Contains("t.csv:4: angle 90 cam deg must be above the previous row's 90 (strictly increasing)"));
    CHECK_THAT(e, Contains("(rule: "));
  }
}

TEST_CASE("target lift: absurd values and crowded angles are input errors naming the row", "[synthesis][target]") {
  TargetLiftOptions opt;
  opt.source = "t.csv";
  // a lift cell of 1.4e301 mm (found by the fuzzer: the spline overflowed to NaN)
  const std::string big = error_of({0, 90, 180, 270}, {0, 5, 1.4e301, 5}, {2, 3, 4, 5}, opt);
  CHECK_THAT(big, Catch::Contains("t.csv:4"));
  CHECK_THAT(big, Catch::Contains("lift must be <= 1000 mm"));
  // two angles 1e-12 deg apart: closing the cycle at that spacing would take 3.6e14 points
  const std::string crowded = error_of({0, 1e-12}, {0, 0}, {2, 3}, opt);
  CHECK_THAT(crowded, Catch::Contains("t.csv"));
  CHECK_THAT(crowded, Catch::Contains("too close together"));
}

TEST_CASE("target lift: rows closer than 1e-6 deg are an input error naming the line (fuzz crash 024fd5e8)",
          "[synthesis][target_lift]") {
  // the fuzzer's table: 0, 1e-14, 39.2 deg reached the spline's singular collocation system
  for (const bool smooth : {false, true}) {
    TargetLiftOptions opt;
    opt.smooth = smooth;
    opt.source = "fuzz.csv";
    const std::string e = error_of({0.0, 1e-14, 39.19999999999}, {0.0, 1.0, 0.0}, {2, 3, 4}, opt);
    INFO(e);
    CHECK_THAT(e, Contains("fuzz.csv:3"));
    CHECK_THAT(e, Contains("rows must be at least 1e-06 deg apart"));
    CHECK_THAT(e, Contains("too close together"));
  }
}
