#include "oracles/spring_chain_oracle.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace camopt::oracles {

namespace {
constexpr double pi = std::numbers::pi;
}  // namespace

SpringChainOracle::SpringChainOracle(const SpringChain& chain) : chain_(chain) {
  if (chain.masses < 1 || !(chain.rate > 0.0) || !(chain.mass > 0.0))
    throw std::invalid_argument("spring chain oracle: needs N >= 1, k > 0, ms > 0");
  const int n = chain.masses;
  for (int r = 1; r <= n; ++r) {
    const double w = 2.0 * std::sqrt(segment_rate() / node_mass()) * std::sin(r * pi / (2.0 * (n + 1)));
    if (w == chain.cam_speed) throw std::domain_error("spring chain oracle: cam speed equals a natural frequency");
    omega_.push_back(w);
    gain_.push_back(segment_rate() * mode_shape(r, n) / modal_mass(r));
  }
}

double SpringChainOracle::node_mass() const { return chain_.mass / (chain_.masses + 1); }
double SpringChainOracle::segment_rate() const { return chain_.rate * (chain_.masses + 1); }

double SpringChainOracle::natural_frequency(int r) const { return omega_[static_cast<std::size_t>(r - 1)]; }
double SpringChainOracle::natural_frequency_hz(int r) const { return natural_frequency(r) / (2.0 * pi); }

// the angle j r pi / (N + 1) reduced modulo 2 pi in integers first: at N = 400 it reaches
// 1250 rad, whose rounding (1e-13) would break the shapes' orthogonality at that level
double SpringChainOracle::mode_shape(int r, int j) const {
  const long n1 = chain_.masses + 1, k = (static_cast<long>(j) * r) % (2 * n1);
  return std::sin(pi * static_cast<double>(k) / static_cast<double>(n1));
}

// sum_j sin^2(j r pi / (N + 1)) = (N + 1) / 2 for r = 1..N
double SpringChainOracle::modal_mass(int) const { return 0.5 * node_mass() * (chain_.masses + 1); }

double SpringChainOracle::effective_mass(int r) const {
  double l = 0.0;
  for (int j = 1; j <= chain_.masses; ++j) l += node_mass() * mode_shape(r, j);
  return l * l / modal_mass(r);
}

std::array<double, 3> SpringChainOracle::top(double t) const {
  const double w = chain_.cam_speed, e = chain_.eccentricity;
  return {e * (1.0 - std::cos(w * t)), e * w * std::sin(w * t), e * w * w * std::cos(w * t)};
}

// q = G e [(1 - cos wr t) / wr^2 - beat], beat = (cos w t - cos wr t) / (wr^2 - w^2),
// q' = G e w (sin w t - (w / wr) sin wr t) / (wr^2 - w^2),  q'' = G e w^2 beat,
// the differences of cosines as products of sines (no cancellation near t = 0 or near
// resonance; q = q' = q'' = 0 at t = 0 exactly). every sine and cosine is of the same two
// rounded phases wr t and w t (their exact halves, sums and differences): wr t reaches
// 1e4 rad at N = 400, and a separately rounded (wr + w) t / 2 would put the terms out of
// step by 1e-12 rad, q'' + wr^2 q by 1e-12 of each term
std::array<double, 3> SpringChainOracle::modal(int r, double t) const {
  const double wr = natural_frequency(r), w = chain_.cam_speed;
  const double g = gain_[static_cast<std::size_t>(r - 1)] * chain_.eccentricity;
  const double d = (wr - w) * (wr + w);
  const double pr = wr * t, pw = w * t;
  const double sr = std::sin(0.5 * pr);
  const double step = 2.0 * sr * sr / (wr * wr);
  const double beat = 2.0 * std::sin(0.5 * (pr + pw)) * std::sin(0.5 * (pr - pw)) / d;
  return {g * (step - beat), g * w * (std::sin(pw) - w / wr * std::sin(pr)) / d, g * w * w * beat};
}

Eigen::Matrix<double, Eigen::Dynamic, 3> SpringChainOracle::displacements(double t) const {
  const int n = chain_.masses;
  Eigen::Matrix<double, Eigen::Dynamic, 3> u = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
  for (int r = 1; r <= n; ++r) {
    const std::array<double, 3> q = modal(r, t);
    for (int j = 1; j <= n; ++j) {
      const double phi = mode_shape(r, j);
      for (int k = 0; k < 3; ++k) u(j - 1, k) += q[static_cast<std::size_t>(k)] * phi;
    }
  }
  return u;
}

std::array<double, 3> SpringChainOracle::displacement(int j, double t) const {
  if (j == 0) return {0.0, 0.0, 0.0};
  if (j == chain_.masses + 1) return top(t);
  std::array<double, 3> u = {0.0, 0.0, 0.0};
  for (int r = 1; r <= chain_.masses; ++r) {
    const std::array<double, 3> q = modal(r, t);
    const double phi = mode_shape(r, j);
    for (std::size_t k = 0; k < 3; ++k) u[k] += q[k] * phi;
  }
  return u;
}

double SpringChainOracle::top_force(double t) const {
  return chain_.preload + segment_rate() * (top(t)[0] - displacement(chain_.masses, t)[0]);
}

double SpringChainOracle::base_force(double t) const {
  return chain_.preload + segment_rate() * displacement(1, t)[0];
}

double continuum_frequency_hz(double rate, double mass, int r) { return 0.5 * r * std::sqrt(rate / mass); }

}  // namespace camopt::oracles
