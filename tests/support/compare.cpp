// the compare helper of the tests (compare.hpp): the allowed error of a tolerance, the worst
// point of a series, and the failure message.
#include "support/compare.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace camopt::test {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// |value - reference|, +infinity when either is not finite (so it is the worst point and fails)
double error_of(double value, double reference) {
  if (!std::isfinite(value) || !std::isfinite(reference)) return kInf;
  return std::abs(value - reference);
}

// why a tolerance cannot be used, or empty: each part finite and not negative
std::string tolerance_problem(Tolerance tol) {
  if (!std::isfinite(tol.abs) || !std::isfinite(tol.rel)) return "tolerance not finite";
  if (tol.abs < 0.0 || tol.rel < 0.0) return "tolerance negative";
  return {};
}

// the allowed error for a scale (|reference| or the peak |reference| of a series)
double allowed_of(Tolerance tol, double scale) { return std::max(tol.abs, tol.rel * scale); }

// a number as the message prints it: shortest round-trip
std::string num(double x) {
  std::array<char, 32> buf{};
  const auto end = std::to_chars(buf.data(), buf.data() + buf.size(), x).ptr;
  return std::string(buf.data(), end);
}

// the verdict of a comparison whose error and allowed error are filled in
void decide(Comparison& c, Tolerance tol) {
  c.reason = tolerance_problem(tol);
  if (c.reason.empty() && !std::isfinite(c.error)) c.reason = "not finite";
  c.pass = c.reason.empty() && c.error <= c.allowed;
}

// the worst point of n entries read through value(i) and reference(i)
template <class Value, class Reference>
Comparison worst_of(std::string_view name, std::size_t n, Value value, Reference reference, Tolerance tol,
                    std::size_t& at) {
  Comparison c;
  c.name = name;
  double peak = 0.0;
  bool finite_peak = true;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = reference(i);
    if (!std::isfinite(r)) finite_peak = false;
    else peak = std::max(peak, std::abs(r));
  }
  c.error = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = error_of(value(i), reference(i));
    if (e > c.error) c.error = e, at = i;
  }
  c.value = value(at);
  c.reference = reference(at);
  c.allowed = allowed_of(tol, finite_peak ? peak : kInf);
  decide(c, tol);
  return c;
}

}  // namespace

std::string Comparison::describe() const {
  std::ostringstream os;
  os << name << (pass ? ": within tolerance" : ": FAILED");
  if (!reason.empty()) os << " (" << reason << ")";
  if (!where.empty()) os << " at " << where;
  os << ": value " << num(value) << ", reference " << num(reference) << ", error " << num(error) << ", allowed "
     << num(allowed);
  return os.str();
}

Comparison compare(std::string_view name, double value, double reference, Tolerance tol) {
  Comparison c;
  c.name = name;
  c.value = value;
  c.reference = reference;
  c.error = error_of(value, reference);
  c.allowed = allowed_of(tol, std::isfinite(reference) ? std::abs(reference) : kInf);
  decide(c, tol);
  return c;
}

Comparison compare_series(std::string_view name, std::span<const double> value, std::span<const double> reference,
                          Tolerance tol, std::span<const double> at, std::string_view at_label) {
  if (value.empty() || value.size() != reference.size() || (!at.empty() && at.size() != value.size())) {
    Comparison c;
    c.name = name;
    c.reason = "series of lengths " + std::to_string(value.size()) + " (value), " + std::to_string(reference.size()) +
               " (reference), " + std::to_string(at.size()) + " (" + std::string(at_label) + ")";
    return c;
  }
  std::size_t i = 0;
  Comparison c = worst_of(name, value.size(), [&](std::size_t k) { return value[k]; },
                          [&](std::size_t k) { return reference[k]; }, tol, i);
  c.where = "index " + std::to_string(i);
  if (!at.empty()) c.where += ", " + std::string(at_label) + " " + num(at[i]);
  return c;
}

Comparison compare_matrix(std::string_view name, const Eigen::Ref<const Eigen::MatrixXd>& value,
                          const Eigen::Ref<const Eigen::MatrixXd>& reference, Tolerance tol) {
  if (value.size() == 0 || value.rows() != reference.rows() || value.cols() != reference.cols()) {
    Comparison c;
    c.name = name;
    c.reason = "shapes " + std::to_string(value.rows()) + "x" + std::to_string(value.cols()) + " (value), " +
               std::to_string(reference.rows()) + "x" + std::to_string(reference.cols()) + " (reference)";
    return c;
  }
  const auto rows = static_cast<std::size_t>(value.rows());
  const auto entry = [rows](const auto& m, std::size_t k) {
    return m(static_cast<Eigen::Index>(k % rows), static_cast<Eigen::Index>(k / rows));
  };
  std::size_t k = 0;
  Comparison c = worst_of(name, static_cast<std::size_t>(value.size()),
                          [&](std::size_t i) { return entry(value, i); },
                          [&](std::size_t i) { return entry(reference, i); }, tol, k);
  c.where = "row " + std::to_string(k % rows) + ", column " + std::to_string(k / rows);
  return c;
}

void SweepCompare::add(double driver, const Motion& kernel, const Motion& oracle) {
  driver_.push_back(driver);
  for (std::size_t k = 0; k < 4; ++k) {
    double value = kernel[k];
    // an angle's displacement: the kernel's value brought within pi of the oracle's
    if (k == 0 && angle_ && std::isfinite(value) && std::isfinite(oracle[k]))
      value = oracle[k] + std::remainder(value - oracle[k], 2.0 * std::numbers::pi);
    kernel_[k].push_back(value);
    oracle_[k].push_back(oracle[k]);
  }
}

std::vector<Comparison> SweepCompare::compare(const double (&rel)[4]) const {
  std::vector<Comparison> out;
  for (std::size_t k = 0; k < 4; ++k)
    out.push_back(compare_series(name_ + ": d^" + std::to_string(k), kernel_[k], oracle_[k], {.rel = rel[k]}, driver_,
                                 "driver"));
  return out;
}

}  // namespace camopt::test
