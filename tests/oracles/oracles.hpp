#pragma once
// closed-form reference mechanisms for the accuracy tests of the kinematics kernel
// (STYLE.md §8; the idea of drake's multibody/benchmarks). every oracle gives a
// displacement and its first three derivatives with respect to its input [per rad or per
// mm], derived analytically and written with plain doubles: nothing here uses camopt::Jet
// or the kernel, so the two cannot share a mistake.
//
// frames: each oracle works in its own textbook frame, stated in its comment. tests place
// the drawing of a mechanism anywhere by a rigid transform; displacements and rotation
// angles do not change under it.
//
// references
//   [norton]  R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed., Industrial
//             Press, 2009 (eccentric cams, roller and flat-faced followers, pressure angle,
//             radius of curvature of a flat-follower cam rho = s + s'' + base radius).
//   [uicker]  J. J. Uicker, G. R. Pennock, J. E. Shigley, Theory of Machines and Mechanisms,
//             4th ed., Oxford, 2011, ch. 2-4 (loop-closure position analysis, complex-algebra
//             velocity and acceleration analysis of the four-bar and slider-crank).
//   [freud]   F. Freudenstein, "Approximate synthesis of four-bar linkages", Trans. ASME 77
//             (1955) 853-861 (the displacement equation of the four-bar).
//   [raven]   F. H. Raven, "Velocity and acceleration analysis of plane and space mechanisms
//             by means of independent-position equations", J. Appl. Mech. 25 (1958) 1-6
//             (differentiating the complex loop equation; carried here to jerk).
#include <Eigen/Core>
#include <array>
#include <functional>

namespace camopt::oracles {

// a quantity and its first three derivatives with respect to the input: m[k] = d^k x / dt^k
using Motion = std::array<double, 4>;

// ---------------------------------------------------------------------------------------
// (a) eccentric disc cam + centred translating flat-faced follower.
// frame: cam pivot at the origin, cam turning counter-clockwise by theta, follower moving
// along +y with its face normal to y, resting on top of the disc. disc centre at
// e (cos phi, sin phi), phi = theta + phase, so the face height is
//   y(theta) = e sin(phi) + R                       (scotch yoke: simple harmonic motion)
// and the lift from the drawing (theta = 0) is s = e (sin phi - sin phase) [norton].
struct EccentricFlatFollower {
  double disc_radius = 0;   // R [mm]
  double eccentricity = 0;  // e [mm]
  double phase = 0;         // polar angle of the disc centre at theta = 0 [rad]

  Motion face_height(double theta) const;  // [mm], per rad
  Motion lift(double theta) const;         // face_height(theta) - face_height(0)
  // x of the contact point on the face: directly above the disc centre, e cos(phi) = s'
  double contact_x(double theta) const;
};

// ---------------------------------------------------------------------------------------
// (b) eccentric disc cam + offset translating roller follower.
// frame: cam pivot at the origin, follower axis the line x = offset, follower moving along
// +y. the roller centre (offset, Y) stays at distance L = R + r from the disc centre
// e (cos phi, sin phi), phi = theta + phase, on the upper branch:
//   Y(theta) = e sin(phi) + w,   w = sqrt(L^2 - u^2),   u = offset - e cos(phi)
// derivatives of w from w^2 + u^2 = L^2 differentiated three times:
//   w' = -u u'/w,  w'' = -(u'^2 + u u'' + w'^2)/w,  w''' = -(3 u' u'' + u u''' + 3 w' w'')/w.
struct EccentricOffsetRoller {
  double disc_radius = 0;    // R [mm]
  double eccentricity = 0;   // e [mm]
  double phase = 0;          // [rad]
  double roller_radius = 0;  // r [mm]
  double offset = 0;         // follower axis x [mm]

