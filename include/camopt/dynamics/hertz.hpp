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
