#pragma once
// a quantity known at the points of a driver grid with its first n derivatives (n = 0..3),
// between the points: on each interval the two-point hermite interpolant of degree 2n + 1
// that matches the value and the n derivatives at both ends (error f^(2n+2) (x - a)^(n+1)
// (x - b)^(n+1) / (2n + 2)!, Burden & Faires, Numerical Analysis, 9th ed., sec. 3.4). Its
// extremes, its crossings of a level and its integral refine the grid values.
#include <array>
#include <vector>

namespace camopt::kin {

// a quantity's value and first three derivatives per driver unit at one grid point
using GridJet = std::array<double, 4>;

// the interpolant on [x0, x0 + h]: p(t) = sum c[j] t^j with t = (x - x0) / h
class HermiteInterval {
 public:
  // order: derivatives matched at each end (0: linear .. 3: degree 7); x1 > x0
  static HermiteInterval fit(double x0, double x1, const GridJet& a, const GridJet& b, int order);

  double x0() const { return x0_; }
  double x1() const { return x0_ + h_; }
  int degree() const { return degree_; }
  // k-th derivative [per driver unit^k] at driver x; x outside the interval extrapolates
  double derivative(int k, double x) const;
  // the driver values in [lo, hi] where the k-th derivative equals level, ascending: every
  // sign change on 64 equal sub-intervals, each refined to rounding (bisection-safeguarded
  // newton). A pair of roots closer than a sub-interval may be missed.
  void solve(int k, double level, double lo, double hi, std::vector<double>& roots) const;
  // where the k-th derivative has a local extreme strictly inside the interval (roots of
  // derivative k + 1), ascending
  void stationary(int k, std::vector<double>& at) const;
  double integral() const;  // over the interval [quantity x driver unit]

 private:
  double x0_ = 0.0, h_ = 1.0;
  int degree_ = 1;
  std::array<double, 8> c_{};
  double poly(int k, double t) const;  // d^k p / dt^k
};

}  // namespace camopt::kin