  Motion centre_height(double theta) const;  // Y [mm]
  Motion lift(double theta) const;           // Y(theta) - Y(0)
  // pressure angle [rad]: the common normal passes through the roller centre and the
  // instant centre (s', 0) of cam and follower [norton], so tan(alpha) = |s' - offset| / Y
  double pressure_angle(double theta) const;
  // perfect rolling: in the cam frame the roller centre circles the disc centre at rate
  // (alpha' - 1), alpha the direction disc centre -> roller centre, alpha' = -e sin(phi)/w;
  // a circle r rolling outside a circle R spins (R + r)/r times as fast as its centre
  // circles, so omega = 1 + (alpha' - 1)(R + r)/r [rad per rad of cam]
  double roller_speed(double theta) const;
};

// ---------------------------------------------------------------------------------------
// (d) four-bar linkage: crank O2-A (length a), coupler A-B (b), rocker O4-B (c), the
// loop O2 + a e^{i th2} + b e^{i th3} = O4 + c e^{i th4} with absolute angles.
// position by freudenstein's equation [freud] in the frame with the ground O2 -> O4 on
// +x: K1 cos th4 - K2 cos th2 + K3 = cos(th2 - th4), K1 = d/a, K2 = d/c,
// K3 = (a^2 - b^2 + c^2 + d^2)/(2 a c), solved by tan(th4/2) = (-B + branch sqrt(B^2 - 4AC))/(2A),
// A = cos th2 - K1 - K2 cos th2 + K3, B = -2 sin th2, C = K1 - (K2 + 1) cos th2 + K3
// (the root taken in its cancellation-free form). coupler angle from the loop; derivatives
// by differentiating the loop equation [raven, uicker].
// driving the rocker is the same linkage seen from O4: FourBar{O4, O2, c, b, a}.
struct FourBar {
  Eigen::Vector2d crank_pivot{0, 0}, rocker_pivot{0, 0};
  double crank = 0, coupler = 0, rocker = 0;  // a, b, c [mm]
  int branch = 1;                             // +1 / -1: the two assemblies

  struct State {
    Motion coupler_angle, rocker_angle;  // absolute [rad], per rad of crank
  };
  bool assembles(double crank_angle) const;
  State solve(double crank_angle) const;
  // the branch whose rocker angle at crank_angle is nearest rocker_angle (a drawing)
  int branch_through(double crank_angle, double rocker_angle) const;
};

// ---------------------------------------------------------------------------------------
// (c) eccentric disc cam + oscillating roller follower (arm pivot P, arm length l, roller
// r). triangle pivot - disc centre - roller centre: the roller centre lies on the circle
// of radius R + r about the disc centre and on the circle l about P (law of cosines). it
// is the four-bar {cam pivot, P, e, R + r, l} with crank angle theta + phase [norton:
// the effective linkage of a circle-arc cam]; branch as in FourBar.
struct EccentricOscillatingRoller {
  double disc_radius = 0, eccentricity = 0, phase = 0, roller_radius = 0;
  Eigen::Vector2d arm_pivot{0, 0};
  double arm_length = 0;
  int branch = 1;

  FourBar linkage() const;
  Motion arm_angle(double theta) const;  // absolute angle of P -> roller centre [rad]
  Motion lift(double theta) const;       // arm_angle(theta) - arm_angle(0) [rad]
  // pressure angle at the roller centre (the trace point [uicker ch. 6]): between the
  // normal (disc centre -> roller centre) and the roller centre's velocity (normal to the
  // arm); 90 deg minus the transmission angle of the effective four-bar
  double pressure_angle(double theta) const;
  // roller spin relative to the arm [rad per rad of cam]: 1 + (alpha' - 1)(R + r)/r - psi'
  // with alpha the coupler angle and psi the arm angle (see EccentricOffsetRoller)
  double roller_speed(double theta) const;
};

// ---------------------------------------------------------------------------------------
// (e) offset slider-crank: crank O2-A (a), connecting rod A-B (b), slider pin
// B = S0 + x u on the line through S0 with unit direction u [uicker]:
//   x = u.(A - S0) + branch sqrt(b^2 - (u x (A - S0))^2)
// inversion (driving the slider): crank angle from the triangle O2 - A - B,
//   th2 = atan2(B - O2) + branch acos((|B - O2|^2 + a^2 - b^2) / (2 a |B - O2|)).
// derivatives of both by differentiating O2 + a e^{i th2} + b e^{i th3} = S0 + x u [raven].
struct SliderCrank {
  Eigen::Vector2d crank_pivot{0, 0};
  double crank = 0, rod = 0;  // a, b [mm]
  Eigen::Vector2d slide_point{0, 0}, slide_direction{1, 0};  // S0 [mm], u (unit)
  int branch = 1;        // slider: which intersection of the rod circle with the line
  int crank_branch = 1;  // inversion: which side of O2 -> B the crank pin lies

