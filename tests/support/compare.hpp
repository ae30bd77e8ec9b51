#pragma once
// the one compare helper of the tests: named tolerances, scalar checks (absolute, relative,
// absolute-or-relative) and series checks (the worst point over a sweep). Every check fails
// on a value, reference or tolerance that is not finite, and its message names the quantity,
// the value, the reference, the error, the allowed error and (for a series) the worst point.
//
//   CHECK_ABS(lift, 1.5, tol::kRoundOffAbs);            // |lift - 1.5| <= tol
//   CHECK_REL(force, closed_form, tol::kSolverRel);     // <= tol * |closed_form|
//   CHECK_NEAR(x, 0.0, tol::kNodeAbs, tol::kJetRel);    // <= max(abs, rel * |reference|)
//   CHECK_SERIES(compare_series("lift", v, r, {.abs = tol::kLiftAbs}, angles, "angle [deg]"));
//
// the macros report through Catch at the caller's file:line; the compare_* functions return
// a Comparison that the helper's own tests read directly.
#include <Eigen/Core>
#include <array>
#include <catch2/catch.hpp>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace camopt::test {

// named tolerances, each with the reason for its size
namespace tol {
// the kinematics engine against closed forms, each relative to the peak magnitude of the same
// quantity over the sweep (docs/kinematics.md#accuracy): position solves to ~1e-12, the
// derivatives come from implicit differentiation of the same solve
inline constexpr double kDisplacementRel = 1e-9;
inline constexpr double kVelocityRel = 1e-7;
inline constexpr double kAccelerationRel = 1e-7;
inline constexpr double kJerkRel = 1e-5;
inline constexpr double kOrderRel[4] = {kDisplacementRel, kVelocityRel, kAccelerationRel, kJerkRel};

// round-off
inline constexpr double kUlpRel = 1e-15;           // one closed form evaluated along two paths: a few ulps
inline constexpr double kUlpAbs = 1e-15;           // the same, for a quantity of size ~1 that may be 0
inline constexpr double kOctantTrigAbs = 2.3e-16;    // sin/cos from the first octant: libm's error there, below an ulp of 1
inline constexpr double kReorderedSumRel = 1e-14;  // the same sum accumulated in another order

// finite differences (tests/oracles/finite_difference.hpp): truncation + round-off at the step used
inline constexpr double kCentral8Step1e3Rel = 1e-11;  // 8th order at h = 1e-3: truncation ~1e-24 f^(9), round-off ~1e-13
inline constexpr double kCentral2Step1e5Rel = 1e-8;   // 2-point at h = 1e-5: truncation h^2 f'''/6 ~1e-10, round-off ~1e-11

// jets and splines (core)
inline constexpr double kJetRecurrenceRel = 1e-13;     // Taylor recurrences against a symbolic closed form
inline constexpr double kJetRecurrenceAbs = 1e-14;     // the same, for references that are ~0
inline constexpr double kJetTwoFormsRel = 1e-12;       // two jet formulations of one function (atan2 vs atan(y/x), compose vs direct)
inline constexpr double kSplineJetRel = 1e-14;         // a spline's jet overload against its scalar derivatives
inline constexpr double kSplineNodeAbs = 1e-12;        // interpolation at the data sites, |f| ~ 1: solve round-off
inline constexpr double kSplineContinuityRel = 1e-9;   // left/right limits at a knot, of max |f^(k)| (f'''' amplifies round-off)
inline constexpr double kSplineWrapRel = 1e-12;        // f^(k)(x + 3 period) vs f^(k)(x): x + 3 period rounds by ~1e-15 rad
inline constexpr double kSplineSolverRel = 1e-12;      // two solvers of one spline system (sparse LU, banded), of the peak
inline constexpr double kCyclicFilterRel = 4e-15;      // residual of the recursive cyclic filter, of the right-hand side
inline constexpr double kSplineIntegralRel = 1e-12;    // exact piecewise integral against Gauss-Legendre
inline constexpr double kSplinePolyAbs = 1e-10;        // reproduction of a quadratic (f'' amplifies round-off by 1/h^2)
inline constexpr double kNaturalEndThirdAbs = 1e-9;    // f''' = 0 at a natural end: solve round-off / h^3
inline constexpr double kNaturalEndFourthAbs = 1e-8;   // f'''' = 0 at a natural end: solve round-off / h^4
inline constexpr double kSplineExtrapolationAbs = 1e-14;  // linear extrapolation a + a' d against the same line, |f| ~ 1
inline constexpr double kSplineExtremeAbs = 1e-6;      // a spline's extreme against the function's: interpolation error at 40 knots

// kinematics: contact outputs and derivatives (tests/kinematics)
inline constexpr double kContactPointRel = kDisplacementRel;  // contact point and normal, of the mechanism size
inline constexpr double kPressureAngleAbs = 1e-9;   // [rad] a position-level angle against its closed form
inline constexpr double kContactRateRel = kVelocityRel;  // roller speed, sliding, entrainment (per rad of cam), of the peak
inline constexpr double kCurvatureRel = 1e-9;       // a position-level output (curvature) against its closed form
inline constexpr double kKernelFdRel = 1e-7;        // solved jets against 6th/8th-order central differences at 1e-3 rad, of the peak
inline constexpr double kNewtonCentringAbs = 1e-6;  // [deg of u] four Newton steps centring a sample in its table piece
inline constexpr double kGapAbs = 1e-12;            // [mm] a contact's clearance against its closed form: solve round-off
inline constexpr double kLiftLossAbs = 1e-12;       // [mm] a summary's peak lift against its closed form
inline constexpr double kPeakAngleAbs = 1e-6;       // [deg] the refined angle of a symmetric peak
inline constexpr double kSweepCountAbs = 2.0;       // points of a span counted on the sweep grid: one at each end
inline constexpr double kPoseAbs = 1e-9;            // [mm] a point that the constraints hold in place
inline constexpr double kSolverPathAbs = 1e-9;      // [mm or rad] two solve paths, each to 1e-13 x size, through the chain's conditioning
inline constexpr double kPrescribedAbs = 1e-11;     // [mm] a prescribed solve against the whole solve, one point
inline constexpr double kOutputLiftRel = 1e-12;     // output lift against raw - rest: one subtraction, of max(1, |raw|)
inline constexpr double kGridPeakAbs = 1e-12;       // [mm] the refined peak never below the grid's (one rounding)
inline constexpr double kEccentricSolveAbs = 1e-11; // [mm] solved eccentric flat-follower lift (Newton to 1e-13 x size)
inline constexpr double kEccentricRateAbs = 1e-9;   // [mm/rad^k] its derivatives by implicit differentiation
inline constexpr double kBruteForceLiftAbs = 1e-8;  // [mm] kernel lift against a brute-force touching height (resolves ~1e-11 mm)
inline constexpr double kChordSpline24Abs = 2e-6;   // [mm] lift from a 24-point chord-length cubic spline contour; O(h^4) below (measured 1.4e-6)
inline constexpr double kTransmissionSineAbs = 1e-4;  // a transmission sine against its value printed to 4 digits
inline constexpr double kPrintedLiftAbs = 0.01;     // [mm] a design's max lift against its documented 3-digit value
inline constexpr double kPrintedLimitAbs = 0.01;    // [deg] a reported limit against its 2-decimal value
inline constexpr double kPrintedRadiusAbs = 1e-3;   // [mm] a profile radius against its documented value
inline constexpr double kPrintedMaxRadiusAbs = 2e-3;  // [mm] the same for the max radius read off a measured table
inline constexpr double kPrintedValveLiftAbs = 5e-4;  // [mm] a valve lift against its value printed to 3 decimals
inline constexpr double kTaylorShiftAbs = 8 * 2.220446049250313e-16 * 10.0;  // a degree-4 Taylor shift: 8 roundings of terms up to ~10
inline constexpr double kPointSeriesAbs = 4 * 2.220446049250313e-16;  // profile point series vs the jet evaluation, of their size (same operations)
inline constexpr double kPointSeriesShiftAbs = 16 * 2.220446049250313e-16;  // a shifted memo entry vs a fresh evaluation, of their size
inline constexpr double kPointCoordAbs = 4 * 2.220446049250313e-16 * 30.0;  // [mm] point and slope, |x| <= 30: 4 roundings
inline constexpr double kPointCurvAbs = 4 * 2.220446049250313e-16 * 300.0;  // second derivative, |x''| <= 300: 4 roundings
inline constexpr double kRotatedSinCosAbs = 2 * 2.220446049250313e-16;      // sin, cos rotated by a small angle: two ulps of 1
inline constexpr double kVariableGearAbs[4] = {1e-13, 1e-12, 1e-11, 1e-10};  // a variable gear's jet: Newton to 1e-13, each order one more 1/h
inline constexpr double kGearInverseAbs[3] = {1e-12, 1e-12, 1e-11};          // its inverse, the same
inline constexpr double kFastGeneralRel[4] = {1e-10, 1e-9, 1e-8, 1e-7};  // two contact formulations, each solved to 1e-13: round-off ~1e-11 of each order's peak
inline constexpr double kFastGeneralContactRel = 1e-8;  // their contact quantities and condition numbers, of the peak
inline constexpr double kPrescribedRel[4] = {1e-12, 1e-11, 1e-10, 1e-9};  // a prescribed pose vs the whole solve from the same bits: round-off, of each order's peak
inline constexpr double kRefinedPeakRel = 0.01;    // the refined peak above the peak of a 2-deg grid: the lift's curvature over a step
inline constexpr double kRefinedPeakAbs = 1e-9;     // [mm] the same, for a peak of ~0

// stress (tests/stress)
inline constexpr double kConditionRel = 1e-6;        // a link's condition number against its closed form, near toggle
inline constexpr double kSummaryOfSameRel = 1e-12;   // a summary's extreme against the extreme of the same per-point values
inline constexpr double kRefinedExtremeRel = 1e-6;   // a refined extreme against the largest of a 0.5-deg grid's closed forms
inline constexpr double kQuasiStaticForceRel = 1e-2; // compliant contact forces against rigid ones at <= 10 rpm: the deflection's share of the peak
}  // namespace tol

