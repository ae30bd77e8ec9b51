#pragma once
// exact response of a helical spring lumped into a chain of equal masses (spring surge),
// by modal superposition. the flexible valvetrain model's surge masses are tested against
// it; nothing here uses camopt library code (standard library and Eigen only).
//
// model (SI: m, s, kg, N): a spring of rate k and mass ms as N internal masses
// m_i = ms / (N + 1) joined by N + 1 segments of rate k_i = (N + 1) k. base fixed, u_0 = 0;
// top end prescribed, u_{N+1} = X(t) = e (1 - cos(w t)); undamped; at rest with every
// u_j = 0 at t = 0. segment j (between u_{j-1} and u_j) carries F0 + k_i (u_j - u_{j-1}),
// compression positive, so
//   m_i u_j'' = k_i (u_{j+1} - 2 u_j + u_{j-1}),   j = 1..N.
// modes of the fixed-fixed chain [meirovitch]: shapes phi_r(j) = sin(j r pi / (N + 1)),
// w_r = 2 sqrt(k_i / m_i) sin(r pi / (2 (N + 1))), modal mass m_i (N + 1) / 2 = ms / 2.
// each modal coordinate, u = sum_r q_r phi_r, obeys
//   q_r'' + w_r^2 q_r = G_r X(t),   G_r = k_i phi_r(N) / (ms / 2),
// from rest: q_r = G_r e [(1 - cos w_r t) / w_r^2 - (cos w t - cos w_r t) / (w_r^2 - w^2)].
// as N grows, w_r tends to the continuum's r pi sqrt(k / ms), f_r = (r / 2) sqrt(k / ms)
// [wahl]: w_r / (r pi sqrt(k / ms)) = sin(z) / z, z = r pi / (2 (N + 1)).
//
// references
//   [meirovitch] L. Meirovitch, Fundamentals of Vibrations, McGraw-Hill, 2001 (lumped
//                fixed-fixed chains, orthogonality of modes, modal superposition).
//   [wahl]       A. M. Wahl, Mechanical Springs, 2nd ed., McGraw-Hill, 1963 (surge: the
//                natural frequencies of a spring fixed at both ends, f_r = (r / 2) sqrt(k / m)).
#include <Eigen/Core>
#include <array>
#include <vector>

namespace camopt::oracles {

struct SpringChain {
  double rate = 0;          // k of the whole spring [N/m]
  double mass = 0;          // ms [kg]
  int masses = 1;           // N internal masses
  double preload = 0;       // F0 [N]
  double eccentricity = 0;  // e of the top end's motion [m]
  double cam_speed = 0;     // w [rad/s]
};

class SpringChainOracle {
 public:
  // throws std::domain_error when w equals some w_r exactly (undamped resonance)
  explicit SpringChainOracle(const SpringChain& chain);

  const SpringChain& chain() const { return chain_; }
  double node_mass() const;     // m_i [kg]
  double segment_rate() const;  // k_i [N/m]

  // mode r = 1..N
  double natural_frequency(int r) const;     // w_r [rad/s]
  double natural_frequency_hz(int r) const;  // [Hz]
  double mode_shape(int r, int j) const;     // phi_r(j), j = 0..N+1
  double modal_mass(int r) const;            // phi_r^T M phi_r = ms / 2 [kg]
  // effective mass of mode r under uniform translation, (phi_r^T M 1)^2 / modal mass [kg];
  // summed over the modes it gives the moving mass N m_i
  double effective_mass(int r) const;

  std::array<double, 3> top(double t) const;          // X, X', X'' [m, m/s, m/s^2]
  std::array<double, 3> modal(int r, double t) const;  // q_r, q_r', q_r''
  // u_j, u_j', u_j'' of every internal mass: row j - 1 for j = 1..N
  Eigen::Matrix<double, Eigen::Dynamic, 3> displacements(double t) const;
  std::array<double, 3> displacement(int j, double t) const;  // j = 0..N+1
  double top_force(double t) const;   // F0 + k_i (X - u_N) [N]
  double base_force(double t) const;  // F0 + k_i u_1 [N]

 private:
  SpringChain chain_;
  std::vector<double> omega_, gain_;  // w_r, G_r; index r - 1
};

// the continuum spring's fixed-fixed natural frequency f_r = (r / 2) sqrt(k / ms) [Hz]
double continuum_frequency_hz(double rate, double mass, int r);

}  // namespace camopt::oracles
