#include "camopt/synthesis/target_lift.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"

namespace camopt::synthesis {

namespace {

constexpr double kCycleDeg = 360.0;
constexpr double kMaxLift = 1000.0;  // [mm] no valve lifts a metre: larger values are a unit or column mistake
constexpr double kRoundingNegative = 1e-3;  // [mm] negatives treated as rounding of 0 (1 um: exported or measured tables)
constexpr double kSpanRelTol = 1e-9;        // |span - 360| <= this * 360: exactly one cycle
constexpr double kWrapGapFactor = 1.5;      // wrap interval / median spacing above which the cycle is not covered
constexpr double kInteriorGapFactor = 4.0;  // interior interval / median spacing above which it is a gap
constexpr double kFineGridDeg = 0.5;        // [cam deg] largest step of the smoothing conversion grid
// steps (interpolation only): an interval rising more than kStepFraction of the peak lift
// with a slope more than kStepSlopeFactor times the slope on both sides of it
constexpr double kStepFraction = 0.02;
constexpr double kStepSlopeFactor = 5.0;
// noise (interpolation only), over windows of 5 equally spaced rows above kNoiseMinLift of
// the peak: median |4th difference| / largest |2nd difference|. Smooth data gives
// (2 pi h / T)^2 * ~0.6 (a cycloid of duration T = 12 rows: 0.17); white noise alone gives
// ~3.4 times its own 2nd differences. Above kNoiseRatio the acceleration of an exact
// interpolant follows the noise. (Real tables in shared/data/real: clean 0.001 .. 0.29,
// measured at 10 um resolution 0.5 .. 0.68.)
constexpr double kNoiseRatio = 0.4;
constexpr double kNoiseMinLift = 0.05;
constexpr int kNoiseMinWindows = 8;
constexpr int kDegree = 5;

std::string fmt(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string where(const std::string& file, int line) {
  SourceRef ref;
  ref.file = file;
  ref.line = line;
  return ref.str();
}

double wrap360(double deg) {
  double w = std::fmod(deg, kCycleDeg);
  if (w < 0) w += kCycleDeg;
  return w;
}

// uniform quintic b-spline values b[r] = N5(u + 5 - r), r = 0..5, at local u in [0, 1):
// cox-de boor on unit knots, N_k(t) = t/k N_{k-1}(t) + (k+1-t)/k N_{k-1}(t-1)
void uniform_basis(double u, int degree, double* b) {
  b[0] = 1.0;
  for (int k = 1; k <= degree; ++k) {
    double prev = 0.0;  // b^{k-1}_{r-1}
    for (int r = 0; r <= k; ++r) {
      const double cur = r < k ? b[r] : 0.0;  // b^{k-1}_r
      b[r] = ((u + k - r) * prev + (r + 1 - u) * cur) / k;
      prev = cur;
    }
  }
}

struct Site {
  double deg;   // [cam deg] as written (or filled)
  double lift;  // [mm]
  int row;      // index into the input, -1 for a filled zero-lift point
};

// rows first .. last equally spaced (to 1e-6 of their spacing)
bool equally_spaced(const std::vector<Site>& data, std::size_t first, std::size_t last) {
  const double h = data[first + 1].deg - data[first].deg;
  for (std::size_t k = first; k < last; ++k)
    if (std::abs((data[k + 1].deg - data[k].deg) - h) > 1e-6 * h) return false;
  return true;
}

// "file:line" of input row i, for messages
struct RowRef {
  const std::string& file;
  const std::vector<int>& lines;  // file line of each row (may be empty)
  std::string operator()(std::size_t i) const { return where(file, lines.empty() ? 0 : lines[i]); }
};

// clean tables only: an exact interpolant rings at a step and follows noise in its
// acceleration, so both are rejected with the row, the values and the remedy
void check_steps_and_noise(const std::vector<Site>& data, const RowRef& at_row) {
  const std::size_t n = data.size();
  double peak = 0.0;
  for (const Site& s : data) peak = std::max(peak, s.lift);
  if (!(peak > 0.0) || n < 5) return;
  auto slope = [&](std::size_t i) { return (data[i + 1].lift - data[i].lift) / (data[i + 1].deg - data[i].deg); };
  for (std::size_t i = 1; i + 2 < n; ++i) {
    const double rise = data[i + 1].lift - data[i].lift;
    const double side = std::max(std::abs(slope(i - 1)), std::abs(slope(i + 1)));
    if (std::abs(rise) > kStepFraction * peak && std::abs(slope(i)) > kStepSlopeFactor * side) {
      throw InputError(at_row(static_cast<std::size_t>(data[i + 1].row)) + ": lift " + fmt(data[i + 1].lift) +
                       " mm at " + fmt(data[i + 1].deg) + " cam deg follows " + fmt(data[i].lift) + " mm at " +
                       fmt(data[i].deg) + " cam deg: a step of " + fmt(rise, 3) + " mm (slope " +
                       fmt(std::abs(slope(i)) / std::max(side, 1e-300), 3) +
                       " times that on either side); an exact interpolant would ring around it. Give the rows of "
                       "the transition, or smooth a measured table (camopt synthesize --smooth)");
    }
  }
  // 2nd and 4th differences over windows of 5 equally spaced rows on the lift event
  std::vector<double> fourth;
  double largest_second = 0.0, worst_fourth = 0.0, worst_spacing = 1.0;
  std::size_t worst = 0;
  for (std::size_t i = 2; i + 2 < n; ++i) {
    const double h = data[i + 1].deg - data[i].deg;
    bool lifted = true;
    for (std::size_t k = i - 2; k <= i + 2; ++k)
      if (data[k].lift < kNoiseMinLift * peak) lifted = false;
    if (!lifted || !equally_spaced(data, i - 2, i + 2)) continue;
    const double second = data[i - 1].lift - 2 * data[i].lift + data[i + 1].lift;
    const double d4 = data[i - 2].lift - 4 * data[i - 1].lift + 6 * data[i].lift - 4 * data[i + 1].lift + data[i + 2].lift;
    largest_second = std::max(largest_second, std::abs(second));
    fourth.push_back(std::abs(d4));
    if (std::abs(d4) > worst_fourth) worst_fourth = std::abs(d4), worst = i, worst_spacing = h;
  }
  if (static_cast<int>(fourth.size()) < kNoiseMinWindows || !(largest_second > 0.0)) return;
  std::nth_element(fourth.begin(), fourth.begin() + static_cast<std::ptrdiff_t>(fourth.size() / 2), fourth.end());
  const double median_fourth = fourth[fourth.size() / 2];
  const double ratio = median_fourth / largest_second;
  if (ratio > kNoiseRatio) {
    const Site& s = data[worst];
    const double h2 = worst_spacing * worst_spacing;
    throw InputError(at_row(static_cast<std::size_t>(s.row)) + ": lift " + fmt(s.lift) + " mm at " + fmt(s.deg) +
                     " cam deg: the table is noisy: its 4th differences scatter by " + fmt(median_fourth, 3) +
                     " mm (median) against a largest 2nd difference of " + fmt(largest_second, 3) + " mm (ratio " +
                     fmt(ratio, 3) + " > " + fmt(kNoiseRatio) + "), so an exact interpolant's acceleration follows "
                     "the noise (here a spike of about " + fmt(worst_fourth / h2, 3) + " mm/deg^2 against the "
                     "table's peak " + fmt(largest_second / h2, 3) + " mm/deg^2); smooth it (camopt synthesize "
                     "--smooth, least squares with the residual reported) or give a clean table");
  }
}

// the largest slope step of an interpolated table (TargetLift::slope_step_*)
void find_slope_step(const std::vector<Site>& data, TargetLift& out) {
  const std::size_t n = data.size();
  double steepest = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i)
    steepest = std::max(steepest, std::abs((data[i + 1].lift - data[i].lift) / (data[i + 1].deg - data[i].deg)));
  if (!(steepest > 0.0)) return;
  for (std::size_t i = 2; i + 3 < n; ++i) {
    const double h = data[i + 1].deg - data[i].deg;
    if (!equally_spaced(data, i - 2, i + 3)) continue;
    double l[6];  // rows i - 2 .. i + 3
    for (std::size_t k = 0; k < 6; ++k) l[k] = data[i - 2 + k].lift;
    const double left = (3 * l[2] - 4 * l[1] + l[0]) / (2 * h), right = (-3 * l[3] + 4 * l[4] - l[5]) / (2 * h);
    const double acc_left = (l[2] - 2 * l[1] + l[0]) / (h * h), acc_right = (l[5] - 2 * l[4] + l[3]) / (h * h);
    const double step = right - left - h * (acc_left + acc_right) / 2;
    if (std::abs(step) / steepest > out.slope_step_ratio) {
      out.slope_step_ratio = std::abs(step) / steepest;
      out.slope_step_mm_per_deg = step;
      out.slope_step_at_deg = data[i + 1].deg;
    }
  }
}

}  // namespace

double PeriodicBSpline::derivative(double cam_deg, int k) const {
  CAMOPT_THROW_UNLESS(k >= 0 && k <= kDegree,
                      "PeriodicBSpline::derivative: order k = " + std::to_string(k) + " must be in 0 .. 5");
  const int m = static_cast<int>(coef.size());
  CAMOPT_THROW_UNLESS(m >= kDegree + 1 && spacing_deg > 0,
                      "PeriodicBSpline: " + std::to_string(m) + " coefficients at spacing_deg = " +
                          format_value(spacing_deg) + " must be >= 6 at a spacing > 0 (a fitted spline)");
  // derivative of a uniform b-spline series: differences of the coefficients over the
  // spacing, one degree lower (de Boor, ch. X)
  std::vector<double> c = coef;
  for (int d = 0; d < k; ++d) {
    const double last = c[static_cast<std::size_t>(m - 1)];
    for (int i = m - 1; i >= 1; --i) c[static_cast<std::size_t>(i)] = (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(i - 1)]) / spacing_deg;
    c[0] = (c[0] - last) / spacing_deg;
  }
  const int degree = kDegree - k;
  const double t = wrap360(cam_deg) / spacing_deg;
  int j = static_cast<int>(std::floor(t));
  double u = t - j;
  if (j >= m) {  // wrap360 rounding up to 360
    j -= m;
  }
  double b[kDegree + 1];
  uniform_basis(u, degree, b);
  double s = 0.0;
  for (int r = 0; r <= degree; ++r) s += c[static_cast<std::size_t>(((j - degree + r) % m + m) % m)] * b[r];
  return s;
}

