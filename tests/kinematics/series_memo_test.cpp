// the pieces of the one-equation contact's fast path: the curve's taylor series in its
// parameter (point_series), the taylor shift of a series and of the per-thread memo, and
// the control sweep that starts every position from one solved drawing.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "camopt/core/jet.hpp"
#include "camopt/core/trig_cache.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/cam_profile.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "support/compare.hpp"

using namespace camopt;

namespace {
using namespace camopt::test::tol;

// a polar cam: base circle 18 mm plus a smooth 8 mm lobe, 1 deg table
kin::CamProfile lobe_profile() {
  ProfileSpec spec;
  spec.name = "lobe";
  spec.form = ProfileForm::polar;
  for (int i = 0; i < 360; ++i) {
    const double a = i * std::numbers::pi / 180.0;
    spec.angle_deg.push_back(i);
    const double c = std::cos(0.5 * a);
    spec.radius_mm.push_back(18.0 + 8.0 * std::pow(c * c, 3));
  }
  return kin::CamProfile::build(spec);
}

// the largest |a_k - b_k| / max |b_k| over the coefficients of two 2-d series
template <int M>
double series_difference(const kin::CurvePoint<Jet<M>>& a, const kin::CurvePoint<Jet<M>>& b) {
  double err = 0.0, peak = 0.0;
  auto add = [&](const Jet<M>& x, const Jet<M>& y) {
    for (int k = 0; k <= M; ++k) {
      err = std::max(err, std::abs(x.c[k] - y.c[k]));
      peak = std::max(peak, std::abs(y.c[k]));
    }
  };
  add(a.x, b.x);
  add(a.y, b.y);
  add(a.dx, b.dx);
  add(a.dy, b.dy);
  return err / peak;
}
}  // namespace

TEST_CASE("jet: taylor_shift re-expands a series about a shifted point", "[jet]") {
  // p(t) = 2 - 3t + 0.5t^2 + 4t^3 - t^4: degree 4, exact in a Jet<4>
  Jet<4> p;
  const double c[5] = {2.0, -3.0, 0.5, 4.0, -1.0};
  for (int k = 0; k <= 4; ++k) p.c[k] = c[k];
  const double h = 0.37;
  taylor_shift(p, h);
  // the shifted coefficients are p^(k)(h) / k!
  auto poly = [&](double t, int k) {
    double sum = 0.0;
    for (int j = k; j <= 4; ++j) {
      double binom = 1.0;
      for (int i = 0; i < k; ++i) binom *= static_cast<double>(j - i) / (i + 1);
      sum += c[j] * binom * std::pow(t, j - k);
    }
    return sum;
  };
  for (int k = 0; k <= 4; ++k) CHECK_ABS(p.c[k], poly(h, k), kTaylorShiftAbs);
  // shifting back restores the series
  taylor_shift(p, -h);
  for (int k = 0; k <= 4; ++k) CHECK_ABS(p.c[k], c[k], kTaylorShiftAbs);
}

TEST_CASE("cam profile: point_series equals the curve on a variable jet", "[kinematics][profile]") {
  const kin::CamProfile profile = lobe_profile();
  for (const double u : {0.0, 0.3, 1.234, 3.0, 5.9}) {
    INFO("u = " << u);
    const auto direct = profile.point(Jet<4>::variable(u), false);
    const auto series = profile.point_series<4>(u);
    CHECK_ABS(series_difference(series, direct), 0.0, kPointSeriesAbs);
    // and its derivatives agree with the double evaluation
    const auto values = profile.point(u, true);
    CHECK_ABS(series.x.c[0], values.x, kPointCoordAbs);
    CHECK_ABS(series.dx.c[0], values.dx, kPointCoordAbs);
    CHECK_ABS(series.dx.c[1], values.ddx, kPointCurvAbs);
  }
}

