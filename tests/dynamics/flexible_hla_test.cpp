// the flexible model with a hydraulic lash adjuster under the CVVL's finger pivot
// (designs/cvvl_swing_cam_hla.toml): the power balance with the HLA's work (the plunger's mass
// coupling and its contact gradients), mass conservation of the chamber's oil, a rigid HLA
// against the fixed pivot, pump-up at over-speed and collapse under a fast leak.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/design_file.hpp"
#include "dynamics/dynamics_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

DesignSpec hla_design() { return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam_hla.toml"); }

struct Run {
  Status status;
  dynamics::FlexibleResult res;
};

Run run(const DesignSpec& d, double rpm, const dynamics::FlexibleOptions& opt, double step = 1.0) {
  const kin::Mechanism mech = kin::compile(d);
  const dynamics::Model model = dynamics::compile_dynamics(d, mech);
  Run r;
  r.status = dynamics::run_flexible(mech, model, {0.0}, rpm, 0, 360, step, opt, r.res);
  return r;
}

dynamics::FlexibleOptions tight(int revolutions) {
  dynamics::FlexibleOptions opt;
  opt.revolutions = revolutions;
  opt.relative_tolerance = 1e-9;
  opt.absolute_tolerance = 1e-11;
  opt.periodic_tolerance = 0.0;
  return opt;
}

// the chamber's oil as its volume at 0 gauge, written out here from docs/hla.md: a unit volume
// at 0 gauge holds 1 - x oil and x air; at gauge p the oil shrinks by exp(-p / beta) (a
// constant bulk modulus) and the air follows p_abs V = const (isothermal)
double content_mm3(const HlaSpec& h, double z, double void_mm3, double p) {
  const double area = pi * h.plunger_diameter_mm * h.plunger_diameter_mm / 4.0;
  const double x = h.air_volume_fraction, p_atm = h.atmospheric_pressure_MPa;
  const double ratio = (1.0 - x) * std::exp(-p / h.bulk_modulus_MPa) + x * p_atm / (p_atm + p);
  return (h.chamber_volume_mm3 + area * z - void_mm3) / ratio;
}

}  // namespace

TEST_CASE("flexible HLA: the chamber's oil changes by the refill minus the leak over the run", "[dynamics][flexible][hla]") {
  const DesignSpec d = hla_design();
  const HlaSpec& h = d.hlas[0];
  const Run r = run(d, 6000, tight(1));
  INFO(r.status.str());
  REQUIRE(r.status.ok());
  const dynamics::FlexibleResult& res = r.res;
  REQUIRE(res.layout.hydraulic_states == 4);
  bool ball_opened = false;
  std::vector<double> content, exchanged;
  for (std::size_t i = 0; i < res.cam_deg.size(); ++i) {
    const double* hs = &res.hydraulic_state[i * 4];  // pressure, void, ball lift, ball velocity
    CHECK(hs[0] == res.hla_pressure[i]);
    ball_opened = ball_opened || res.hla_ball_lift[i] > 0.0;
    content.push_back(content_mm3(h, res.hla_plunger[i], hs[1], hs[0]) - content_mm3(h, res.hla_plunger[0], res.hydraulic_state[1], res.hydraulic_state[0]));
    exchanged.push_back((res.hla_refill_volume[i] - res.hla_refill_volume[0]) - (res.hla_leak_volume[i] - res.hla_leak_volume[0]));
  }
  // the leak over the revolution is ~0.05 mm^3 of a 150 mm^3 chamber
  const double leak = res.hla_leak_volume.back() - res.hla_leak_volume.front();
  INFO("leak " << leak << " mm^3 over the revolution");
  CHECK(ball_opened);
  CHECK(leak > 0.01);
  CHECK_COMPARISON(test::compare_series("chamber content change [mm^3]", exchanged, content, {.abs = 1e-4 * leak},
                                        res.cam_deg, "cam [deg]"));
}

