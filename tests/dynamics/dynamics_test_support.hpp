#pragma once
// shared designs of the dynamics tests (built in code, like the kinematics tests)
#include <cmath>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "kinematics/kinematics_test_support.hpp"
#include "support/compare.hpp"

namespace camopt::dyn_test {

inline MaterialSpec steel() {
  MaterialSpec m;
  m.name = "steel";
  m.youngs_modulus_GPa = 210;
  m.poisson_ratio = 0.3;
  return m;
}

// direct-acting valve: eccentric disc (R 18, e 4) on a flat tappet (mass 0.07 kg, steel
// line contact 8 mm wide), valve spring rate [N/mm] and preload [N]
inline DesignSpec direct_valve(double rate_N_per_mm, double preload_N) {
  using namespace kin_test;
  const oracles::EccentricFlatFollower o{18, 4, -90 * deg};
  const double h = o.face_height(0)[0];
  DesignSpec d = design("direct_valve", "cam", "tappet");
  d.nodes = {rotational("cam", {0, 0}), translational("tappet", {0, h}, {0, 1})};
  d.nodes[1].mass_kg = 0.07;
  d.profiles = {eccentric_profile("disc", 18, 4)};
  ConnectionSpec k = contact("cam_tappet", profile_surface("cam", "disc", {0, 0}, -90),
                             line_surface("tappet", {0, h}, {0, -1}));
  k.material_a = k.material_b = "steel";
  k.width_mm = 8;
  d.connections = {k};
  d.materials = {steel()};
  SpringSpec s;
  s.name = "valve_spring";
  s.node = "tappet";
  s.rate_N_per_mm = rate_N_per_mm;
  s.preload_N = preload_N;
  d.springs = {s};
  return d;
}

// the direct-acting valve (spring 40 N/mm, 250 N preload) with a 45 g valve spring of
// `surge_masses` internal masses (0: massless chain, m/3 on the valve)
inline DesignSpec valve_with_spring_mass(int surge_masses) {
  DesignSpec d = direct_valve(40, 250);
  d.springs[0].mass_kg = 0.045;
  d.springs[0].surge_masses = surge_masses;
  return d;
}

// independent Hertz line law: solve delta = a (ln(4R/a) - 1) for a by the fixed point
// a = delta / (ln(4R/a) - 1) (contraction ~ 1/ln(4R/a) < 0.1), F = pi L E* a
inline double hertz_force_fixed_point(double delta, double length, double e_star, double radius) {
  if (delta <= 0) return 0.0;
  double a = delta / 10;
  for (int i = 0; i < 22; ++i) a = delta / (std::log(4 * radius / a) - 1);
  return camopt::pi * length * e_star * a;
}

// the power balance of a flexible run, point by point from its start: the work put in (drive,
// gas, the HLAs' and the springs' the energy leaves out) against the energy stored and lost (viscous, friction) [N mm], within `rel` of the
// largest drive work
inline camopt::test::Comparison power_balance(const dynamics::FlexibleResult& r, double rel) {
  std::vector<double> work_in(r.cam_deg.size()), work_out(r.cam_deg.size());
  double drive = 0.0;  // the largest |drive work| [N mm]
  for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
    work_in[i] = (r.drive_work[i] - r.drive_work[0]) + (r.gas_work[i] - r.gas_work[0]) +
                 (r.hla_work[i] - r.hla_work[0]) + (r.spring_work[i] - r.spring_work[0]);
    work_out[i] = (r.viscous_loss[i] - r.viscous_loss[0]) + (r.friction_loss[i] - r.friction_loss[0]) +
                  (r.energy[i] - r.energy[0]);
    drive = std::max(drive, std::abs(r.drive_work[i] - r.drive_work[0]));
  }
  return camopt::test::compare_series("work in - energy change - losses [N mm]", work_in, work_out,
                                      {.abs = rel * drive}, r.cam_deg, "cam [deg]");
}

}  // namespace camopt::dyn_test