// the outcome of one comparison
struct Comparison {
  std::string name;         // the quantity compared
  bool pass = false;        // within the allowed error, and everything finite
  double value = 0.0;       // at the worst point of a series
  double reference = 0.0;   // at the worst point of a series
  double error = 0.0;       // |value - reference| (+inf when either is not finite)
  double allowed = 0.0;     // the allowed |value - reference|
  std::string where;        // the worst point of a series ("index 12, angle [deg] 6"); empty for a scalar
  std::string reason;       // why it failed, when not for the size of the error (a non-finite tolerance, ...)

  std::string describe() const;
};

// a tolerance: the allowed error is max(abs, rel * scale), scale being |reference| for a
// scalar and the peak |reference| over the series for a series
struct Tolerance {
  double abs = 0.0;
  double rel = 0.0;
};

// one value against its reference
Comparison compare(std::string_view name, double value, double reference, Tolerance tol);
inline Comparison compare_abs(std::string_view name, double value, double reference, double abs) {
  return compare(name, value, reference, {.abs = abs});
}
inline Comparison compare_rel(std::string_view name, double value, double reference, double rel) {
  return compare(name, value, reference, {.rel = rel});
}

// a series against its reference, point by point; the worst point is reported by its index
// and, when `at` is given (same length), by its abscissa (a driver angle, a time, ...). An
// empty series, or series of different lengths, fail.
Comparison compare_series(std::string_view name, std::span<const double> value, std::span<const double> reference,
                          Tolerance tol, std::span<const double> at = {}, std::string_view at_label = "at");
