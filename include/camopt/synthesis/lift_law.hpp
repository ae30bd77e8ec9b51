#pragma once
// lift laws: the classic dwell-rise-dwell cam motions, one class per law, each giving its
// value and three derivatives in closed form (the style of chrono's ChFunction*,
// e.g. ChFunctionCycloidal). a law is a rise of height h [mm] over a duration beta
// [cam deg]:
//   s(theta) = h y(x),  s^(k)(theta) = h / beta^k y^(k)(x),  x = theta / beta in [0, 1]
// where y is the law's normalized unit rise, y(0) = 0, y(1) = 1, y'(0) = y'(1) = 0 and
// y''(0) = y''(1) = 0 for every law here. full events (ramps, dwell, asymmetric fall) are
// assembled from rises in lift_law_event.hpp. formulas and sources: docs/lift-laws.md.
//
// references
//   [norton]   R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed., Industrial
//              Press, 2009: double-dwell cam functions (cycloidal, modified trapezoid,
//              modified sine, 3-4-5 and 4-5-6-7 polynomials) and their peak coefficients;
//              polynomial and polydyne cams.
//   [rothbart] H. A. Rothbart (ed.), Cam Design Handbook, McGraw-Hill, 2004: basic curves
//              and polynomial cam functions.
//   [dudley]   W. M. Dudley, "New methods in valve cam design", SAE Quarterly Transactions
//              2 (1948) 19-33: the polydyne cam, cam lift = valve lift + (m/k) valve accel.
//   [deboor]   C. de Boor, A Practical Guide to Splines, rev. ed., Springer, 2001, ch. IX-X
//              (b-spline evaluation, derivative and integral of a b-spline).
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace camopt::synthesis {

// lift and its first three derivatives with respect to cam angle: for a rise or an event
// [mm], [mm/deg], [mm/deg^2], [mm/deg^3]; for a normalized unit rise, dimensionless per
// unit of x = theta / beta.
struct Motion {
  double lift = 0.0;
  double vel = 0.0;
  double acc = 0.0;
  double jerk = 0.0;

  // d^k lift / dtheta^k for k = 0..3
  constexpr double operator[](int k) const noexcept {
    switch (k) {
      case 0:
        return lift;
      case 1:
        return vel;
      case 2:
        return acc;
      default:
        return jerk;
    }
  }
};

enum class LawKind {
  polynomial_345,
  polynomial_4567,
  cycloidal,
  modified_trapezoid,
  modified_sine,
  polydyne,
  bspline,
};

inline constexpr std::array<LawKind, 7> kAllLaws = {
    LawKind::polynomial_345, LawKind::polynomial_4567, LawKind::cycloidal, LawKind::modified_trapezoid,
    LawKind::modified_sine,  LawKind::polydyne,        LawKind::bspline};

// "polynomial-345", "polynomial-4567", "cycloidal", "modified-trapezoid", "modified-sine",
// "polydyne", "bspline"
const char* to_string(LawKind law);
// the names of every law, comma separated (for help texts and messages)
std::string law_names();
// the law named `name`; InputError "`what`: unknown law 'name' (allowed: ...)" otherwise
LawKind parse_law(std::string_view name, std::string_view what);

// a rise of height h [mm] over beta [cam deg] starting at theta = 0: 0 before it, h after
// it (dwell-rise-dwell). immutable; evaluation never allocates.
class RiseLaw {
 public:
  // InputError when height_mm or duration_deg is not finite and positive
  RiseLaw(double height_mm, double duration_deg);
  virtual ~RiseLaw() = default;

  double height_mm() const noexcept { return h_; }
  double duration_deg() const noexcept { return beta_; }
  virtual LawKind kind() const noexcept = 0;

  // the normalized unit rise y(x), y', y'', y''' [1]: the closed form on [0, 1] (so the
  // ends give the limits from inside the rise), y = 0 before and 1 after with zero rates
  Motion unit(double x) const noexcept;
  // lift [mm] and its derivatives per cam degree at theta = angle_deg [cam deg] from the
  // start of the rise
  Motion evaluate(double angle_deg) const noexcept;

  // the highest derivative order k (1..3) such that y^(1..k) all vanish at both ends: 2
  // means velocity and acceleration are zero there and jerk is not, so joining a dwell is
  // c2 with a finite jerk step
  virtual int zero_order_at_ends() const noexcept = 0;
  // interior angles x in (0, 1) where the law switches segment (y''' may have a corner)
  virtual std::vector<double> breakpoints() const { return {}; }

 protected:
  RiseLaw(const RiseLaw&) = default;
  RiseLaw& operator=(const RiseLaw&) = default;

  // the unit rise for x in [0, 1]
  virtual Motion unit_inside(double x) const noexcept = 0;

 private:
  double h_ = 0.0;     // [mm]
  double beta_ = 0.0;  // [cam deg]
};

// 3-4-5 polynomial: y = 10 x^3 - 15 x^4 + 6 x^5 [norton]. peak |y''| = 10 sqrt(3)/3.
class Polynomial345 final : public RiseLaw {
 public:
  using RiseLaw::RiseLaw;
  LawKind kind() const noexcept override { return LawKind::polynomial_345; }
  int zero_order_at_ends() const noexcept override { return 2; }

 private:
  Motion unit_inside(double x) const noexcept override;
};

// 4-5-6-7 polynomial: y = 35 x^4 - 84 x^5 + 70 x^6 - 20 x^7 [norton]; zero jerk at the ends.
class Polynomial4567 final : public RiseLaw {
 public:
  using RiseLaw::RiseLaw;
  LawKind kind() const noexcept override { return LawKind::polynomial_4567; }
  int zero_order_at_ends() const noexcept override { return 3; }

 private:
  Motion unit_inside(double x) const noexcept override;
};

// cycloidal: y = x - sin(2 pi x) / (2 pi) [norton]. peak |y''| = 2 pi.
class Cycloidal final : public RiseLaw {
 public:
  using RiseLaw::RiseLaw;
  LawKind kind() const noexcept override { return LawKind::cycloidal; }
  int zero_order_at_ends() const noexcept override { return 2; }

 private:
  Motion unit_inside(double x) const noexcept override;
};

// modified trapezoid [norton]: y'' is a quarter sine over x in [0, 1/8], constant over
// [1/8, 3/8], a half cosine over [3/8, 5/8], constant over [5/8, 7/8] and a quarter sine
// back to zero over [7/8, 1]; peak |y''| = 8 pi / (2 + pi) = 4.8881.
class ModifiedTrapezoid final : public RiseLaw {
 public:
  using RiseLaw::RiseLaw;
  static double peak_acceleration_coefficient() noexcept;
  LawKind kind() const noexcept override { return LawKind::modified_trapezoid; }
  int zero_order_at_ends() const noexcept override { return 2; }
  std::vector<double> breakpoints() const override { return {0.125, 0.375, 0.625, 0.875}; }

 private:
  Motion unit_inside(double x) const noexcept override;
};

// modified sine [norton]: y'' is a quarter sine of period 1/2 over [0, 1/8], a half cosine
// of period 3/2 over [1/8, 7/8] and a quarter sine back to zero over [7/8, 1];
// peak |y''| = 4 pi^2 / (4 + pi) = 5.5280.
class ModifiedSine final : public RiseLaw {
 public:
  using RiseLaw::RiseLaw;
  static double peak_acceleration_coefficient() noexcept;
  LawKind kind() const noexcept override { return LawKind::modified_sine; }
  int zero_order_at_ends() const noexcept override { return 2; }
  std::vector<double> breakpoints() const override { return {0.125, 0.875}; }

 private:
  Motion unit_inside(double x) const noexcept override;
};

// polydyne [dudley, norton]: the cam lift that makes a single-mass valvetrain (cam ->
// stiffness k -> mass m) follow the valve motion p(x) exactly at one design speed:
//   y = p + K p'',   K = (omega_cam / (omega_n beta))^2   [1]
// with omega_cam the cam speed [rad/s], omega_n = sqrt(k/m) [rad/s] and beta [rad]. p is
// the 5-6-7-8-9 polynomial p = 126 x^5 - 420 x^6 + 540 x^7 - 315 x^8 + 70 x^9, the
// lowest-degree polynomial with p' .. p'''' zero at both ends, so the cam keeps zero
// velocity and acceleration at the ends (y'' = p'' + K p'''' = 0). K = 0 gives p itself.
class Polydyne final : public RiseLaw {
 public:
  // InputError when dynamic_factor is not finite and >= 0
  Polydyne(double height_mm, double duration_deg, double dynamic_factor);
  // K for an engine speed [rpm, crankshaft], the valvetrain's natural frequency [Hz] and
  // the rise duration [cam deg]; crank_per_cam = 2 for a 4-stroke engine
  static double dynamic_factor(double engine_rpm, double natural_frequency_hz, double duration_deg,
                               double crank_per_cam = 2.0) noexcept;
  double dynamic_factor() const noexcept { return k_; }
  // the valve motion p(x) and its first three derivatives [1]
  Motion valve_motion(double x) const noexcept;
  LawKind kind() const noexcept override { return LawKind::polydyne; }
  int zero_order_at_ends() const noexcept override { return k_ == 0.0 ? 3 : 2; }

 private:
  Motion unit_inside(double x) const noexcept override;
  double k_ = 0.0;
};

// acceleration designed as a b-spline: y''(x) = sum_i c_i N_{i,p}(x) on uniform clamped
// knots over [0, 1] [deboor]; velocity and lift are its exact first and second integrals
// (b-splines of degree p+1 and p+2, de boor ch. X), jerk its exact derivative.
//
// closure: the given control values are a shape in any unit. they are changed by the
// smallest amount (least squares over the control values) that gives
//   c_0 = 0 and c_{n-1} = 0         (zero acceleration at both ends: c2 joins)
//   sum_i c_i int N_i = 0           (zero velocity at the end of the rise)
// and then scaled so that y(1) = 1. a shape whose closed form has no positive net rise
// (y(1) <= 0) is an InputError.
class BSplineAcceleration final : public RiseLaw {
 public:
  static constexpr int kMinDegree = 2;
  static constexpr int kMaxDegree = 5;

  // control_values: at least max(degree + 1, 4) finite values; degree in [2, 5].
  // InputError "acc_controls: ..." / "bspline_degree: ..." on bad input.
  BSplineAcceleration(double height_mm, double duration_deg, std::span<const double> control_values,
                      int degree = 3);

  int degree() const noexcept { return p_; }
  // the acceleration control values of the unit rise (after closure and scaling)
  const std::vector<double>& controls() const noexcept { return c_; }
  // the knots of the acceleration spline
  const std::vector<double>& knots() const noexcept { return t_; }
  // the scale applied after closure: controls() = scale * (closed values)
  double shape_scale() const noexcept { return scale_; }
  // rms of the closure change relative to the rms of the given values [1]
  double closure_change() const noexcept { return change_; }

  LawKind kind() const noexcept override { return LawKind::bspline; }
  int zero_order_at_ends() const noexcept override { return 2; }
  std::vector<double> breakpoints() const override;

 private:
  Motion unit_inside(double x) const noexcept override;

  int p_ = 3;
  std::vector<double> t_, c_;    // acceleration: degree p on t_
  std::vector<double> tv_, d_;   // velocity: degree p+1 on tv_ = [0, t_, 1]
  std::vector<double> ty_, e_;   // lift: degree p+2 on ty_ = [0, tv_, 1]
  std::vector<double> tj_, g_;   // jerk: degree p-1 on t_ without its end knots
  double scale_ = 1.0, change_ = 0.0;
};

// the value at x of the b-spline of degree p with knots t and coefficients c (de boor's
// algorithm; x outside [t_p, t_n] evaluates the end span). p <= 7.
double bspline_value(std::span<const double> t, std::span<const double> c, int p, double x) noexcept;

// uniform clamped knots on [a, b] for n coefficients of degree p (p+1 repeated end knots)
std::vector<double> clamped_uniform_knots(int n, int p, double a = 0.0, double b = 1.0);

// the integral from t_0 of a degree-p spline (knots t, coefficients c): a degree p+1
// spline on knots [t_0, t, t_end] with d_0 = 0, d_{i+1} = d_i + c_i (t_{i+p+1} - t_i)/(p+1)
// [deboor ch. X]
void bspline_integral(const std::vector<double>& t, const std::vector<double>& c, int p, std::vector<double>& t_out,
                      std::vector<double>& d_out);

// the derivative of a degree-p spline (p >= 1): degree p-1 on t without its end knots,
// g_i = p (c_{i+1} - c_i) / (t_{i+p+1} - t_{i+1}) [deboor ch. X]
void bspline_derivative(const std::vector<double>& t, const std::vector<double>& c, int p, std::vector<double>& t_out,
                        std::vector<double>& g_out);

}  // namespace camopt::synthesis
