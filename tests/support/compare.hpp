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
