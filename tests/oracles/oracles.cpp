#include "oracles/oracles.hpp"

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace camopt::oracles {

namespace {

constexpr double pi = std::numbers::pi;
using Complex = std::complex<double>;

// a constant and the input itself, as motions
Motion constant(double v) { return {v, 0.0, 0.0, 0.0}; }
Motion input(double v) { return {v, 1.0, 0.0, 0.0}; }

// d^n/dt^n of L(t) e^{i th(t)} by leibniz' rule, with the derivatives of E = e^{i th}
//   E' = i th' E,  E'' = (i th'' - th'^2) E,  E''' = (i th''' - 3 th' th'' - i th'^3) E
Complex vector_derivative(const Motion& length, const Motion& angle, int n) {
  const Complex i(0.0, 1.0);
  const double w1 = angle[1], w2 = angle[2], w3 = angle[3];
  const Complex e[4] = {1.0, i * w1, i * w2 - w1 * w1, i * w3 - 3.0 * w1 * w2 - i * w1 * w1 * w1};
  static constexpr double binomial[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  Complex s = 0.0;
  for (int k = 0; k <= n; ++k) s += binomial[n][k] * length[static_cast<std::size_t>(k)] * e[n - k];
  return s * std::polar(1.0, angle[0]);
}

// one vector sign * L e^{i th} of a closed planar loop sum = constant
struct LoopVector {
  double sign = 1.0;
  Motion length, angle;
  enum class Unknown { none, length, angle } unknown = Unknown::none;
};

// derivatives of order 1..3 of the loop's two unknowns (positions already set): the n-th
// derivative of the loop equation is linear in the unknowns' n-th derivatives,
//   sum_unknown coefficient_j x_j^(n) = -(the rest),
// coefficient i L E for an angle and E for a length [raven]; 2x2 real system by cramer.
void differentiate_loop(std::vector<LoopVector>& loop) {
  int u[2] = {-1, -1}, count = 0;
  for (int j = 0; j < static_cast<int>(loop.size()); ++j)
    if (loop[static_cast<std::size_t>(j)].unknown != LoopVector::Unknown::none) u[count++] = j;
  const Complex i(0.0, 1.0);
  Complex coefficient[2];
  for (int k = 0; k < 2; ++k) {
    const LoopVector& v = loop[static_cast<std::size_t>(u[k])];
    const Complex e = std::polar(1.0, v.angle[0]);
    coefficient[k] = v.unknown == LoopVector::Unknown::angle ? v.sign * i * v.length[0] * e : v.sign * e;
  }
  const double det = coefficient[0].real() * coefficient[1].imag() - coefficient[1].real() * coefficient[0].imag();
  for (int n = 1; n <= 3; ++n) {
    Complex rest = 0.0;
    for (auto& v : loop) {
      if (v.unknown == LoopVector::Unknown::angle) v.angle[static_cast<std::size_t>(n)] = 0.0;
      if (v.unknown == LoopVector::Unknown::length) v.length[static_cast<std::size_t>(n)] = 0.0;
      rest += v.sign * vector_derivative(v.length, v.angle, n);
    }
    const Complex rhs = -rest;
    const double x0 = (rhs.real() * coefficient[1].imag() - coefficient[1].real() * rhs.imag()) / det;
    const double x1 = (coefficient[0].real() * rhs.imag() - rhs.real() * coefficient[0].imag()) / det;
    const double x[2] = {x0, x1};
    for (int k = 0; k < 2; ++k) {
      LoopVector& v = loop[static_cast<std::size_t>(u[k])];
      (v.unknown == LoopVector::Unknown::angle ? v.angle : v.length)[static_cast<std::size_t>(n)] = x[k];
    }
  }
}

double angle_of(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }
Eigen::Vector2d unit(double a) { return {std::cos(a), std::sin(a)}; }

Motion minus_start(Motion m, double start) {
  m[0] -= start;
  return m;
}

}  // namespace

double wrap_angle(double a) { return std::remainder(a, 2.0 * pi); }

double polar_radius_of_curvature(double r, double r1, double r2) {
  const double s = r * r + r1 * r1;
  return s * std::sqrt(s) / (r * r + 2.0 * r1 * r1 - r * r2);
}

// ---- (a) ----
Motion EccentricFlatFollower::face_height(double theta) const {
  const double phi = theta + phase, e = eccentricity, s = std::sin(phi), c = std::cos(phi);
  return {e * s + disc_radius, e * c, -e * s, -e * c};
}
Motion EccentricFlatFollower::lift(double theta) const { return minus_start(face_height(theta), face_height(0)[0]); }
double EccentricFlatFollower::contact_x(double theta) const { return eccentricity * std::cos(theta + phase); }

// ---- (b) ----
Motion EccentricOffsetRoller::centre_height(double theta) const {
  const double phi = theta + phase, e = eccentricity, s = std::sin(phi), c = std::cos(phi);
  const double L = disc_radius + roller_radius;
  const double u0 = offset - e * c, u1 = e * s, u2 = e * c, u3 = -e * s;
  const double w0 = std::sqrt(L * L - u0 * u0);
  const double w1 = -u0 * u1 / w0;
  const double w2 = -(u1 * u1 + u0 * u2 + w1 * w1) / w0;
  const double w3 = -(3.0 * u1 * u2 + u0 * u3 + 3.0 * w1 * w2) / w0;
  return {e * s + w0, e * c + w1, -e * s + w2, -e * c + w3};
}
Motion EccentricOffsetRoller::lift(double theta) const { return minus_start(centre_height(theta), centre_height(0)[0]); }
double EccentricOffsetRoller::pressure_angle(double theta) const {
  const Motion y = centre_height(theta);
  return std::atan(std::abs(y[1] - offset) / y[0]);
}
double EccentricOffsetRoller::roller_speed(double theta) const {
  const double phi = theta + phase, e = eccentricity, L = disc_radius + roller_radius;
  const double u = offset - e * std::cos(phi), w = std::sqrt(L * L - u * u);
  const double alpha1 = -e * std::sin(phi) / w;
  return 1.0 + (alpha1 - 1.0) * L / roller_radius;
}

// ---- (d) ----
namespace {
struct FreudensteinRoots {
  bool real = false;
  double angle[2] = {0, 0};  // rocker angle for branch +1, -1
};
FreudensteinRoots freudenstein(const FourBar& f, double crank_angle) {
  const Eigen::Vector2d g = f.rocker_pivot - f.crank_pivot;
  const double d = g.norm(), ground = angle_of(g), a = f.crank, b = f.coupler, c = f.rocker;
  const double t2 = crank_angle - ground, c2 = std::cos(t2), s2 = std::sin(t2);
  const double K1 = d / a, K2 = d / c, K3 = (a * a - b * b + c * c + d * d) / (2.0 * a * c);
  const double A = c2 - K1 - K2 * c2 + K3, B = -2.0 * s2, C = K1 - (K2 + 1.0) * c2 + K3;
  const double disc = B * B - 4.0 * A * C;
  FreudensteinRoots r;
  if (!(disc >= 0.0)) return r;
  r.real = true;
  const double sq = std::sqrt(disc);
  for (int k = 0; k < 2; ++k) {
    const double sigma = k == 0 ? 1.0 : -1.0;
    // tan(th4/2) = (-B + sigma sq)/(2A) = 2C/(-B - sigma sq): pick the form without cancellation
    const double y = sigma * B <= 0.0 ? -B + sigma * sq : 2.0 * C;
    const double x = sigma * B <= 0.0 ? 2.0 * A : -B - sigma * sq;
    r.angle[k] = wrap_angle(2.0 * std::atan2(y, x) + ground);
  }
  return r;
}
}  // namespace

bool FourBar::assembles(double crank_angle) const { return freudenstein(*this, crank_angle).real; }

FourBar::State FourBar::solve(double crank_angle) const {
  const FreudensteinRoots roots = freudenstein(*this, crank_angle);
  const double th4 = roots.angle[branch > 0 ? 0 : 1];
  const Eigen::Vector2d A = crank_pivot + crank * unit(crank_angle);
  const Eigen::Vector2d B = rocker_pivot + rocker * unit(th4);
  const double th3 = angle_of(B - A);
  std::vector<LoopVector> loop = {
      {1.0, constant(crank), input(crank_angle), LoopVector::Unknown::none},
      {1.0, constant(coupler), constant(th3), LoopVector::Unknown::angle},
      {-1.0, constant(rocker), constant(th4), LoopVector::Unknown::angle},
  };
  differentiate_loop(loop);
  return {loop[1].angle, loop[2].angle};
}

int FourBar::branch_through(double crank_angle, double rocker_angle) const {
  const FreudensteinRoots roots = freudenstein(*this, crank_angle);
  return std::abs(wrap_angle(roots.angle[0] - rocker_angle)) <= std::abs(wrap_angle(roots.angle[1] - rocker_angle))
             ? 1
             : -1;
}

// ---- (c) ----
FourBar EccentricOscillatingRoller::linkage() const {
  return {Eigen::Vector2d(0, 0), arm_pivot, eccentricity, disc_radius + roller_radius, arm_length, branch};
}
Motion EccentricOscillatingRoller::arm_angle(double theta) const { return linkage().solve(theta + phase).rocker_angle; }
Motion EccentricOscillatingRoller::lift(double theta) const {
  Motion m = arm_angle(theta);
  m[0] = wrap_angle(m[0] - arm_angle(0)[0]);
  return m;
}
double EccentricOscillatingRoller::pressure_angle(double theta) const {
  const FourBar::State s = linkage().solve(theta + phase);
  return std::acos(std::min(1.0, std::abs(std::sin(s.coupler_angle[0] - s.rocker_angle[0]))));
}
double EccentricOscillatingRoller::roller_speed(double theta) const {
  const FourBar::State s = linkage().solve(theta + phase);
  return 1.0 + (s.coupler_angle[1] - 1.0) * (disc_radius + roller_radius) / roller_radius - s.rocker_angle[1];
}

// ---- (e) ----
bool SliderCrank::assembles(double crank_angle) const {
  const Eigen::Vector2d q = crank_pivot + crank * unit(crank_angle) - slide_point;
  const double perp = slide_direction.x() * q.y() - slide_direction.y() * q.x();
  return rod * rod - perp * perp >= 0.0;
}

SliderCrank::State SliderCrank::solve(double crank_angle) const {
  const Eigen::Vector2d A = crank_pivot + crank * unit(crank_angle);
  const Eigen::Vector2d q = A - slide_point;
  const double along = slide_direction.dot(q);
  const double perp = slide_direction.x() * q.y() - slide_direction.y() * q.x();
  const double x = along + branch * std::sqrt(rod * rod - perp * perp);
  const Eigen::Vector2d B = slide_point + x * slide_direction;
  std::vector<LoopVector> loop = {
      {1.0, constant(crank), input(crank_angle), LoopVector::Unknown::none},
      {1.0, constant(rod), constant(angle_of(B - A)), LoopVector::Unknown::angle},
      {-1.0, constant(x), constant(angle_of(slide_direction)), LoopVector::Unknown::length},
  };
  differentiate_loop(loop);
  return {loop[1].angle, loop[2].length};
}

SliderCrank::State SliderCrank::invert(double slider_x) const {
  const Eigen::Vector2d B = slide_point + slider_x * slide_direction;
  const Eigen::Vector2d D = B - crank_pivot;
  const double rho = D.norm();
  const double cos_beta = (rho * rho + crank * crank - rod * rod) / (2.0 * crank * rho);
  const double th2 = angle_of(D) + crank_branch * std::acos(cos_beta);
  const Eigen::Vector2d A = crank_pivot + crank * unit(th2);
  std::vector<LoopVector> loop = {
      {1.0, constant(crank), constant(th2), LoopVector::Unknown::angle},
      {1.0, constant(rod), constant(angle_of(B - A)), LoopVector::Unknown::angle},
      {-1.0, input(slider_x), constant(angle_of(slide_direction)), LoopVector::Unknown::none},
  };
  differentiate_loop(loop);
  return {loop[1].angle, loop[0].angle};
}

int SliderCrank::branch_through(double crank_angle, double slider_x) const {
  SliderCrank s = *this;
  s.branch = 1;
  const double plus = s.solve(crank_angle).slider[0];
  s.branch = -1;
  const double minus = s.solve(crank_angle).slider[0];
  return std::abs(plus - slider_x) <= std::abs(minus - slider_x) ? 1 : -1;
}

int SliderCrank::crank_branch_through(double slider_x, double crank_angle) const {
  SliderCrank s = *this;
  s.crank_branch = 1;
  const double plus = s.invert(slider_x).slider[0];
  s.crank_branch = -1;
  const double minus = s.invert(slider_x).slider[0];
  return std::abs(wrap_angle(plus - crank_angle)) <= std::abs(wrap_angle(minus - crank_angle)) ? 1 : -1;
}

// ---- (f) ----
Motion GearPair::output(double input_angle) const { return {ratio * input_angle, ratio, 0.0, 0.0}; }
Motion GearPair::input(double output_angle) const { return {output_angle / ratio, 1.0 / ratio, 0.0, 0.0}; }
Motion RackPinion::rack(double pinion_angle) const { return {pitch_radius * pinion_angle, pitch_radius, 0.0, 0.0}; }
Motion RackPinion::pinion(double rack_travel) const {
  return {rack_travel / pitch_radius, 1.0 / pitch_radius, 0.0, 0.0};
}

// ---- (g) ----
double FlatFollowerPolarCam::contact_polar_angle(double theta) const {
  const double psi = pi / 2.0 - orientation - theta;
  double r[4];
  // global scan for the maximiser of r(phi) cos(phi - psi), then newton on its stationarity
  // condition g(phi) = r' cos(phi - psi) - r sin(phi - psi) = 0
  constexpr int samples = 720;
  double best = -1e300, phi = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double p = 2.0 * pi * k / samples;
    radius(p, r);
    const double v = r[0] * std::cos(p - psi);
    if (v > best) best = v, phi = p;
  }
  for (int it = 0; it < 60; ++it) {
    radius(phi, r);
    const double c = std::cos(phi - psi), s = std::sin(phi - psi);
    const double g = r[1] * c - r[0] * s;
    const double dg = (r[2] - r[0]) * c - 2.0 * r[1] * s;
    const double step = g / dg;
    phi -= step;
    if (std::abs(step) < 1e-16) break;
  }
  return phi;
}

Motion FlatFollowerPolarCam::face_height(double theta) const {
  const double psi = pi / 2.0 - orientation - theta;
  const double phi = contact_polar_angle(theta);
  double r[4];
  radius(phi, r);
  const double h0 = r[0] * std::cos(phi - psi), h1 = r[0] * std::sin(phi - psi);
  const double S = r[0] * r[0] + r[1] * r[1];
  const double D = r[0] * r[0] + 2.0 * r[1] * r[1] - r[0] * r[2];
  const double dD = 2.0 * r[0] * r[1] + 3.0 * r[1] * r[2] - r[0] * r[3];
  const double rho = S * std::sqrt(S) / D;
  const double drho_dphi = (3.0 * std::sqrt(S) * (r[0] * r[1] + r[1] * r[2]) * D - S * std::sqrt(S) * dD) / (D * D);
  const double h2 = rho - h0;
  const double h3 = drho_dphi * S / D - h1;
  return {h0, -h1, h2, -h3};
}

Motion FlatFollowerPolarCam::lift(double theta) const { return minus_start(face_height(theta), face_height(0)[0]); }

double FlatFollowerPolarCam::radius_of_curvature(double theta) const {
  double r[4];
  radius(contact_polar_angle(theta), r);
  return polar_radius_of_curvature(r[0], r[1], r[2]);
}

double FlatFollowerPolarCam::contact_x(double theta) const { return face_height(theta)[1]; }

}  // namespace camopt::oracles