// the same for Eigen vectors and matrices (entries compared one by one; the worst entry is
// reported by row and column); the scale of tol.rel is the largest |reference| entry
Comparison compare_matrix(std::string_view name, const Eigen::Ref<const Eigen::MatrixXd>& value,
                          const Eigen::Ref<const Eigen::MatrixXd>& reference, Tolerance tol);

// a series built point by point, for a loop over a sweep:
//   Series s("contact force [N]", "angle [deg]");
//   for (...) s.add(angle, kernel, closed_form);
//   CHECK_SERIES(s.compare({.rel = tol::kForceRel}));
class Series {
 public:
  explicit Series(std::string name, std::string at_label = "driver") : name_(std::move(name)), at_label_(std::move(at_label)) {}
  void add(double at, double value, double reference) {
    at_.push_back(at);
    value_.push_back(value);
    reference_.push_back(reference);
  }
  Comparison compare(Tolerance tol) const { return compare_series(name_, value_, reference_, tol, at_, at_label_); }
  std::size_t size() const { return at_.size(); }

 private:
  std::string name_, at_label_;
  std::vector<double> at_, value_, reference_;
};

// a displacement and its three derivatives against an oracle over a sweep: compare(rel) gives
// one Comparison per order k, within rel[k] of the oracle's peak |d^k| over the sweep; the
// displacement of an angle is compared modulo 2 pi.
class SweepCompare {
 public:
  using Motion = std::array<double, 4>;
  SweepCompare(std::string name, bool angle) : name_(std::move(name)), angle_(angle) {}
  void add(double driver, const Motion& kernel, const Motion& oracle);
  std::vector<Comparison> compare(const double (&rel)[4] = tol::kOrderRel) const;
  std::size_t size() const { return driver_.size(); }

