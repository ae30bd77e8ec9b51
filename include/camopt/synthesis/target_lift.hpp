#pragma once
// target valve lift for `camopt synthesize`: a lift table against cam angle turned into a
// periodic quintic (c4) spline, with closure on the base circle and optional smoothing.
// core module: no file i/o (the cli reads the csv with io::read_angle_table and converts
// crank to cam degrees before calling).
//
// rules
// - angles strictly increasing (the caller checks), any range, at most one cycle: a table
//   spanning more than 360 cam deg is an InputError. a table spanning exactly 360 deg
//   repeats its first site at the end: with interpolation the last row is dropped (its
//   lift must equal the first row's within closure_tolerance_mm, else InputError naming
//   the step at the seam); with smoothing both rows are kept as measurements.
// - lift must be >= 0 (base circle). interpolation: values in [-1e-3, 0) mm are rounding
//   and are clamped to 0, anything lower is an InputError naming the line. smoothing:
//   measured tables scatter around zero on the base circle, so values down to
//   -max(1e-9, closure_tolerance_mm) are kept as measured; lower ones are rejected.
// - clean tables (smooth = false) are interpolated exactly: knots at the data sites.
// - closure: a table whose wrap-around interval (last row to first row + 360 deg) is
//   longer than 1.5 times its median spacing does not cover the cycle; it is closed on
//   the base circle by zero-lift points at (about) the median spacing across the gap.
//   both ends must then be on the base circle (lift <= closure_tolerance_mm), otherwise
//   closing would leave a step: InputError naming the end, its lift and the rule.
//   an interior interval longer than 4 median spacings is a gap: when both its ends are
//   on the base circle it is filled with zero lift the same way (e.g. a table that lists
//   only the two base-circle points of a long dwell), otherwise InputError.
// - smoothing (smooth = true): least-squares periodic quintic b-spline on uniform knots
//   (spacing 360 / round(360 / smoothing_knot_spacing_deg)), normal equations with a
//   cholesky factorisation (de Boor, "A Practical Guide to Splines", rev. ed., ch. XIV).
//   it is then interpolated by PeriodicSpline on a uniform grid that refines the knots
//   (step <= 0.5 deg, every knot a grid point): the fitted spline lies in the space of
//   the interpolant, so the conversion reproduces it to rounding (tested to 1e-6 mm).
//   zero-lift closure points take part in the fit but not in the reported residual.
#include <span>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/spline.hpp"

namespace camopt::synthesis {

struct TargetLiftOptions {
  bool smooth = false;                      // measured/noisy tables: least-squares smoothing instead of interpolation
  double smoothing_knot_spacing_deg = 4.0;  // [cam deg] knot spacing of the smoothing spline
  double closure_tolerance_mm = 0.05;       // [mm] largest lift at the table ends that may be closed on the base circle
  std::string source = "";                  // file name for messages

  // throws InputError naming the field, its value and the rule it breaks (one rule per check)
  void validate() const;
};

struct TargetLift {
  PeriodicSpline lift;  // lift [mm] against cam angle [rad], period 2*pi, c4 (quintic)
  bool closed_on_base_circle = false;
  std::string closure_message;  // what was added or dropped to close the cycle
  // fit residual against the data [mm], angle as written [cam deg] (0 when interpolating)
  double residual_rms_mm = 0, residual_max_mm = 0, residual_max_at_deg = 0;
  // peak of the spline [mm] and its angle [cam deg, in the table's range first .. first + 360)
  double max_lift_mm = 0, max_lift_at_deg = 0;
  // the table's largest slope step (an interpolated table): across one interval, the
  // slopes at its ends from the two intervals beyond each end, less what the acceleration on
  // both sides explains [mm/deg], relative to the table's steepest slope, and the interval's
  // end [cam deg as written]. A lift computed with lash steps where the lash is taken up
  // (the bundled Valvetronic's: 0.33), which no cam can give; a smooth table leaves ~1e-3
  double slope_step_mm_per_deg = 0, slope_step_ratio = 0, slope_step_at_deg = 0;

  double lift_at(double cam_deg) const;  // [mm] at [cam deg]
};

// cam_deg, lift_mm and lines (file line of each row; may be empty) have one entry per row.
// InputError for bad options (TargetLiftOptions::validate) or a table that breaks a rule
// above; a Status when the smoothing's least-squares fit is singular (out then undefined)
[[nodiscard]] Status fit_target_lift(std::span<const double> cam_deg, std::span<const double> lift_mm,
                                     const std::vector<int>& lines, const TargetLiftOptions& options, TargetLift& out);

// the same, returning the fit; a failed Status is thrown as NumericalError (the form the
// CLI uses, where NumericalError maps to its exit code)
TargetLift fit_target_lift(std::span<const double> cam_deg, std::span<const double> lift_mm,
                           const std::vector<int>& lines, const TargetLiftOptions& options);

// the least-squares periodic quintic b-spline behind smoothing (exposed for tests):
// f(theta) = sum_j coef[j] N5((theta - j * spacing) / spacing), period 360 deg, where N5
// is the uniform cardinal b-spline of degree 5 on [0, 6].
struct PeriodicBSpline {
  double spacing_deg = 0.0;   // [cam deg], 360 / coef.size()
  std::vector<double> coef;   // [mm]

  // d^k f / dtheta^k at theta [cam deg] for k = 0..5, in [mm / deg^k]; InputError for
  // another k or an unfitted spline
  double derivative(double cam_deg, int k) const;
  double operator()(double cam_deg) const { return derivative(cam_deg, 0); }
};

// fit to (cam_deg, lift_mm) at any angles (wrapped modulo 360; repeats allowed) with knot
// spacing 360 / round(360 / knot_spacing_deg) (at least 6 knots). throws InputError when
// the knot spacing is not in (0, 60] or a knot interval holds no site (the fit would be
// singular there); a singular Status when the normal equations are not positive definite.
[[nodiscard]] Status fit_periodic_bspline(std::span<const double> cam_deg, std::span<const double> lift_mm,
                                          double knot_spacing_deg, PeriodicBSpline& fit,
                                          const std::string& source = "");

}  // namespace camopt::synthesis
