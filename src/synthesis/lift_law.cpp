// closed-form lift laws: polynomials, cycloidal, modified trapezoid, modified sine,
// polydyne (sources in lift_law.hpp and docs/lift-laws.md).
#include "camopt/synthesis/lift_law.hpp"

#include <cmath>
#include <sstream>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"

namespace camopt::synthesis {

namespace {


std::string num(double v) { return format_value(v, 10); }

// p(x) and its first `orders` derivatives by horner sums; a[m] is the coefficient of x^m
template <std::size_t M>
void polynomial(const std::array<double, M>& a, double x, int orders, double* out) noexcept {
  for (int k = 0; k <= orders; ++k) {
    // d^k/dx^k sum a_m x^m = sum_{m>=k} a_m m!/(m-k)! x^(m-k)
    double s = 0.0;
    for (int m = static_cast<int>(M) - 1; m >= k; --m) {
      double f = 1.0;
      for (int i = 0; i < k; ++i) f *= m - i;
      s = s * x + a[static_cast<std::size_t>(m)] * f;
    }
    out[k] = s;
  }
}

template <std::size_t M>
Motion polynomial_motion(const std::array<double, M>& a, double x) noexcept {
  double d[4];
  polynomial(a, x, 3, d);
  return {d[0], d[1], d[2], d[3]};
}

// one segment of a trigonometric law: y'' = p + q sin(w u + phi), u = x - x0, starting with
// y = y0 and y' = v0. closed-form integrals:
//   y'   = v0 + p u - (q/w) (cos(w u + phi) - cos phi)
//   y    = y0 + v0 u + p u^2/2 - (q/w) ((sin(w u + phi) - sin phi)/w - u cos phi)
//   y''' = q w cos(w u + phi)
struct SineSegment {
  double x0 = 0.0, x1 = 0.0;
  double p = 0.0, q = 0.0, w = 1.0, phi = 0.0;
  double y0 = 0.0, v0 = 0.0;

  Motion at(double x) const noexcept {
    const double u = x - x0;
    const double sn = std::sin(w * u + phi), cs = std::cos(w * u + phi);
    const double s0 = std::sin(phi), c0 = std::cos(phi);
    Motion m;
    m.jerk = q * w * cs;
    m.acc = p + q * sn;
    m.vel = v0 + p * u - (q / w) * (cs - c0);
    m.lift = y0 + v0 * u + 0.5 * p * u * u - (q / w) * ((sn - s0) / w - u * c0);
    return m;
  }
};

// a law made of sine/constant acceleration segments: fills y0, v0 of each segment by
// integrating the previous ones exactly, then scales the acceleration so that y(1) = 1
template <std::size_t N>
struct SegmentedLaw {
  std::array<SineSegment, N> seg;
  double peak = 0.0;  // the scale, i.e. the peak |y''| for unit-amplitude shapes

  explicit SegmentedLaw(std::array<SineSegment, N> s) : seg(s) {
    double y = 0.0, v = 0.0;
    for (auto& g : seg) {
      g.y0 = y;
      g.v0 = v;
      const Motion end = g.at(g.x1);
      y = end.lift;
      v = end.vel;
    }
    const double scale = 1.0 / y;
    for (auto& g : seg) {
      g.p *= scale;
      g.q *= scale;
      g.y0 *= scale;
      g.v0 *= scale;
    }
    peak = scale;
  }