 private:
  std::string name_;
  bool angle_;
  std::vector<double> driver_;
  std::array<std::vector<double>, 4> kernel_, oracle_;
};

// one scalar quantity (a contact quantity, a force) against its closed form over a sweep:
// within max(abs, rel * peak |closed form|)
class ScalarCompare {
 public:
  explicit ScalarCompare(std::string name) : series_(std::move(name)) {}
  void add(double driver, double kernel, double oracle) { series_.add(driver, kernel, oracle); }
  Comparison compare(double rel, double abs = 0.0) const { return series_.compare({.abs = abs, .rel = rel}); }

 private:
  Series series_;
};

}  // namespace camopt::test

// report a Comparison (or a list of them) through Catch at the caller's file:line
#define CAMOPT_REPORT_COMPARISON_(macro, ...)                     \
  do {                                                            \
    const ::camopt::test::Comparison camopt_cmp_ = (__VA_ARGS__); \
    INFO(camopt_cmp_.describe());                                 \
    macro(camopt_cmp_.pass);                                      \
  } while (false)

#define CHECK_COMPARISON(...) CAMOPT_REPORT_COMPARISON_(CHECK, __VA_ARGS__)
#define REQUIRE_COMPARISON(...) CAMOPT_REPORT_COMPARISON_(REQUIRE, __VA_ARGS__)
#define CHECK_SERIES(...) CHECK_COMPARISON(__VA_ARGS__)
#define REQUIRE_SERIES(...) REQUIRE_COMPARISON(__VA_ARGS__)

// each comparison of a list (a sweep's orders), reported one by one
#define CHECK_COMPARISONS(...)                                  \
  do {                                                          \
    for (const ::camopt::test::Comparison& camopt_cmp_ : (__VA_ARGS__)) { \
      INFO(camopt_cmp_.describe());                             \
      CHECK(camopt_cmp_.pass);                                  \
    }                                                           \
  } while (false)

// scalars: the quantity's name is the expression as written
#define CHECK_ABS(value, reference, abs_tol) \
  CHECK_COMPARISON(::camopt::test::compare_abs(#value, (value), (reference), (abs_tol)))
#define CHECK_REL(value, reference, rel_tol) \
  CHECK_COMPARISON(::camopt::test::compare_rel(#value, (value), (reference), (rel_tol)))
#define CHECK_NEAR(value, reference, abs_tol, rel_tol) \
  CHECK_COMPARISON(::camopt::test::compare(#value, (value), (reference), {.abs = (abs_tol), .rel = (rel_tol)}))
#define REQUIRE_ABS(value, reference, abs_tol) \
  REQUIRE_COMPARISON(::camopt::test::compare_abs(#value, (value), (reference), (abs_tol)))
#define REQUIRE_REL(value, reference, rel_tol) \
  REQUIRE_COMPARISON(::camopt::test::compare_rel(#value, (value), (reference), (rel_tol)))
#define REQUIRE_NEAR(value, reference, abs_tol, rel_tol) \
  REQUIRE_COMPARISON(::camopt::test::compare(#value, (value), (reference), {.abs = (abs_tol), .rel = (rel_tol)}))