// the CVVL with the finger return spring and no lash, with and without an HLA under the finger
// pivot: the HLA's oil 2e5 MPa without air in 150 mm^3 (A^2 beta / V = 4.5e6 N/mm), a sealed
// plunger, a check
// valve that never opens, and a gallery pressure far above the loads' pull (the trapped oil
// holds the pivot both ways)
struct RigidHla {
  DesignSpec fixed, rigid;
  RigidHla() {
    fixed = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
    for (ConnectionSpec& c : fixed.connections) c.lash_mm = 0.0;
    rigid = fixed;
    HlaSpec h = hla_design().hlas[0];
    h.bulk_modulus_MPa = 2e5;
    h.chamber_volume_mm3 = 150.0;
    h.travel_min_mm = -1.5;
    h.air_volume_fraction = 0.0;
    h.leak_clearance_mm = 1e-5;
    h.return_spring_preload_N = 0.0;
    h.return_spring_rate_N_per_mm = 0.0;
    h.ball_spring_preload_N = 1e3;
    h.supply_pressure_MPa = 20.0;
    rigid.hlas.push_back(h);
  }
};

TEST_CASE("flexible HLA: a rigid HLA moves the valve as the fixed pivot and carries its reaction",
          "[dynamics][flexible][hla]") {
  const RigidHla designs;
  dynamics::FlexibleOptions opt = tight(2);
  opt.relative_tolerance = 1e-8;
  opt.absolute_tolerance = 1e-10;
  SECTION("3000 rpm: the valve lift and the contact forces of the fixed pivot") {
    const Run a = run(designs.fixed, 3000, opt), b = run(designs.rigid, 3000, opt);
    INFO(a.status.str() << "\n" << b.status.str());
    REQUIRE(a.status.ok());
    REQUIRE(b.status.ok());
    // the plunger gives by F V / (A^2 beta): 2.2e-7 mm per N of pivot load
    double z_max = 0.0;
    for (double z : b.res.hla_plunger) z_max = std::max(z_max, std::abs(z));
    INFO("largest plunger travel " << z_max << " mm");
    CHECK(z_max < 5e-4);
    CHECK_COMPARISON(test::compare_series("valve lift [mm]", a.res.lift, b.res.lift, {.abs = 1e-3}, a.res.cam_deg,
                                          "cam [deg]"));
    const std::size_t nc = a.res.connections;
    for (std::size_t c = 0; c < nc; ++c) {
      std::vector<double> fa, fb;
      for (std::size_t i = 0; i < a.res.cam_deg.size(); ++i)
        fa.push_back(a.res.force[i * nc + c]), fb.push_back(b.res.force[i * nc + c]);
      CHECK_COMPARISON(test::compare_series("connection " + std::to_string(c) + " force [N]", fa, fb, {.abs = 5.0},
                                            a.res.cam_deg, "cam [deg]"));
    }
  }
  SECTION("250 rpm: the HLA's force balances the contact forces on the finger along its axis") {
    // the finger's force balance along the axis written here: the HLA pushes with what the
    // contacts press down, -sum F_c (side n_c) . axis (n_c from body a into b, on the kinematic
    // path: the rigid sweep's contact states); the finger's inertia is below 0.2 N at 250 rpm
    const kin::Mechanism mech = kin::compile(designs.rigid);
    const dynamics::Model model = dynamics::compile_dynamics(designs.rigid, mech);
    dynamics::RigidSweep sweep;
    REQUIRE(dynamics::rigid_sweep(mech, model, {0.0}, 0, 360, 1, sweep).ok());
    const Run b = run(designs.rigid, 250, opt);
    INFO(b.status.str());
    REQUIRE(b.status.ok());
    const int finger = mech.node_index("finger");
    const std::size_t nc = mech.connections.size();
    std::vector<double> balance;
    double peak = 0.0;
    for (std::size_t i = 0; i < sweep.points(); ++i) {
      REQUIRE(b.res.cam_deg[i] == sweep.cam_deg[i]);
      double pressed = 0.0;
      for (std::size_t c = 0; c < nc; ++c) {
        const kin::Connection& conn = mech.connections[c];
        if (conn.node_a != finger && conn.node_b != finger) continue;
        const double side = conn.node_b == finger ? 1.0 : -1.0;
        pressed += b.res.force[i * nc + c] * side * sweep.contact[i * nc + c].normal_y;  // axis +y
      }
      balance.push_back(-pressed);
      peak = std::max(peak, std::abs(balance.back()));
    }
    INFO("peak pivot load " << peak << " N");
    CHECK(peak > 300.0);
    CHECK_COMPARISON(test::compare_series("HLA force [N]", balance, b.res.hla_force, {.abs = 1e-3 * peak}, b.res.cam_deg,
                                          "cam [deg]"));
  }
}

