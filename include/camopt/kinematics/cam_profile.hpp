#pragma once
// a cam profile compiled from a ProfileSpec: a closed, counter-clockwise curve p(u) in
// the profile frame [mm], C4 continuous (periodic quintic splines), evaluable on jets so
// the profile's own curvature feeds follower acceleration and jerk exactly.
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/core/trig_cache.hpp"
#include "camopt/core/dual.hpp"

namespace camopt::kin {

// a curve point with its first and second derivatives with respect to the parameter u
template <class T>
struct CurvePoint {
  T x, y, dx, dy, ddx, ddy;
};

class CamProfile {
 public:
  // polar / base_plus_lift: u is the polar angle [rad]; xy: u is 2*pi * chord fraction.
  // circle / eccentric profiles are exact discs (is_disc()); contacts use them as circles.
  static CamProfile build(const ProfileSpec& spec);

  const std::string& name() const { return name_; }
  bool is_disc() const { return is_disc_; }
  double disc_radius_mm() const { return disc_radius_; }
  double disc_center_x_mm() const { return disc_center_x_; }  // on the profile's 0-deg axis

  // smallest and largest distance from the profile origin [mm]
  double base_radius_mm() const { return base_radius_; }
  double max_radius_mm() const { return max_radius_; }
  // polar radius at a polar angle [rad] (excess radius = radius - base radius)
  double radius_at(double polar_angle_rad) const;

  // second = false leaves ddx, ddy unset (cheaper: residuals need no curvature).
  // memo (values only): fetch the spline through the per-thread memo below, for an
  // iteration whose last parameter the derivative sweeps evaluate again
  template <class T>
  CurvePoint<T> point(const T& u, bool second = true, bool memo = false) const;

  // the curve's taylor series of order M in its parameter about u: point(Jet<M>::variable(u))
  // without the general composition (the argument's series is u + eps); through the memo
  template <int M>
  CurvePoint<Jet<M>> point_series(double u) const;

  // the per-thread memo's entries at parameter u (spline derivatives, sin and cos) moved
  // to u + h by their taylor series, exact on the spline's quintic piece to round-off:
  // an iteration that steps by a tiny h without evaluating the curve again leaves the
  // later sweeps at u + h a memo hit. Nothing happens if u is not in the memo.
  void shift_memo(double u, double h) const;

 private:
  // f, f', f'' of spline `which` (0: r or x, 1: y) at u, on jets or duals
  template <class T>
  void spline_jets(int which, const T& u, T& f, T& f1, T& f2, bool second, bool memo) const;
  void spline_jets(int which, double u, double& f, double& f1, double& f2, bool second, bool memo) const;
  // out[k] = f^(k)(u), k = 0..need, through a per-thread memo: one kinematic point
  // evaluates the same spline at the same parameter in several derivative sweeps
  // (jacobian, second and third order, contact outputs), so a miss fetches every order.
  // Results are bit-identical to PeriodicSpline::evaluate. (Value sweeps bypass it unless
  // asked: their parameters change on every iteration.)
  void spline_derivatives(int which, double u, int need, double* out) const;
  const PeriodicSpline& spline(int which) const { return which == 0 ? (polar_ ? r_ : x_) : y_; }
  struct Memo {
    static constexpr unsigned size = 4;
    struct Entry {
      std::uint64_t key = 0;
      double u = 0.0;
      double d[PeriodicSpline::degree + 1] = {};
    } entries[size];
    unsigned next = 0;
  };
  static Memo& memo() noexcept;  // per thread

 public:
  // empties this thread's memos (splines and sin/cos): a computation that starts here gives
  // the same bits whatever ran on the thread before (shifted and inserted entries are
  // within round-off of, not equal to, a fresh evaluation)
  static void clear_thread_memo() noexcept {
    memo() = Memo{};
    SinCosMemo::local().clear();
  }

 private:
  static std::uint64_t next_memo_id() noexcept {
    static std::atomic<std::uint64_t> counter{0};
    return counter.fetch_add(1, std::memory_order_relaxed) + 1;
  }

