#pragma once
// Hertz line contact (two parallel cylinders, or a cylinder on a flat) under a normal load
// F over a length L: Johnson, Contact Mechanics, 1985, sec. 4.2 (eqs. 4.43-4.45) with
// P = F / L per unit length:
//   half-width b = sqrt(4 P R* / (pi E*)),  max pressure p0 = sqrt(P E* / (pi R*)),
//   1/R* = k_a + k_b (curvatures, + convex, - concave, 0 flat), 1/E* as in contact_modulus.
namespace camopt::dynamics {

struct HertzLine {
  double max_pressure = 0.0;  // p0 [N/mm^2 = MPa]
  double half_width = 0.0;    // b [mm]
};

// force [N], length [mm], e_star [N/mm^2], curvature_sum = 1/R* [1/mm]. A non-positive
// force or curvature sum (conforming surfaces) gives zero pressure and width.
HertzLine hertz_line(double force, double length, double e_star, double curvature_sum);

}  // namespace camopt::dynamics

namespace camopt::dynamics {

// approach (mutual deflection) of a line contact under load, Johnson 1985 sec. 4.2 / 5.?
// for two cylinders: delta = (P / (pi E*)) (2 ln(4 R*/b) - 1), P = F / L. With
// a = F / (pi L E*) [mm] and b^2 = 4 R* a this reads delta = a (ln(4 R*/a) - 1), valid
// while a < 4 R*/e^2 (dDelta/da > 0). force [N], length L [mm], e_star [N/mm^2],
// reduced_radius R* [mm]; returns [mm] (0 for F <= 0).
double line_contact_approach(double force, double length, double e_star, double reduced_radius);
// the inverse: the force [N] at an approach [mm] (Newton on a; 0 for approach <= 0).
// The law stiffens with load: dF/dDelta = pi L E* / (ln(4 R*/a) - 2).
double line_contact_force(double approach, double length, double e_star, double reduced_radius);
// the same, Newton started from load_length_mm a = F / (pi L E*) when 0 < a < 4 R* (the last
// solution of a contact whose approach changes little between calls: ~half the logarithms;
// a start too far off falls back to the cold start); a returns the solution (0 for
// approach <= 0). Equal to the cold start to rounding.
double line_contact_force(double approach, double length, double e_star, double reduced_radius,
                          double& load_length_mm);
// tangent stiffness dF/dDelta at a force [N/mm]
double line_contact_tangent_stiffness(double force, double length, double e_star, double reduced_radius);
// secant stiffness F / delta at a force [N/mm] (mode (b) linearisation)
double line_contact_secant_stiffness(double force, double length, double e_star, double reduced_radius);
// elastic energy stored at a force: int_0^delta F d(delta) = F^2/(2 pi L E*) (ln(4R*/a) - 3/2) [N mm]
double line_contact_energy(double force, double length, double e_star, double reduced_radius);

// Hunt-Crossley contact damping (Hunt & Crossley, J. Appl. Mech. 42 (1975) 440-445): the
// dissipative force is proportional to the elastic one, F = F_e (1 + 3/2 alpha d(delta)/dt),
// so it vanishes at touch-down (no force jump) and the coefficient of restitution of an
// impact at speed v is e = 1 - alpha v to first order. Clamped at 0 (no tension while the
// bodies part faster than 2 / (3 alpha)). elastic [N], rate [mm/s], alpha [s/mm].
inline double hunt_crossley_force(double elastic, double rate, double alpha) {
  const double f = elastic * (1.0 + 1.5 * alpha * rate);
  return f > 0.0 ? f : 0.0;
}
// alpha [s/mm] giving restitution e at the impact speed [mm/s] (e = 1 - alpha v)
inline double hunt_crossley_alpha(double restitution, double impact_speed) {
  return (1.0 - restitution) / impact_speed;
}

}  // namespace camopt::dynamics