Status fit_periodic_bspline(std::span<const double> cam_deg, std::span<const double> lift_mm,
                            double knot_spacing_deg, PeriodicBSpline& fit, const std::string& source) {
  CAMOPT_THROW_UNLESS(cam_deg.size() == lift_mm.size(),
                      "fit_periodic_bspline: lift_mm has " + std::to_string(lift_mm.size()) +
                          " values, must have as many as cam_deg (" + std::to_string(cam_deg.size()) + ")");
  if (!std::isfinite(knot_spacing_deg) || knot_spacing_deg <= 0 || knot_spacing_deg > kCycleDeg / (kDegree + 1)) {
    throw InputError(where(source, 0) + ": smoothing knot spacing " + fmt(knot_spacing_deg) +
                     " cam deg: must be > 0 and <= 60 cam deg (at least 6 knots per cycle)");
  }
  const int m = std::max(kDegree + 1, static_cast<int>(std::lround(kCycleDeg / knot_spacing_deg)));
  fit = {};
  fit.spacing_deg = kCycleDeg / m;

  // normal equations a^t a c = a^t y; row i of a holds the 6 basis values at site i
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  std::vector<int> per_interval(static_cast<std::size_t>(m), 0);
  double b[kDegree + 1];
  for (std::size_t i = 0; i < cam_deg.size(); ++i) {
    const double t = wrap360(cam_deg[i]) / fit.spacing_deg;
    int j = static_cast<int>(std::floor(t));
    const double u = t - j;
    if (j >= m) j -= m;
    ++per_interval[static_cast<std::size_t>(j)];
    uniform_basis(u, kDegree, b);
    int idx[kDegree + 1];
    for (int r = 0; r <= kDegree; ++r) idx[r] = ((j - kDegree + r) % m + m) % m;
    for (int r = 0; r <= kDegree; ++r) {
      rhs[idx[r]] += b[r] * lift_mm[i];
      for (int q = 0; q <= kDegree; ++q) normal(idx[r], idx[q]) += b[r] * b[q];
    }
  }
  // one site in every knot interval makes the fit well posed (schoenberg-whitney)
  for (int j = 0; j < m; ++j) {
    if (per_interval[static_cast<std::size_t>(j)] == 0) {
      throw InputError(where(source, 0) + ": smoothing knot spacing " + fmt(fit.spacing_deg) +
                       " cam deg: no data between " + fmt(j * fit.spacing_deg) + " and " +
                       fmt((j + 1) * fit.spacing_deg) +
                       " cam deg; every knot interval needs a data point (use a larger knot spacing)");
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(normal);
  if (llt.info() != Eigen::Success)
    return {StatusCode::singular, "least-squares smoothing: normal equations not positive definite", source};
  const Eigen::VectorXd c = llt.solve(rhs);
  fit.coef.assign(c.data(), c.data() + m);
  return Status::success();
}

double TargetLift::lift_at(double cam_deg) const { return lift(cam_deg * rad_per_deg); }

namespace {

// the rows as sites: lift >= 0 (rounding negatives clamped to 0 when interpolating, noise
// kept when smoothing) and <= kMaxLift
std::vector<Site> sites_from_rows(std::span<const double> cam_deg, std::span<const double> lift_mm,
                                  const TargetLiftOptions& options, const RowRef& at_row) {
  const double tol = options.closure_tolerance_mm;
  const double negative_limit = options.smooth ? std::max(kRoundingNegative, tol) : kRoundingNegative;
  std::vector<Site> data;
  data.reserve(cam_deg.size());
  for (std::size_t i = 0; i < cam_deg.size(); ++i) {
    double y = lift_mm[i];
    if (y < -negative_limit) {
      throw InputError(at_row(i) + ": lift " + fmt(y) + " mm at " + fmt(cam_deg[i]) +
                       " cam deg: lift must be >= 0 (base circle)" +
                       (options.smooth ? " (smoothing keeps noise down to -" + fmt(negative_limit) + " mm)" : ""));
    }
    if (!(y <= kMaxLift)) {  // also keeps the spline arithmetic far from overflow
      throw InputError(at_row(i) + ": lift " + fmt(y) + " mm at " + fmt(cam_deg[i]) + " cam deg: lift must be <= " +
                       fmt(kMaxLift) + " mm (check the unit and the column)");
    }
    if (y < 0 && !options.smooth) y = 0.0;
    data.push_back({cam_deg[i], y, static_cast<int>(i)});
  }
  return data;
}

// the arguments of fit_target_lift, one rule per check: sizes, finite values, ascending
// angles at least min_spacing_deg apart (InputError naming the field, the value and the rule)
void check_rows(std::span<const double> cam_deg, std::span<const double> lift_mm, const std::vector<int>& lines,
                const TargetLiftOptions& options, const RowRef& at_row) {
  const std::string& file = options.source;
  const std::size_t n_in = cam_deg.size();
  CAMOPT_THROW_UNLESS(lift_mm.size() == n_in, "fit_target_lift: lift_mm has " + std::to_string(lift_mm.size()) +
                                                  " rows, must have as many as cam_deg (" + std::to_string(n_in) + ")");
  CAMOPT_THROW_UNLESS(lines.empty() || lines.size() == n_in,
                      "fit_target_lift: lines has " + std::to_string(lines.size()) +
                          " entries, must be empty or one per row (" + std::to_string(n_in) + ")");
  if (n_in < 2) {
    throw InputError(where(file, 0) + ": a target lift table needs at least 2 rows (has " + std::to_string(n_in) + ")");
  }
  for (std::size_t i = 0; i < n_in; ++i) {
    CAMOPT_THROW_UNLESS(std::isfinite(cam_deg[i]) && std::isfinite(lift_mm[i]),
                        at_row(i) + ": angle " + format_value(cam_deg[i]) + " cam deg and lift " +
                            format_value(lift_mm[i]) + " mm must both be finite");
    if (i > 0)
      CAMOPT_THROW_UNLESS(cam_deg[i] > cam_deg[i - 1], at_row(i) + ": angle " + format_value(cam_deg[i]) +
                                                           " cam deg must be above the previous row's " +
                                                           format_value(cam_deg[i - 1]) + " (strictly increasing)");
  }
  // rows closer than this make the interpolating spline's collocation system singular (no
  // lift table is measured that finely) [cam deg]
  constexpr double min_spacing_deg = 1e-6;
  for (std::size_t i = 1; i < n_in; ++i)
    if (cam_deg[i] - cam_deg[i - 1] < min_spacing_deg)
      throw InputError(at_row(i) + ": angle " + fmt(cam_deg[i]) + " cam deg is only " +
                       fmt(cam_deg[i] - cam_deg[i - 1]) + " deg after the previous row's " + fmt(cam_deg[i - 1]) +
                       ": the angles are too close together for a lift table (rows must be at least " +
                       fmt(min_spacing_deg) + " deg apart: merge them)");
}

// a cam's lift is measured from its base circle: the table must come down to it
void check_reaches_base_circle(const std::vector<Site>& data, double tol, const RowRef& at_row) {
  const auto lowest = std::min_element(data.begin(), data.end(), [](const Site& a, const Site& b) { return a.lift < b.lift; });
  if (lowest->lift > tol)
    throw InputError(at_row(static_cast<std::size_t>(lowest->row)) + ": the lift never comes down to the base circle: its " +
                     "smallest value is " + fmt(lowest->lift) + " mm (at " + fmt(lowest->deg) + " cam deg), above the " +
                     "closure tolerance " + fmt(tol) + " mm; a target is measured from the base circle (zero lift), so " +
                     "subtract the offset (a lash or another datum) from every row");
}

// at most one cycle; exactly one cycle repeats the first site at the end: with
// interpolation the last row is dropped, with smoothing both are kept. true when the table
// spans the full cycle; message: what was done
bool close_seam(std::vector<Site>& data, const TargetLiftOptions& options, const RowRef& at_row, std::string& message) {
  const std::string& file = options.source;
  const double tol = options.closure_tolerance_mm;
  const double first = data.front().deg;
  const double span = data.back().deg - first;
  if (span > kCycleDeg * (1 + kSpanRelTol)) {
    throw InputError(where(file, 0) + ": the table spans " + fmt(span) + " cam deg (" + fmt(first) + " .. " +
                     fmt(data.back().deg) +
                     "), more than one cycle (360 cam deg); give at most one cycle (crank-angle tables: 720 crank deg)");
  }
  if (!(span >= kCycleDeg * (1 - kSpanRelTol))) return false;
  const Site& last = data.back();
  const double step = std::abs(last.lift - data.front().lift);
  if (!options.smooth) {
    if (step > tol) {
      throw InputError(at_row(static_cast<std::size_t>(last.row)) + ": the table spans one full cycle (" + fmt(first) +
                       " .. " + fmt(last.deg) + " cam deg) but its last row (" + fmt(last.deg) + " cam deg, " +
                       fmt(last.lift) + " mm) does not repeat its first (" + fmt(first) + " cam deg, " +
                       fmt(data.front().lift) + " mm): a step of " + fmt(step, 3) +
                       " mm at the seam, more than the closure tolerance " + fmt(tol) +
                       " mm; make the last lift equal the first, drop the last row, or smooth the table");
    }
    message = "table covers the full cycle (" + fmt(first) + " .. " + fmt(last.deg) + " cam deg); the last row repeats the first angle and was dropped";
    if (step > 0) message += " (its lift differs by " + fmt(step, 3) + " mm; the first row's " + fmt(data.front().lift) + " mm is kept)";
    data.pop_back();
  } else {
    message = "table covers the full cycle (" + fmt(first) + " .. " + fmt(last.deg) +
              " cam deg); the first and last rows are the same angle and both enter the fit";
  }
  return true;
}

// the median spacing of the table [cam deg] (the fill spacing)
double median_spacing(const std::vector<Site>& data) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < data.size(); ++i) gaps.push_back(data[i].deg - data[i - 1].deg);
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  return gaps[gaps.size() / 2];
}

// zero-lift points at about spacing h strictly inside (a, b) appended to sites
void fill_zero_lift(double a, double b, double h, const std::string& file, std::vector<Site>& sites) {
  constexpr double kMaxFillPoints = 1e5;  // far above any real table (0.01 deg over a 360 deg gap: 3.6e4)
  const double count = std::ceil((b - a) / h - 1e-9);
  if (!(count <= kMaxFillPoints))
    throw InputError(where(file, 0) + ": the gap " + fmt(a) + " .. " + fmt(b) +
                     " cam deg would be filled with zero lift at the table's median spacing " + fmt(h) +
                     " deg, i.e. " + fmt(count) + " points (more than " + fmt(kMaxFillPoints) +
                     "); the angles are too close together for a lift table: check the angle column");
  const int k = std::max(1, static_cast<int>(count));
  for (int j = 1; j < k; ++j) sites.push_back({a + (b - a) * j / k, 0.0, -1});
}

// the sites of the spline: the data, with interior gaps on the base circle filled with zero
// lift and the cycle closed on the base circle over the wrap-around interval when the table
// does not cover it. closed: it was; message: what was added
std::vector<Site> close_cycle(const std::vector<Site>& data, bool repeated_seam, const TargetLiftOptions& options,
                              const RowRef& at_row, bool& closed, std::string& message) {
  const std::string& file = options.source;
  const double tol = options.closure_tolerance_mm;
  const double h = median_spacing(data);
  const auto on_base_circle = [&](const Site& s) { return s.lift <= tol; };
  std::vector<Site> sites;
  sites.reserve(data.size() * 2);
  std::string interior_msg;
  for (std::size_t i = 0; i < data.size(); ++i) {
    sites.push_back(data[i]);
    if (i + 1 == data.size()) break;
    const Site& a = data[i];
    const Site& b = data[i + 1];
    if (b.deg - a.deg <= kInteriorGapFactor * h) continue;
    if (!on_base_circle(a) || !on_base_circle(b)) {
      const Site& off = on_base_circle(a) ? b : a;
      throw InputError(at_row(static_cast<std::size_t>(off.row)) + ": the table has a gap from " + fmt(a.deg) + " to " +
                       fmt(b.deg) + " cam deg (" + fmt(b.deg - a.deg) + " deg, more than " + fmt(kInteriorGapFactor) +
                       " times its median spacing " + fmt(h) + " deg) with lift " + fmt(off.lift) + " mm at " +
                       fmt(off.deg) + " cam deg: a gap may only span the base circle (lift <= " + fmt(tol) +
                       " mm at both ends); fill in the rows");
    }
    fill_zero_lift(a.deg, b.deg, h, file, sites);
    interior_msg += (interior_msg.empty() ? "" : ", ") + fmt(a.deg) + " .. " + fmt(b.deg);
  }
  // closure over the wrap-around interval
  const double first = data.front().deg;
  const double last_deg = data.back().deg;
  const double wrap = first + kCycleDeg - last_deg;
  closed = false;
  if (!repeated_seam && wrap > kWrapGapFactor * h) {
    const Site& s0 = data.front();
    const Site& s1 = data.back();
    for (const Site* end : {&s0, &s1}) {
      if (on_base_circle(*end)) continue;
      throw InputError(at_row(static_cast<std::size_t>(end->row)) + ": the table covers " + fmt(last_deg - first) +
                       " cam deg (" + fmt(first) + " .. " + fmt(last_deg) + ") and " +
                       (end == &s0 ? "starts" : "ends") + " at " + fmt(end->deg) + " cam deg with lift " +
                       fmt(end->lift) + " mm: a table that does not cover the cycle must end on the base circle (lift <= " +
                       fmt(tol) + " mm); give the full cycle or a table that returns to zero lift");
    }
    fill_zero_lift(last_deg, first + kCycleDeg, h, file, sites);
    closed = true;
    message = "table covers " + fmt(last_deg - first) + " deg (" + fmt(first) + " .. " + fmt(last_deg) +
              " cam deg); closed on the base circle (zero lift) over the remaining " + fmt(wrap) + " deg";
    message += " (end lifts " + fmt(s0.lift) + " mm at " + fmt(first) + " and " + fmt(s1.lift) + " mm at " +
               fmt(last_deg) + " cam deg stepped to zero)";
  } else if (message.empty()) {
    message = "table covers the full cycle (" + fmt(first) + " .. " + fmt(last_deg) + " cam deg, the last " + fmt(wrap) +
              " deg close the cycle)";
  }
  if (!interior_msg.empty()) {
    message += "; gaps on the base circle filled with zero lift: " + interior_msg + " cam deg";
  }
  if (static_cast<int>(sites.size()) < kDegree + 1) {
    throw InputError(where(file, 0) + ": a target lift table needs at least 6 points per cycle (has " +
                     std::to_string(sites.size()) + ")");
  }
  return sites;
}

// exact interpolation, knots at the sites
void interpolate_sites(const std::vector<Site>& sites, TargetLift& out) {
  std::vector<double> x, y;
  x.reserve(sites.size());
  y.reserve(sites.size());
  for (const Site& s : sites) {
    x.push_back(s.deg * rad_per_deg);
    y.push_back(s.lift);
  }
  out.lift = PeriodicSpline::interpolate(x, y, 2 * pi);
}

// least-squares smoothing of the sites, converted to the periodic spline on a grid that
// refines the knots (the fitted spline lies in the interpolant's space), with the residual
// against the rows of the table
Status smooth_sites(const std::vector<Site>& sites, std::span<const double> cam_deg, std::span<const double> lift_mm,
                    const TargetLiftOptions& options, TargetLift& out) {
  std::vector<double> sd, sy;
  for (const Site& s : sites) {
    sd.push_back(s.deg);
    sy.push_back(s.lift);
  }
  PeriodicBSpline fit;
  if (Status st = fit_periodic_bspline(sd, sy, options.smoothing_knot_spacing_deg, fit, options.source); !st.ok())
    return st;
  const int per_knot = static_cast<int>(std::ceil(fit.spacing_deg / kFineGridDeg - 1e-9));
  const int count = static_cast<int>(fit.coef.size()) * per_knot;
  const double step = fit.spacing_deg / per_knot;
  std::vector<double> x(static_cast<std::size_t>(count)), y(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    x[static_cast<std::size_t>(i)] = i * step * rad_per_deg;
    y[static_cast<std::size_t>(i)] = fit(i * step);
  }
  out.lift = PeriodicSpline::interpolate(x, y, 2 * pi);
  // residual against the rows of the table
  const std::size_t n_in = cam_deg.size();
  double sum2 = 0.0;
  for (std::size_t i = 0; i < n_in; ++i) {
    const double r = out.lift_at(cam_deg[i]) - lift_mm[i];
    sum2 += r * r;
    if (std::abs(r) > out.residual_max_mm) {
      out.residual_max_mm = std::abs(r);
      out.residual_max_at_deg = cam_deg[i];
    }
  }
  out.residual_rms_mm = std::sqrt(sum2 / static_cast<double>(n_in));
  return Status::success();
}

// peak lift: best breakpoint or piece midpoint, refined by newton on f' = 0; its angle in
// the table's range first .. first + 360 [cam deg]
void find_peak(double first, TargetLift& out) {
  const auto knots = out.lift.knots();
  double best_x = knots[0], best_f = -1e300;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const double next = i + 1 < knots.size() ? knots[i + 1] : knots[0] + 2 * pi;
    for (int q = 0; q < 4; ++q) {
      const double xq = knots[i] + (next - knots[i]) * q / 4.0;
      const double f = out.lift(xq);
      if (f > best_f) {
        best_f = f;
        best_x = xq;
      }
    }
  }
  double d[3];
  double xn = best_x;
  for (int it = 0; it < 20; ++it) {
    out.lift.evaluate(xn, 2, d);
    if (!(d[2] < 0)) break;
    const double dx = -d[1] / d[2];
    if (std::abs(dx) > 0.5 * rad_per_deg) break;  // stay near the sampled peak
    xn += dx;
    if (std::abs(dx) < 1e-14) break;
  }
  if (out.lift(xn) >= best_f) best_x = xn;
  out.max_lift_mm = out.lift(best_x);
  double at = best_x / rad_per_deg;
  at = first + wrap360(at - first);
  out.max_lift_at_deg = at;
}

}  // namespace