  std::string name_;
  bool polar_ = true;
  bool is_disc_ = false;
  double disc_radius_ = 0.0, disc_center_x_ = 0.0;
  PeriodicSpline r_;       // polar: r(u)
  PeriodicSpline x_, y_;   // xy: x(u), y(u)
  double base_radius_ = 0.0, max_radius_ = 0.0;
  // identifies this profile's splines in the memo; copies share it with the contents
  std::uint64_t memo_id_ = next_memo_id();
};

inline CamProfile::Memo& CamProfile::memo() noexcept {
  thread_local Memo m{};
  return m;
}

inline void CamProfile::spline_derivatives(int which, double u, int need, double* out) const {
  Memo& memo = CamProfile::memo();
  const std::uint64_t key = memo_id_ * 2 + static_cast<std::uint64_t>(which);  // ids start at 1: key 0 is empty
  for (const Memo::Entry& e : memo.entries)
    if (e.key == key && e.u == u) {
      for (int k = 0; k <= need; ++k) out[k] = e.d[k];
      return;
    }
  Memo::Entry& e = memo.entries[memo.next];
  memo.next = (memo.next + 1) % Memo::size;
  spline(which).evaluate(u, PeriodicSpline::degree, e.d);
  e.key = key;
  e.u = u;
  for (int k = 0; k <= need; ++k) out[k] = e.d[k];
}

inline void CamProfile::shift_memo(double u, double h) const {
  const int splines = polar_ ? 1 : 2;
  for (int which = 0; which < splines; ++which) {
    Memo& memo = CamProfile::memo();
    const std::uint64_t key = memo_id_ * 2 + static_cast<std::uint64_t>(which);
    const Memo::Entry* from = nullptr;
    for (const Memo::Entry& e : memo.entries)
      if (e.key == key && e.u == u) from = &e;
    if (from == nullptr) continue;
    double shifted[PeriodicSpline::degree + 1];
    // f^(k)(u + h) = sum_j f^(k+j)(u) h^j / j! (horner; exact for the quintic piece)
    constexpr int n = PeriodicSpline::degree;
    double h_over[n + 1];  // h / j
    for (int j = 1; j <= n; ++j) h_over[j] = h / j;
    for (int k = 0; k <= n; ++k) {
      double acc = from->d[n];
      for (int m = n - 1; m >= k; --m) acc = from->d[m] + acc * h_over[m - k + 1];
      shifted[k] = acc;
    }
    Memo::Entry* to = &memo.entries[memo.next];
    memo.next = (memo.next + 1) % Memo::size;
    std::copy(shifted, shifted + PeriodicSpline::degree + 1, to->d);
    to->key = key;
    to->u = u + h;
  }
  if (polar_ || is_disc_) memo_sin_cos_shift(u, h);
}

inline void CamProfile::spline_jets(int which, double u, double& f, double& f1, double& f2, bool second,
                                     bool memo) const {
  double d[3];
  if (memo)
    spline_derivatives(which, u, second ? 2 : 1, d);
  else
    spline(which).evaluate(u, second ? 2 : 1, d);
  f = d[0];
  f1 = d[1];
  if (second) f2 = d[2];
}

template <class T>
void CamProfile::spline_jets(int which, const T& u, T& f, T& f1, T& f2, bool second, bool /*memo: always*/) const {
  // f, f', f'' of order N need derivatives up to N + 2 (quintic: f^(5) piecewise constant)
  constexpr int N = taylor_order<T>;
  double d[N + 3 > 6 ? N + 3 : 6] = {};
  const int need = N + (second ? 2 : 1);
  spline_derivatives(which, u.value(), need < 5 ? need : 5, d);
  f = compose(d, u);
  f1 = compose(d + 1, u);
  if (second) f2 = compose(d + 2, u);
}

template <class T>
CurvePoint<T> CamProfile::point(const T& u, bool second, bool memo) const {
  CurvePoint<T> p;
  T c, s;
  if (is_disc_ || polar_) sin_cos(u, s, c);
  if (is_disc_) {
    p.x = disc_center_x_ + disc_radius_ * c;
    p.y = disc_radius_ * s;
    p.dx = -disc_radius_ * s;
    p.dy = disc_radius_ * c;
    p.ddx = -disc_radius_ * c;
    p.ddy = -disc_radius_ * s;
    return p;
  }
  if (polar_) {
    T r, r1, r2;
    spline_jets(0, u, r, r1, r2, second, memo);
    // p = r (cos u, sin u)
    p.x = r * c;
    p.y = r * s;
    p.dx = r1 * c - p.y;
    p.dy = r1 * s + p.x;
    if (second) {
      p.ddx = r2 * c - 2.0 * r1 * s - p.x;
      p.ddy = r2 * s + 2.0 * r1 * c - p.y;
    }
    return p;
  }
  spline_jets(0, u, p.x, p.dx, p.ddx, second, memo);
  spline_jets(1, u, p.y, p.dy, p.ddy, second, memo);
  return p;
}

template <int M>
CurvePoint<Jet<M>> CamProfile::point_series(double u) const {
  static_assert(M + 1 <= PeriodicSpline::degree, "the series of p' needs f^(M+1)");
  const auto& inv_factorial = camopt::detail::kInvFactorial<M + 1>;
  // the series of f and of f' about u from f^(k)(u): f_k = f^(k) / k!, f'_k = f^(k+1) / k!
  auto series = [&](int which, Jet<M>& f, Jet<M>& f1) {
    double d[PeriodicSpline::degree + 1];
    spline_derivatives(which, u, M + 1, d);
    for (int k = 0; k <= M; ++k) {
      f.c[k] = d[k] * inv_factorial[static_cast<std::size_t>(k)];
      f1.c[k] = d[k + 1] * inv_factorial[static_cast<std::size_t>(k)];
    }
  };
  CurvePoint<Jet<M>> p;
  if (!is_disc_ && !polar_) {
    series(0, p.x, p.dx);
    series(1, p.y, p.dy);
    return p;
  }
  // sin(u + eps), cos(u + eps): the derivatives cycle s, c, -s, -c
  double s0, c0;
  sin_cos(u, s0, c0);
  Jet<M> s, c;
  const double cycle_s[4] = {s0, c0, -s0, -c0}, cycle_c[4] = {c0, -s0, -c0, s0};
  for (int k = 0; k <= M; ++k) {
    s.c[k] = cycle_s[k % 4] * inv_factorial[static_cast<std::size_t>(k)];
    c.c[k] = cycle_c[k % 4] * inv_factorial[static_cast<std::size_t>(k)];
  }
  if (is_disc_) {
    p.x = disc_center_x_ + disc_radius_ * c;
    p.y = disc_radius_ * s;
    p.dx = -disc_radius_ * s;
    p.dy = disc_radius_ * c;
    return p;
  }
  Jet<M> r, r1;
  series(0, r, r1);
  p.x = r * c;
  p.y = r * s;
  p.dx = r1 * c - p.y;
  p.dy = r1 * s + p.x;
  return p;
}

}  // namespace camopt::kin
