// the spring chain by modal superposition checked against its equations of motion, an
// eigen-solver of the same chain, a fixed-step RK4, momentum balance, the quasi-static
// limit and the continuum spring's surge frequencies.
#include "oracles/spring_chain_oracle.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "oracles/finite_difference.hpp"
#include "support/compare.hpp"

namespace {

using namespace camopt::oracles;
using camopt::test::Series;
namespace tol = camopt::test::tol;

constexpr double pi = std::numbers::pi;

// a valve spring: 40 N/mm, 30 g, 250 N preload, top end moved by the 4 mm eccentric at
// 4700 rpm (surge f_1 = 577 Hz against a cam at 78 Hz)
SpringChain valve_spring(int n) { return {40e3, 0.03, n, 250.0, 4e-3, 4700.0 * 2.0 * pi / 60.0}; }

}  // namespace

TEST_CASE("spring chain oracle: the modal solution satisfies the equations of motion from rest", "[oracles]") {
  for (const int n : {4, 40, 400}) {
    const SpringChainOracle o(valve_spring(n));
    const double mi = o.node_mass(), ki = o.segment_rate();
    // the modal sums' round-off is relative to their terms, each of order k e whatever the
    // local u (tiny ahead of the wave front), so k e joins the local terms in the scale;
    // worst measured: 4e-15 of it (N = 4), 4e-14 (40), 5e-13 (400)
    const double force_scale = o.chain().rate * o.chain().eccentricity;
    // at rest at t = 0, and u'' = 0 there too since X(0) = 0
    const Eigen::Matrix<double, Eigen::Dynamic, 3> u0 = o.displacements(0.0);
    CHECK(u0.cwiseAbs().maxCoeff() == 0.0);
    const double span = 2.0 * pi / o.chain().cam_speed;
    for (int i = 1; i <= 24; ++i) {
      const double t = span * i / 17.0;
      const Eigen::Matrix<double, Eigen::Dynamic, 3> u = o.displacements(t);
      auto at = [&](int j) { return j == 0 ? 0.0 : j == n + 1 ? o.top(t)[0] : u(j - 1, 0); };
      for (int j = 1; j <= n; ++j) {
        const double residual = mi * u(j - 1, 2) - ki * (at(j + 1) - 2.0 * at(j) + at(j - 1));
        const double scale = mi * std::abs(u(j - 1, 2)) +
                             ki * (std::abs(at(j + 1)) + 2.0 * std::abs(at(j)) + std::abs(at(j - 1))) + force_scale;
        INFO("N " << n << " t " << t << " j " << j << " scale " << scale << " N");
        CHECK_ABS(residual, 0.0, tol::kResidualRel * scale);
      }
      // displacement() and displacements() are the same sums
      CHECK_REL(o.displacement(n / 2, t)[0], u(n / 2 - 1, 0), tol::kModalSumTwoPathsRel);
    }
  }
  // the analytic derivatives against 8th-order differences (step 1/100 of the top mode)
  for (const int n : {4, 40}) {
    const SpringChainOracle o(valve_spring(n));
    const double h = 0.01 * 2.0 * pi / o.natural_frequency(n);
    for (const int j : {1, n / 2, n}) {
      // within kOracleFdRel of the peak over the samples
      Series velocity("u' of node " + std::to_string(j) + " of " + std::to_string(n), "t [s]");
      Series acceleration("u'' of node " + std::to_string(j) + " of " + std::to_string(n), "t [s]");
      for (int i = 0; i < 40; ++i) {
        const double t = 0.5e-3 + 3.1e-4 * i;
        const std::array<double, 3> u = o.displacement(j, t);
        velocity.add(t, u[1], central_difference([&](double s) { return o.displacement(j, s)[0]; }, t, 1, 4, h));
        acceleration.add(t, u[2], central_difference([&](double s) { return o.displacement(j, s)[1]; }, t, 1, 4, h));
      }
      CHECK_SERIES(velocity.compare({.rel = tol::kOracleFdRel}));
      CHECK_SERIES(acceleration.compare({.rel = tol::kOracleFdRel}));
    }
  }
}