  struct State {
    Motion rod_angle;  // absolute [rad]
    Motion slider;     // x [mm] (forward) or crank angle [rad] (inverse), per input
  };
  bool assembles(double crank_angle) const;
  State solve(double crank_angle) const;   // slider = x [mm], per rad of crank
  State invert(double slider_x) const;     // slider = crank angle [rad], per mm of slider
  int branch_through(double crank_angle, double slider_x) const;
  int crank_branch_through(double slider_x, double crank_angle) const;
};

// ---------------------------------------------------------------------------------------
// (f) gear pair (output angle = ratio * input angle) and rack and pinion (rack travel =
// pitch radius * pinion angle), each driven from either end.
struct GearPair {
  double ratio = 1;
  Motion output(double input_angle) const;
  Motion input(double output_angle) const;
};
struct RackPinion {
  double pitch_radius = 1;  // [mm]
  Motion rack(double pinion_angle) const;  // [mm]
  Motion pinion(double rack_travel) const; // [rad]
};

// ---------------------------------------------------------------------------------------
// (g) direct-acting flat tappet on a general convex polar cam r(phi).
// frame: cam pivot at the origin, follower along +y, face normal to y; the profile's 0 axis
// at angle `orientation` at theta = 0. the face height is the support function
//   h(psi) = max_phi r(phi) cos(phi - psi),   psi = pi/2 - orientation - theta,
// its maximiser phi* solves tan(phi* - psi) = r'/r (the contact normal), and by the
// envelope relations [norton: rho = s + s'' + base radius]
//   h' = r sin(phi* - psi),   h + h'' = rho = (r^2 + r'^2)^{3/2} / (r^2 + 2 r'^2 - r r''),
//   h''' = rho_phi dphi*/dpsi - h',   dphi*/dpsi = (r^2 + r'^2) / (r^2 + 2 r'^2 - r r'').
// with d/dtheta = -d/dpsi: y' = -h', y'' = h'', y''' = -h'''.
// the contact point lies at x = -h'(psi) = y' along the face, and on a cam turning at unit
// rate the material points slide past each other at the face height y (see the test).
struct FlatFollowerPolarCam {
  // r and its first three derivatives at polar angle phi [rad] -> out[0..3] [mm per rad^k]
  std::function<void(double phi, double* out)> radius;
  double orientation = 0;  // [rad]

  double contact_polar_angle(double theta) const;  // phi* [rad]
  Motion face_height(double theta) const;          // [mm], per rad
  Motion lift(double theta) const;                 // face_height(theta) - face_height(0)
  double radius_of_curvature(double theta) const;  // of the cam at the contact [mm]
  double contact_x(double theta) const;            // along the face [mm]
};

// polar radius of curvature (r^2 + r'^2)^{3/2} / (r^2 + 2 r'^2 - r r'') from r, r', r''
double polar_radius_of_curvature(double r, double r1, double r2);

// wrap an angle difference into (-pi, pi]
double wrap_angle(double a);

}  // namespace camopt::oracles