TEST_CASE("cam profile: a shifted memo entry equals a fresh evaluation", "[kinematics][profile]") {
  const kin::CamProfile profile = lobe_profile();
  for (const double u : {0.2, 1.0, 2.5}) {
    for (const double h : {1e-7, -3e-9, 2.5e-12}) {
      INFO("u = " << u << ", h = " << h);
      (void)profile.point_series<4>(u);  // into the memo
      profile.shift_memo(u, h);
      const auto shifted = profile.point_series<4>(u + h);  // memo hit: the shifted entry
      // a copy of the profile has its own memo key: a fresh evaluation
      const kin::CamProfile fresh = lobe_profile();
      const auto direct = fresh.point_series<4>(u + h);
      CHECK_ABS(series_difference(shifted, direct), 0.0, kPointSeriesShiftAbs);
    }
  }
  // sin and cos rotated by h agree with libm to an ulp or two
  for (const double x : {0.1, 2.0, -4.0}) {
    for (const double h : {1e-3, -1e-7, 1e-12}) {
      double s, c;
      sin_cos(x, s, c);
      memo_sin_cos_shift(x, h);
      sin_cos(x + h, s, c);
      CHECK_ABS(s, std::sin(x + h), kRotatedSinCosAbs);
      CHECK_ABS(c, std::cos(x + h), kRotatedSinCosAbs);
    }
  }
}

TEST_CASE("control sweep: every position equals its own solve from a fresh workspace", "[kinematics][sweep]") {
  // the sweep starts each position from one solved drawing per thread; the continuation
  // from there is the same computation solve() makes from a fresh workspace, so the
  // results are identical whichever thread or order solves a position
  const auto m = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml"));
  kin::SweepSpec spec;
  spec.start = 10.0;
  spec.stop = 70.0;
  spec.step = 2.0;
  spec.request = {3, true};
  spec.threads = 2;
  spec.control_positions = {{16.0}, {3.0}, {8.0}};
  const auto r = kin::sweep(m, spec);
  const std::size_t nv = m.variables.size();
  for (std::size_t p = 0; p < spec.control_positions.size(); ++p) {
    INFO("control " << spec.control_positions[p][0]);
    REQUIRE(r.positions[p].status.ok());
    kin::Workspace ws(m);
    ws.set_controls(spec.control_positions[p]);
    for (std::size_t i = 0; i < r.driver.size(); ++i) {
      REQUIRE(kin::solve(m, ws, r.driver[i] * (std::numbers::pi / 180.0), spec.request).ok());
      for (std::size_t c = 0; c < m.connections.size(); ++c) {
        CHECK(r.positions[p].contacts[i * m.connections.size() + c].pressure_angle == ws.contacts[c].pressure_angle);
        CHECK(r.positions[p].contacts[i * m.connections.size() + c].roller_speed == ws.contacts[c].roller_speed);
      }
      for (std::size_t v = 0; v < nv; ++v) {
        // the sweep's own conversion (rad -> deg as 1 / deg), so equality is exact
        const double to_output = m.variables[v].is_angle ? 1.0 / (std::numbers::pi / 180.0) : 1.0;
        double scale = to_output;
        for (int k = 0; k <= 3; ++k, scale *= std::numbers::pi / 180.0)
          CHECK(r.positions[p].value(i, static_cast<int>(v), k) == ws.vars[v].derivative(k) * scale);
      }
    }
  }
}

TEST_CASE("lift-only sweeps solve the same positions as sweeps with every output", "[kinematics][sweep]") {
  // lift only runs the one-equation contacts on a first-order series in u from a linear
  // prediction; with derivatives on a fourth-order series from the Taylor prediction. Both
  // converge to 1e-13 x the mechanism size.
  for (const char* file : {"designs/cvvl_swing_cam.toml", "designs/roller_finger_follower.toml", "designs/vvld.toml"}) {
    INFO(file);
    const auto m = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/" + file));
    kin::SweepSpec spec;
    spec.step = 0.5;
    if (!m.controls.empty()) spec.control_positions = {{m.controls[0].min}, {m.controls[0].max}};
    spec.request = {0, false};
    const auto lift_only = kin::sweep(m, spec);
    spec.request = {3, true};
    const auto all = kin::sweep(m, spec);
    const std::size_t nv = m.variables.size();
    for (std::size_t p = 0; p < all.positions.size(); ++p) {
      REQUIRE(lift_only.positions[p].status.ok());
      REQUIRE(all.positions[p].status.ok());
      // every variable at every point [mm or deg]
      std::vector<double> alone, with_all;
      for (std::size_t i = 0; i < all.driver.size(); ++i)
        for (std::size_t v = 0; v < nv; ++v) {
          alone.push_back(lift_only.positions[p].value(i, static_cast<int>(v), 0));
          with_all.push_back(all.positions[p].value(i, static_cast<int>(v), 0));
        }
      CHECK_SERIES(camopt::test::compare_series("position solved alone", alone, with_all, {.abs = kSolverPathAbs}));
    }
  }
}