TEST_CASE("flexible HLA: pump-up at over-speed, collapse of an unrefilled leak",
          "[dynamics][flexible][hla]") {
  dynamics::FlexibleOptions opt;
  opt.revolutions = 3;
  opt.periodic_tolerance = 0.0;
  SECTION("9000 rpm: the finger leaves the swing cam and the valve, the ball refills the chamber, the plunger extends") {
    // a 10 mm plunger on a soft return spring (1.5 N/mm, 12 N) over 150 mm^3 with 0.5 % air, and a check
    // valve that closes quickly (0.3 N/mm, 0.1 N, 0.3 mm of travel): the bundled HLA's slow
    // ball lets the chamber's oil flow back at this speed instead, and the plunger sinks
    DesignSpec d = hla_design();
    HlaSpec& h = d.hlas[0];
    h.plunger_diameter_mm = 10.0;
    h.plunger_mass_kg = 0.012;
    h.chamber_volume_mm3 = 150.0;
    h.air_volume_fraction = 0.005;
    h.travel_min_mm = -1.5;
    h.travel_max_mm = 1.5;
    h.return_spring_rate_N_per_mm = 1.5;
    h.leak_clearance_mm = 0.004;
    h.leak_length_mm = 8.0;
    h.ball_diameter_mm = 3.175;
    h.ball_mass_kg.reset();
    h.seat_diameter_mm = 2.2;
    h.ball_travel_mm = 0.3;
    h.cage_height_mm.reset();
    h.ball_spring_rate_N_per_mm = 0.3;
    h.ball_spring_preload_N = 0.1;
    const Run r = run(d, 9000, opt);
    INFO(r.status.str());
    REQUIRE(r.status.ok());
    const dynamics::FlexibleResult& res = r.res;
    const double drift = res.hla_plunger.back() - res.hla_plunger.front();
    const double refill = res.hla_refill_volume.back() - res.hla_refill_volume.front();
    INFO("drift " << drift << " mm, refill " << refill << " mm^3");
    CHECK(drift > 0.01);
    CHECK(refill > 1.0);
  }
  SECTION("3000 rpm, a worn plunger and a starved check valve: the leak is not refilled, the plunger sinks") {
    // 20 um clearance; 0.15 MPa in the gallery against a ball that needs 0.25 MPa across it to
    // open (0.125 N on a 0.8 mm seat): the chamber's floor of -0.095 MPa gives it 0.245 MPa at
    // most, so the ball never leaves its seat
    DesignSpec d = hla_design();
    d.hlas[0].leak_clearance_mm = 0.02;
    d.hlas[0].supply_pressure_MPa = 0.15;
    d.hlas[0].seat_diameter_mm = 0.8;
    d.hlas[0].ball_spring_preload_N = 0.125;
    d.hlas[0].ball_travel_mm = 0.1;  // the ball sits higher in the smaller seat: its cage leaves 0.15 mm
    const Run r = run(d, 3000, opt);
    INFO(r.status.str());
    REQUIRE(r.status.ok());
    const dynamics::FlexibleResult& res = r.res;
    const double drift = res.hla_plunger.back() - res.hla_plunger.front();
    const double leak = res.hla_leak_volume.back() - res.hla_leak_volume.front();
    const double refill = res.hla_refill_volume.back() - res.hla_refill_volume.front();
    INFO("drift " << drift << " mm, leak " << leak << " mm^3, refill " << refill << " mm^3");
    CHECK(drift < -0.05);
    CHECK(leak > 5.0);
    CHECK(refill == 0.0);
  }
}


TEST_CASE("flexible HLA: an HLA in series on a translational node is an input error naming its table",
          "[dynamics][flexible][hla]") {
  DesignSpec d = hla_design();
  d.hlas[0].node = "valve";
  const kin::Mechanism mech = kin::compile(d);
  const dynamics::Model model = dynamics::compile_dynamics(d, mech);
  dynamics::FlexibleResult res;
  CHECK_THROWS_WITH(dynamics::run_flexible(mech, model, {0.0}, 3000, 0, 360, 1, dynamics::FlexibleOptions{}, res),
                    Catch::Contains("cvvl_swing_cam_hla.toml:") && Catch::Contains("hla 'finger_hla' on node 'valve'") &&
                        Catch::Contains("fixed pivot of a solved rotational node"));
}