void TargetLiftOptions::validate() const {
  CAMOPT_THROW_UNLESS(std::isfinite(closure_tolerance_mm) && closure_tolerance_mm >= 0,
                      where(source, 0) + ": target lift option closure_tolerance_mm = " +
                          format_value(closure_tolerance_mm) + " mm must be finite and >= 0");
  CAMOPT_THROW_UNLESS(!smooth || (std::isfinite(smoothing_knot_spacing_deg) && smoothing_knot_spacing_deg > 0 &&
                                  smoothing_knot_spacing_deg <= kCycleDeg / (kDegree + 1)),
                      where(source, 0) + ": target lift option smoothing_knot_spacing_deg = " +
                          format_value(smoothing_knot_spacing_deg) +
                          " cam deg must be > 0 and <= 60 cam deg when smoothing (at least 6 knots per cycle)");
}

Status fit_target_lift(std::span<const double> cam_deg, std::span<const double> lift_mm, const std::vector<int>& lines,
                       const TargetLiftOptions& options, TargetLift& out) {
  const RowRef at_row{options.source, lines};
  // the options and the rows, one rule per check
  options.validate();
  check_rows(cam_deg, lift_mm, lines, options, at_row);
  // the rows as sites, lift >= 0, coming down to the base circle
  std::vector<Site> data = sites_from_rows(cam_deg, lift_mm, options, at_row);
  check_reaches_base_circle(data, options.closure_tolerance_mm, at_row);
  // at most one cycle: a repeated seam dropped (interpolation) or kept (smoothing)
  const double first = data.front().deg;
  std::string message;
  const bool repeated_seam = close_seam(data, options, at_row, message);
  if (data.size() < 2) {
    throw InputError(where(options.source, 0) + ": a target lift table needs at least 2 distinct angles");
  }
  // gaps on the base circle filled, the cycle closed on the base circle
  bool closed = false;
  const std::vector<Site> sites = close_cycle(data, repeated_seam, options, at_row, closed, message);
  // after the gap and closure rules, so a table with both hears about its ends first
  if (!options.smooth) check_steps_and_noise(data, at_row);
  out = {};
  out.closed_on_base_circle = closed;
  out.closure_message = message;
  if (!options.smooth) find_slope_step(data, out);
  // the periodic spline: interpolated at the sites, or least-squares smoothed
  if (!options.smooth) {
    interpolate_sites(sites, out);
  } else if (Status st = smooth_sites(sites, cam_deg, lift_mm, options, out); !st.ok()) {
    return st;
  }
  // the peak and its angle
  find_peak(first, out);
  return Status::success();
}

TargetLift fit_target_lift(std::span<const double> cam_deg, std::span<const double> lift_mm,
                           const std::vector<int>& lines, const TargetLiftOptions& options) {
  TargetLift out;
  if (Status st = fit_target_lift(cam_deg, lift_mm, lines, options, out); !st.ok()) throw NumericalError(st);
  return out;
}

}  // namespace camopt::synthesis
