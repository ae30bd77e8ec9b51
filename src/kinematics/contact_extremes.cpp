// the contact extremes of a sweep's summary refined between its grid points (see
// contact_extremes.hpp): grid-local maxima, their brackets, Brent's method on solves seeded
// from the nearest grid point.
#include "contact_extremes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "camopt/core/units.hpp"

namespace camopt::kin::detail {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
// the location of a refined extreme is resolved to this [driver deg or mm]: far below any
// engineering use, a few dozen solves per extreme
constexpr double location_tolerance = 1e-9;
// a grid-local maximum whose neighbours differ from it by less than this, relative to the
// quantity's largest magnitude over the grid, is flat to round-off (a circle's constant
// curvature, a dwell): refining it cannot gain anything visible
constexpr double flat_relative = 1e-12;
constexpr int max_brent_iterations = 100;
// the polishing stencil's spacing, of the bracket
constexpr double polish_fraction = 5e-3;
constexpr double golden_fraction = 0.3819660112501051;  // (3 - sqrt 5) / 2

// Brent's method (Brent, Algorithms for Minimization without Derivatives, 1973, ch. 5) for
// the largest value of f on [a, b] from the point x inside with f(x) = fx: parabolic steps
// through the three best points, golden section where the parabola is not trusted (or a
// value is not finite, where f is undefined). Returns the best point evaluated.
template <class F>
Extreme brent_max(const F& f, double a, double b, double x, double fx) {
  // minimise g = -f
  double gx = -fx, w = x, gw = gx, v = x, gv = gx, d = 0.0, e = 0.0;
  for (int it = 0; it < max_brent_iterations; ++it) {
    const double xm = 0.5 * (a + b);
    const double tol1 = 0.25 * location_tolerance + 4 * std::numeric_limits<double>::epsilon() * std::abs(x);
    const double tol2 = 2.0 * tol1;
    if (std::abs(x - xm) <= tol2 - 0.5 * (b - a)) break;
    bool parabolic = false;
    if (std::abs(e) > tol1 && std::isfinite(gx) && std::isfinite(gw) && std::isfinite(gv)) {
      const double r = (x - w) * (gx - gv);
      double q = (x - v) * (gx - gw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      const double e_prev = e;
      if (std::abs(p) < std::abs(0.5 * q * e_prev) && p > q * (a - x) && p < q * (b - x)) {
        e = d;
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = xm >= x ? tol1 : -tol1;
        parabolic = true;
      }
    }
    if (!parabolic) {
      e = x >= xm ? a - x : b - x;
      d = golden_fraction * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d >= 0 ? tol1 : -tol1);
    const double gu = -f(u);
    if (gu <= gx) {
      (u >= x ? a : b) = x;
      v = w, gv = gw, w = x, gw = gx, x = u, gx = gu;
    } else {
      (u < x ? a : b) = u;
      if (gu <= gw || w == x) {
        v = w, gv = gw, w = u, gw = gu;
      } else if (gu <= gv || v == x || v == w) {
        v = u, gv = gu;
      }
    }
  }
  return {-gx, x};
}

// the location of a smooth maximum polished by one newton step on the derivative: Brent's
// method resolves it only to about sqrt(2 round-off / |f''|) (values are flat there), a
// newton step from five-point differences at spacing h (errors h^4 f^(5) / 30 and round-off
// / h) to round-off / (h f''). Taken only where f is smooth there (f'' < 0, the step within
// h) and f at the new point is the same to `flat_relative`; the value reported is the larger.
template <class F>
Extreme polish(const F& f, Extreme e, double h) {
  const double m2 = f(e.at - 2 * h), m1 = f(e.at - h), p1 = f(e.at + h), p2 = f(e.at + 2 * h);
  const double d1 = (m2 - 8 * m1 + 8 * p1 - p2) / (12 * h);
  const double d2 = (-m2 + 16 * m1 - 30 * e.value + 16 * p1 - p2) / (12 * h * h);
  if (!std::isfinite(d1) || !(d2 < 0)) return e;
  const double step = -d1 / d2;
  if (!(std::abs(step) < h)) return e;
  const double v = f(e.at + step);
  if (!(v >= e.value - flat_relative * std::abs(e.value))) return e;
  return {std::max(v, e.value), e.at + step};
}

// a grid-local maximum of one connection's series and the most refining it could gain
struct Candidate {
  std::size_t series, i;
  double value;  // at the grid point
  double bound;  // optimistic: the grid value plus its largest drop to a neighbour (inf: unknown)
};

// the grid-local maxima of series g worth refining. On a parabola the maximum within one
// step of a grid-local maximum exceeds it by at most a quarter of its larger drop to a
// neighbour; the bound takes the whole drop. A neighbour where g is undefined (the contact
// opens) leaves the bound unknown.
void add_candidates(const std::vector<double>& g, std::size_t series, std::vector<Candidate>& out) {
  const std::size_t n = g.size();
  double scale = 0.0;
  for (double v : g)
    if (std::isfinite(v)) scale = std::max(scale, std::abs(v));
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(g[i])) continue;
    const bool left = i > 0, right = i + 1 < n;
    if ((left && g[i - 1] > g[i]) || (right && g[i + 1] > g[i])) continue;
    double drop = 0.0;
    if (left) drop = std::max(drop, g[i] - g[i - 1]);
    if (right) drop = std::max(drop, g[i] - g[i + 1]);
    if (std::isfinite(drop) && drop <= flat_relative * scale) continue;  // flat to round-off
    out.push_back({series, i, g[i], g[i] + drop});
  }
}

}  // namespace