  Motion at(double x) const noexcept {
    std::size_t i = 0;
    while (i + 1 < N && x >= seg[i].x1) ++i;
    return seg[i].at(x);
  }
};

// modified trapezoid [norton]: unit-amplitude shape, scaled by the constructor
const SegmentedLaw<5>& modified_trapezoid() {
  static const SegmentedLaw<5> law({{
      {0.0, 0.125, 0.0, 1.0, 4.0 * pi, 0.0},               // quarter sine up
      {0.125, 0.375, 1.0, 0.0, 1.0, 0.0},                   // constant +
      {0.375, 0.625, 0.0, 1.0, 4.0 * pi, 0.5 * pi},       // half cosine + -> -
      {0.625, 0.875, -1.0, 0.0, 1.0, 0.0},                  // constant -
      {0.875, 1.0, 0.0, 1.0, 4.0 * pi, -0.5 * pi},        // quarter sine back to 0
  }});
  return law;
}

// modified sine [norton]
const SegmentedLaw<3>& modified_sine() {
  static const SegmentedLaw<3> law({{
      {0.0, 0.125, 0.0, 1.0, 4.0 * pi, 0.0},                    // quarter sine, period 1/2
      {0.125, 0.875, 0.0, 1.0, 4.0 * pi / 3.0, 0.5 * pi},      // half cosine, period 3/2
      {0.875, 1.0, 0.0, 1.0, 4.0 * pi, -0.5 * pi},             // quarter sine back to 0
  }});
  return law;
}

// 5-6-7-8-9 polynomial of the polydyne valve motion
constexpr std::array<double, 10> kPolydyneValve = {0, 0, 0, 0, 0, 126.0, -420.0, 540.0, -315.0, 70.0};

}  // namespace

const char* to_string(LawKind law) {
  switch (law) {
    case LawKind::polynomial_345:
      return "polynomial-345";
    case LawKind::polynomial_4567:
      return "polynomial-4567";
    case LawKind::cycloidal:
      return "cycloidal";
    case LawKind::modified_trapezoid:
      return "modified-trapezoid";
    case LawKind::modified_sine:
      return "modified-sine";
    case LawKind::polydyne:
      return "polydyne";
    case LawKind::bspline:
      return "bspline";
  }
  return "?";
}

std::string law_names() {
  std::string s;
  for (LawKind k : kAllLaws) s += (s.empty() ? "" : ", ") + std::string(to_string(k));
  return s;
}

LawKind parse_law(std::string_view name, std::string_view what) {
  for (LawKind k : kAllLaws)
    if (name == to_string(k)) return k;
  throw InputError(std::string(what) + ": unknown law '" + std::string(name) + "' (allowed: " + law_names() + ")");
}

// ---- RiseLaw ---------------------------------------------------------------------------

RiseLaw::RiseLaw(double height_mm, double duration_deg) : h_(height_mm), beta_(duration_deg) {
  if (!std::isfinite(height_mm) || height_mm <= 0.0)
    throw InputError("height_mm = " + num(height_mm) + " mm: must be finite and positive");
  if (!std::isfinite(duration_deg) || duration_deg <= 0.0)
    throw InputError("duration_deg = " + num(duration_deg) + " cam deg: must be finite and positive");
}

Motion RiseLaw::unit(double x) const noexcept {
  if (!(x >= 0.0)) return {};  // also NaN: zero lift
  if (x > 1.0) return {1.0, 0.0, 0.0, 0.0};
  return unit_inside(x);
}

Motion RiseLaw::evaluate(double angle_deg) const noexcept {
  const Motion y = unit(angle_deg / beta_);
  // s^(k) = h / beta^k y^(k)
  const double s1 = h_ / beta_, s2 = s1 / beta_, s3 = s2 / beta_;
  return {h_ * y.lift, s1 * y.vel, s2 * y.acc, s3 * y.jerk};
}

// ---- polynomials -----------------------------------------------------------------------

Motion Polynomial345::unit_inside(double x) const noexcept {
  static constexpr std::array<double, 6> a = {0, 0, 0, 10.0, -15.0, 6.0};
  return polynomial_motion(a, x);
}

Motion Polynomial4567::unit_inside(double x) const noexcept {
  static constexpr std::array<double, 8> a = {0, 0, 0, 0, 35.0, -84.0, 70.0, -20.0};
  return polynomial_motion(a, x);
}

// ---- cycloidal -------------------------------------------------------------------------

Motion Cycloidal::unit_inside(double x) const noexcept {
  const double w = 2.0 * pi;
  const double s = std::sin(w * x), c = std::cos(w * x);
  return {x - s / w, 1.0 - c, w * s, w * w * c};
}

// ---- modified trapezoid / modified sine ------------------------------------------------

double ModifiedTrapezoid::peak_acceleration_coefficient() noexcept { return modified_trapezoid().peak; }
Motion ModifiedTrapezoid::unit_inside(double x) const noexcept { return modified_trapezoid().at(x); }

double ModifiedSine::peak_acceleration_coefficient() noexcept { return modified_sine().peak; }
Motion ModifiedSine::unit_inside(double x) const noexcept { return modified_sine().at(x); }

// ---- polydyne --------------------------------------------------------------------------

Polydyne::Polydyne(double height_mm, double duration_deg, double dynamic_factor)
    : RiseLaw(height_mm, duration_deg), k_(dynamic_factor) {
  if (!std::isfinite(dynamic_factor) || dynamic_factor < 0.0)
    throw InputError("dynamic_factor = " + num(dynamic_factor) + ": must be finite and >= 0");
}

double Polydyne::dynamic_factor(double engine_rpm, double natural_frequency_hz, double duration_deg,
                                double crank_per_cam) noexcept {
  const double omega_cam = engine_rpm / crank_per_cam * 2.0 * pi / 60.0;  // [rad/s]
  const double omega_n = 2.0 * pi * natural_frequency_hz;                  // [rad/s]
  const double beta = duration_deg * pi / 180.0;                          // [rad]
  const double r = omega_cam / (omega_n * beta);
  return r * r;
}

Motion Polydyne::valve_motion(double x) const noexcept {
  if (!(x >= 0.0)) return {};
  if (x > 1.0) return {1.0, 0.0, 0.0, 0.0};
  return polynomial_motion(kPolydyneValve, x);
}

Motion Polydyne::unit_inside(double x) const noexcept {
  // y^(k) = p^(k) + K p^(k+2)
  double d[6];
  polynomial(kPolydyneValve, x, 5, d);
  return {d[0] + k_ * d[2], d[1] + k_ * d[3], d[2] + k_ * d[4], d[3] + k_ * d[5]};
}

}  // namespace camopt::synthesis