TEST_CASE("spring chain oracle: closed-form modes against an eigen-solver, orthogonality, effective masses",
          "[oracles]") {
  for (const int n : {4, 40}) {
    const SpringChainOracle o(valve_spring(n));
    const double mi = o.node_mass(), ki = o.segment_rate();
    // K = k_i tridiag(-1, 2, -1), M = m_i I: eigenvalues of K / m_i, ascending
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
    for (int j = 0; j < n; ++j) {
      k(j, j) = 2.0 * ki / mi;
      if (j > 0) k(j, j - 1) = k(j - 1, j) = -ki / mi;
    }
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues();
    for (int r = 1; r <= n; ++r) {
      const double w = o.natural_frequency(r);
      CHECK_REL(w * w, lambda(r - 1), tol::kEigenSolverRel);
      CHECK_REL(o.natural_frequency_hz(r), w / (2.0 * pi), tol::kUlpRel);
    }
    // phi_r^T M phi_s = delta_rs ms / 2
    for (int r = 1; r <= n; ++r)
      for (int s = 1; s <= n; ++s) {
        double m = 0.0;
        for (int j = 1; j <= n; ++j) m += mi * o.mode_shape(r, j) * o.mode_shape(s, j);
        CHECK_ABS(m, r == s ? o.modal_mass(r) : 0.0, tol::kModalMassRel * o.modal_mass(r));
      }
    CHECK_REL(o.modal_mass(1), 0.5 * o.chain().mass, tol::kModalMassRel);
    // effective masses: sum_j sin(j z) = cot(z / 2) for odd r, 0 for even, z = r pi / (N + 1),
    // and summed over the modes they give the moving mass N m_i
    double sum = 0.0;
    for (int r = 1; r <= n; ++r) {
      const double cot = 1.0 / std::tan(r * pi / (2.0 * (n + 1)));
      const double expected = r % 2 == 1 ? mi * mi * cot * cot / o.modal_mass(r) : 0.0;
      CHECK_ABS(o.effective_mass(r), expected, tol::kModalMassRel * n * mi);
      sum += o.effective_mass(r);
    }
    CHECK_REL(sum, n * mi, tol::kModalMassRel);
    // the first mode carries (8 / pi^2) (z cot z)^2 of the spring's mass ms, z = pi / (2 (N + 1)),
    // and z cot z = 1 - z^2/3 - z^4/45 - ...: 8 / pi^2 = 81 % (the continuum's) less under 2 z^2 / 3
    const double z = pi / (2.0 * (n + 1)), share = o.effective_mass(1) / o.chain().mass;
    CHECK(share <= 8.0 / (pi * pi));
    CHECK(share >= 8.0 / (pi * pi) * (1.0 - 2.0 * z * z / 3.0));
  }
}

TEST_CASE("spring chain oracle: agrees with a fixed-step RK4 of the chain", "[oracles]") {
  // RK4 at 1/400 of the top mode's period over one cam revolution (phase error per step
  // (w h)^5 / 120 = 8e-11 for the top mode, which carries little); measured 1e-13 m and
  // 2e-8 N (N = 4), 3e-14 m and 1.2e-8 N (N = 10)
  for (const int n : {4, 10}) {
    const SpringChainOracle o(valve_spring(n));
    const double mi = o.node_mass(), ki = o.segment_rate();
    const double h = 2.0 * pi / o.natural_frequency(n) / 400.0;
    const long steps = std::lround(2.0 * pi / o.chain().cam_speed / h);
    auto accel = [&](double t, const Eigen::VectorXd& u) {
      Eigen::VectorXd a(n);
      for (int j = 0; j < n; ++j) {
        const double below = j == 0 ? 0.0 : u(j - 1), above = j == n - 1 ? o.top(t)[0] : u(j + 1);
        a(j) = ki * (above - 2.0 * u(j) + below) / mi;
      }
      return a;
    };
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n);
    Series lift("rk4 node displacements [m] of " + std::to_string(n), "t [s]");
    Series force("rk4 end forces [N] of " + std::to_string(n), "t [s]");
    for (long i = 0; i < steps; ++i) {
      const double t = static_cast<double>(i) * h;
      const Eigen::VectorXd k1u = v, k1v = accel(t, u);
      const Eigen::VectorXd k2u = v + 0.5 * h * k1v, k2v = accel(t + 0.5 * h, u + 0.5 * h * k1u);
      const Eigen::VectorXd k3u = v + 0.5 * h * k2v, k3v = accel(t + 0.5 * h, u + 0.5 * h * k2u);
      const Eigen::VectorXd k4u = v + h * k3v, k4v = accel(t + h, u + h * k3u);
      u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
      v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      if (i % 8 == 0) {
        const double t1 = t + h;
        const Eigen::VectorXd modal = o.displacements(t1).col(0);
        for (int j = 0; j < n; ++j) lift.add(t1, u(j), modal(j));
        force.add(t1, o.chain().preload + ki * (o.top(t1)[0] - u(n - 1)), o.top_force(t1));
        force.add(t1, o.chain().preload + ki * u(0), o.base_force(t1));
      }
    }
    CHECK_SERIES(lift.compare({.abs = tol::kChainRk4LiftAbs}));
    CHECK_SERIES(force.compare({.abs = tol::kChainRk4ForceAbs}));
  }
}