ContactProbe::ContactProbe(const Mechanism& m, const SweepResult& r, std::size_t p)
    : mech(m), result(r), position(p) {
  // a sweep's outputs are k! c_k per driver deg^k, in deg for angles (sweep.cpp): back to
  // taylor coefficients per driver rad^k in rad
  const std::size_t nv = m.variables.size();
  const double unit = m.driver_is_angle() ? rad_per_deg : 1.0;
  constexpr double factorial[4] = {1.0, 1.0, 2.0, 6.0};
  scale_.resize(nv * 4);
  for (std::size_t v = 0; v < nv; ++v) {
    double f = m.variables[v].is_angle ? rad_per_deg : 1.0;
    for (int k = 0; k <= 3; ++k, f /= unit) scale_[v * 4 + k] = f / factorial[k];
  }
  seed_.assign(nv, Jet3(0.0));
}

const std::vector<ContactState>* ContactProbe::at(double x) {
  const std::vector<double>& grid = result.driver;
  const PositionResult& p = result.positions[position];
  // the nearest grid point
  const auto above = std::lower_bound(grid.begin(), grid.end(), x);
  std::size_t j = static_cast<std::size_t>(above - grid.begin());
  if (j == grid.size() || (j > 0 && x - grid[j - 1] <= grid[j] - x)) --j;
  for (std::size_t v = 0; v < seed_.size(); ++v)
    for (int k = 0; k <= 3; ++k) seed_[v].c[k] = p.value(j, static_cast<int>(v), k) * scale_[v * 4 + k];
  if (!ws_) {
    ws_.emplace(mech);
    ws_->set_controls(p.controls);
  }
  const double unit = mech.driver_is_angle() ? rad_per_deg : 1.0;
  ++solves_;
  // each refined point is solved from its grid point alone: the thread's profile and sin/cos
  // memos (which hold shifted, not recomputed, entries) start empty, so the result does not
  // depend on which positions this thread solved before
  CamProfile::clear_thread_memo();
  const Status st = solve_near(mech, *ws_, grid[j] * unit, seed_, x * unit, Request{1, true});
  if (!st.ok()) {
    failed_ = true;
    return nullptr;
  }
  return &ws_->contacts;
}

std::optional<ContactExtreme> refined_max(ContactProbe& probe, const std::vector<std::size_t>& contacts,
                                          const ContactQuantity& q, double floor) {
  const std::vector<double>& x = probe.result.driver;
  const PositionResult& p = probe.result.positions[probe.position];
  const std::size_t nc = probe.mech.connections.size(), n = x.size();
  // each connection's series at the grid points, the best value and the local maxima
  std::optional<ContactExtreme> best;
  std::vector<Candidate> list;
  std::vector<double> g(n);
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      g[i] = q(p.contacts[i * nc + contacts[k]]);
      if (std::isfinite(g[i]) && (!best || g[i] > best->extreme.value)) best = ContactExtreme{{g[i], x[i]}, contacts[k]};
    }
    if (n >= 2) add_candidates(g, k, list);
  }
  std::sort(list.begin(), list.end(), [](const Candidate& a, const Candidate& b) { return a.bound > b.bound; });
  // each that could beat the best so far, maximised on the span to its neighbours
  for (const Candidate& c : list) {
    if (c.bound < std::max(floor, best->extreme.value)) break;
    const std::size_t contact = contacts[c.series];
    auto f = [&](double at) {
      const std::vector<ContactState>* states = probe.at(at);
      return states ? q((*states)[contact]) : -inf;
    };
    const double a = x[c.i == 0 ? 0 : c.i - 1], b = x[std::min(c.i + 1, n - 1)];
    // at an end of the range the grid point is an end of the bracket: start inside it
    const bool end = c.i == 0 || c.i + 1 == n;
    const double start = !end ? x[c.i] : c.i == 0 ? a + golden_fraction * (b - a) : b - golden_fraction * (b - a);
    Extreme e = brent_max(f, a, b, start, end ? f(start) : c.value);
    // inside the bracket by more than the stencil: its location polished
    const double h = polish_fraction * (b - a);
    if (e.at - 2 * h > a && e.at + 2 * h < b) e = polish(f, e, h);
    if (e.value > best->extreme.value) best = ContactExtreme{e, contact};
  }
  return best;
}

}  // namespace camopt::kin::detail
