#pragma once
// hermite polynomials on [0, 1] from end values and derivatives (per unit of the local
// parameter), used to resample envelopes and to interpolate inverse motions.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace camopt::synthesis {

// quintic hermite on [0, 1] from value, first and second derivative (per unit t) at both ends
struct Quintic {
  double a[6];
  Quintic(double p0, double d0, double s0, double p1, double d1, double s1) {
    // p(t) = a0 + a1 t + ... + a5 t^5 matching p, p', p'' at t = 0 and 1
    a[0] = p0;
    a[1] = d0;
    a[2] = 0.5 * s0;
    const double r0 = p1 - (a[0] + a[1] + a[2]);
    const double r1 = d1 - (a[1] + 2 * a[2]);
    const double r2 = s1 - 2 * a[2];
    a[3] = 10 * r0 - 4 * r1 + 0.5 * r2;
    a[4] = -15 * r0 + 7 * r1 - r2;
    a[5] = 6 * r0 - 3 * r1 + 0.5 * r2;
  }
  // value and first derivative only
  void eval(double t, double& p, double& d) const {
    p = ((((a[5] * t + a[4]) * t + a[3]) * t + a[2]) * t + a[1]) * t + a[0];
    d = (((5 * a[5] * t + 4 * a[4]) * t + 3 * a[3]) * t + 2 * a[2]) * t + a[1];
  }
  void eval(double t, double& p, double& d, double& s) const {
    p = ((((a[5] * t + a[4]) * t + a[3]) * t + a[2]) * t + a[1]) * t + a[0];
    d = (((5 * a[5] * t + 4 * a[4]) * t + 3 * a[3]) * t + 2 * a[2]) * t + a[1];
    s = ((20 * a[5] * t + 12 * a[4]) * t + 6 * a[3]) * t + 2 * a[2];
  }
};

// curvature of a polar curve r(phi) from r, dr/dphi, d2r/dphi2 (+ convex) [1/mm]
inline double polar_curvature(double r, double d1, double d2) {
  const double q = r * r + d1 * d1;
  return (r * r + 2 * d1 * d1 - r * d2) / (q * std::sqrt(q));
}

// septic hermite on [0, 1] from value and three derivatives (per unit t) at both ends:
// p0[k], p1[k] = d^k p / dt^k at t = 0 and t = 1
struct Septic {
  double a[8];
  Septic(const double* p0, const double* p1) {
    a[0] = p0[0];
    a[1] = p0[1];
    a[2] = 0.5 * p0[2];
    a[3] = p0[3] / 6;
    const double r0 = p1[0] - (a[0] + a[1] + a[2] + a[3]);
    const double r1 = p1[1] - (a[1] + 2 * a[2] + 3 * a[3]);
    const double r2 = p1[2] - (2 * a[2] + 6 * a[3]);
    const double r3 = p1[3] - 6 * a[3];
    // inverse of the end conditions on a4..a7 (rows: value, d1, d2, d3 of t^4..t^7 at 1)
    a[4] = 35 * r0 - 15 * r1 + 2.5 * r2 - r3 / 6;
    a[5] = -84 * r0 + 39 * r1 - 7 * r2 + r3 / 2;
    a[6] = 70 * r0 - 34 * r1 + 6.5 * r2 - r3 / 2;
    a[7] = -20 * r0 + 10 * r1 - 2 * r2 + r3 / 6;
  }
  // value and slope only (d[0], d[1]: the same numbers as eval's)
  void eval1(double t, double* d) const {
    d[0] = a[7];
    d[1] = 0.0;
    for (int k = 6; k >= 0; --k) {
      d[1] = d[1] * t + d[0];
      d[0] = d[0] * t + a[k];
    }
  }
  // d[k] = p^(k)(t), k = 0..3
  void eval(double t, double* d) const {
    // horner with synthetic division (Numerical Recipes, ddpoly): d[j] = p^(j) / j!
    d[0] = a[7];
    d[1] = d[2] = d[3] = 0.0;
    for (int k = 6; k >= 0; --k) {
      d[3] = d[3] * t + d[2];
      d[2] = d[2] * t + d[1];
      d[1] = d[1] * t + d[0];
      d[0] = d[0] * t + a[k];
    }
    d[2] *= 2.0;
    d[3] *= 6.0;
  }
};

// a nose over `length` of the variable: from value p, slope d and second derivative s (per
// unit of the variable) to a maximum with value p + d length / 2, slope 0, second
// derivative -d / length (decelerating as a parabola would) and third derivative 0, so its
// mirror image beyond the maximum joins it c3 (the start's third derivative is 0: a join
// there is c2). Septic::eval at t = distance / length gives derivatives per unit t.
inline Septic nose_septic(double p, double d, double s, double length) {
  const double start[4] = {p, d * length, s * length * length, 0.0};
  const double top[4] = {p + 0.5 * d * length, 0.0, -d * length, 0.0};
  return Septic(start, top);
}

// septic hermite pieces between consecutive points a span apart, from the value and three
// derivatives at both ends per unit of the variable, built once for a table evaluated many
// times. Each point carries `fields` functions, laid out [field * 4 + derivative]
class SepticPieces {
 public:
  explicit SepticPieces(int fields = 1) : fields_(fields) {}
  // the interval from point a to point b, `span` of the variable apart
  void add_interval(const double* a, const double* b, double span) {
    for (int f = 0; f < fields_; ++f) {
      double e0[4], e1[4], power = 1.0;
      for (int k = 0; k < 4; ++k, power *= span) e0[k] = a[4 * f + k] * power, e1[k] = b[4 * f + k] * power;
      Piece& p = pieces_.emplace_back(Piece{Septic(e0, e1), {}});
      power = span;
      for (int k = 1; k < 4; ++k, power *= span) p.divisor[k - 1] = power;
    }
    ++intervals_;
  }
  std::size_t intervals() const { return intervals_; }
  // field f on interval i at t in [0, 1] of it: out[k] = derivative k per unit of the variable
  void eval(std::size_t i, int f, double t, double* out) const {
    const Piece& p = pieces_[i * static_cast<std::size_t>(fields_) + static_cast<std::size_t>(f)];
    p.septic.eval(t, out);
    for (int k = 1; k < 4; ++k) out[k] /= p.divisor[k - 1];
  }
  // ... its value and first derivative only (out[0], out[1])
  void eval1(std::size_t i, int f, double t, double* out) const {
    const Piece& p = pieces_[i * static_cast<std::size_t>(fields_) + static_cast<std::size_t>(f)];
    p.septic.eval1(t, out);
    out[1] /= p.divisor[0];
  }
  // field f at x, counted in intervals from the first point (evenly spaced points), on the
  // interval holding it (the first or the last beyond the ends); slope_only: eval1
  void eval_at(double x, int f, double* out, bool slope_only = false) const {
    const int last = static_cast<int>(intervals_) - 1;
    const int i = x > 0.0 ? std::min(last, static_cast<int>(x)) : 0;  // (truncation is floor for x > 0)
    if (slope_only)
      eval1(static_cast<std::size_t>(i), f, x - i, out);
    else
      eval(static_cast<std::size_t>(i), f, x - i, out);
  }

 private:
  struct Piece {
    Septic septic;
    double divisor[3];  // span^1..3
  };
  int fields_;
  std::size_t intervals_ = 0;
  std::vector<Piece> pieces_;
};

}  // namespace camopt::synthesis
