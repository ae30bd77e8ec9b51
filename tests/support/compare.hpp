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
#include "support/tolerances.hpp"

namespace camopt::test {


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