TEST_CASE("spring chain oracle: end forces obey momentum balance and the quasi-static limit", "[oracles]") {
  // F_top - F_base = sum_j m_i u_j'' (the internal masses' momentum)
  const SpringChainOracle o(valve_spring(12));
  for (int i = 1; i <= 30; ++i) {
    const double t = 4.3e-4 * i;
    const double momentum_rate = o.node_mass() * o.displacements(t).col(2).sum();
    const double scale = std::abs(o.top_force(t)) + std::abs(o.base_force(t));
    CHECK_ABS(o.top_force(t) - o.base_force(t), momentum_rate, tol::kResidualRel * scale * 12);
  }
  // a cam far below surge (w = w_1 / 100): the chain follows the top end's ramp shape and
  // both ends carry F0 + k X, up to the surge left by starting from rest, of order
  // (w / w_1)^2 k e
  SpringChain slow = valve_spring(12);
  slow.cam_speed = SpringChainOracle(slow).natural_frequency(1) / 100.0;
  const SpringChainOracle q(slow);
  const double ke = slow.rate * slow.eccentricity;
  for (int i = 1; i <= 30; ++i) {
    const double t = 2.0 * pi / slow.cam_speed * i / 31.0;
    const double static_force = slow.preload + slow.rate * q.top(t)[0];
    CHECK_ABS(q.top_force(t), static_force, tol::kSlowSurgeRel * ke);
    CHECK_ABS(q.base_force(t), static_force, tol::kSlowSurgeRel * ke);
    CHECK_ABS(q.displacement(6, t)[0], q.top(t)[0] * 6.0 / 13.0, tol::kSlowSurgeRel * slow.eccentricity);
  }
}

TEST_CASE("spring chain oracle: frequencies tend to the continuum's (r/2) sqrt(k/ms) as 1/N^2", "[oracles]") {
  // w_r / (r pi sqrt(k/ms)) = sin(z) / z with z = r pi / (2 (N + 1)); the alternating series
  // of sin puts the relative error 1 - sin(z)/z in [z^2/6 (1 - z^2/20), z^2/6]
  const SpringChain s = valve_spring(1);
  CHECK_REL(continuum_frequency_hz(s.rate, s.mass, 1), 577.3502691896, tol::kPrinted13DigitsRel);
  for (int r = 1; r <= 3; ++r) {
    double previous = 0.0;
    int previous_n = 0;
    for (const int n : {4, 40, 400}) {
      const SpringChainOracle o(valve_spring(n));
      const double error = 1.0 - o.natural_frequency_hz(r) / continuum_frequency_hz(s.rate, s.mass, r);
      const double z = r * pi / (2.0 * (n + 1)), bound = z * z / 6.0;
      INFO("r " << r << " N " << n << " relative error " << error << " bound " << bound);
      CHECK(error <= bound * (1.0 + 1e-9));
      CHECK(error >= bound * (1.0 - z * z / 20.0) * (1.0 - 1e-9));
      if (previous_n > 0) {
        // between N = 4 and 40 (and 40 and 400) the error falls by ((N' + 1) / (N + 1))^2
        // to within the z^2/20 terms
        const double ratio = previous / error, expected = std::pow((n + 1.0) / (previous_n + 1.0), 2);
        const double z_prev = r * pi / (2.0 * (previous_n + 1));
        CHECK(ratio <= expected / (1.0 - z * z / 20.0));
        CHECK(ratio >= expected * (1.0 - z_prev * z_prev / 20.0));
      }
      previous = error;
      previous_n = n;
    }
  }
}

TEST_CASE("spring chain oracle: a cam speed equal to a natural frequency is refused", "[oracles]") {
  SpringChain s = valve_spring(6);
  s.cam_speed = SpringChainOracle(s).natural_frequency(2);
  CHECK_THROWS_AS(SpringChainOracle(s), std::domain_error);
  s.cam_speed *= 1.0 + 1e-9;
  CHECK_NOTHROW(SpringChainOracle(s));
}
