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

TEST_CASE("flexible HLA: power balance of the CVVL with its HLA (drive and HLA work = energy change + losses)",
          "[dynamics][flexible][hla]") {
  const DesignSpec d = hla_design();
  REQUIRE(d.hlas.size() == 1);
  REQUIRE(d.hlas[0].bulk_modulus_pressure_slope == 0.0);
  REQUIRE(d.hlas[0].air_polytropic_index == 1.0);
  const Run r = run(d, 6000, tight(1));
  INFO(r.status.str());
  REQUIRE(r.status.ok());
  // the HLA does work on the train (its plunger moves under load) and the check is
  // not empty: a wrong mass coupling or gradient of the plunger breaks the balance
  const double hla_work = r.res.hla_work.back() - r.res.hla_work.front();
  INFO("HLA work " << hla_work << " N mm, drive work " << r.res.drive_work.back() - r.res.drive_work.front());
  CHECK(std::abs(hla_work) > 1e-3);
  CHECK_COMPARISON(dyn_test::power_balance(r.res, tol::kPowerBalanceRel));
}

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

TEST_CASE("flexible HLA: a rigid HLA (stiff oil, no leak, no preload) moves the valve as the fixed pivot",
          "[dynamics][flexible][hla]") {
  // the CVVL with the finger return spring and no lash on both sides; the HLA's oil 1e7 MPa
  // without air, a sealed plunger, a check valve that never opens, and a gallery pressure far
  // above the loads' pull (the trapped oil holds the pivot both ways)
  DesignSpec fixed = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
  for (ConnectionSpec& c : fixed.connections) c.lash_mm = 0.0;
  DesignSpec rigid = fixed;
  HlaSpec h = hla_design().hlas[0];
  h.bulk_modulus_MPa = 1e7;
  h.air_volume_fraction = 0.0;
  h.leak_clearance_mm = 1e-5;
  h.return_spring_preload_N = 0.0;
  h.return_spring_rate_N_per_mm = 0.0;
  h.ball_spring_preload_N = 1e3;
  h.supply_pressure_MPa = 20.0;
  rigid.hlas.push_back(h);
  dynamics::FlexibleOptions opt = tight(2);
  const Run a = run(fixed, 3000, opt), b = run(rigid, 3000, opt);
  INFO(a.status.str() << "\n" << b.status.str());
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  // the plunger moves by F V / (A^2 beta): ~2.4e-9 mm per N of pivot load
  double z_max = 0.0;
  for (double z : b.res.hla_plunger) z_max = std::max(z_max, std::abs(z));
  INFO("largest plunger travel " << z_max << " mm");
  CHECK(z_max < 1e-5);
  CHECK_COMPARISON(test::compare_series("valve lift [mm]", a.res.lift, b.res.lift, {.abs = 1e-5}, a.res.cam_deg, "cam [deg]"));
  const std::size_t nc = a.res.connections;
  for (std::size_t c = 0; c < nc; ++c) {
    std::vector<double> fa, fb;
    for (std::size_t i = 0; i < a.res.cam_deg.size(); ++i) fa.push_back(a.res.force[i * nc + c]), fb.push_back(b.res.force[i * nc + c]);
    CHECK_COMPARISON(test::compare_series("connection " + std::to_string(c) + " force [N]", fa, fb, {.abs = 1.0},
                                          a.res.cam_deg, "cam [deg]"));
  }
}

TEST_CASE("flexible HLA: pump-up at over-speed holds the valve open, a fast leak collapses the plunger",
          "[dynamics][flexible][hla]") {
  dynamics::FlexibleOptions opt;
  opt.revolutions = 3;
  opt.periodic_tolerance = 0.0;
  SECTION("9000 rpm: the finger leaves the swing cam, the ball refills the chamber, the plunger extends") {
    const Run r = run(hla_design(), 9000, opt);
    INFO(r.status.str());
    REQUIRE(r.status.ok());
    const dynamics::FlexibleResult& res = r.res;
    const double drift = res.hla_plunger.back() - res.hla_plunger.front();
    const double refill = res.hla_refill_volume.back() - res.hla_refill_volume.front();
    double min_lift = 1e9;
    for (double l : res.lift) min_lift = std::min(min_lift, l);
    INFO("drift " << drift << " mm, refill " << refill << " mm^3, lowest valve lift " << min_lift << " mm");
    CHECK(drift > 0.05);
    CHECK(refill > 1.0);
    CHECK(min_lift > 0.01);  // pumped up: the valve never reaches its seat
  }
  SECTION("3000 rpm with a 20 um clearance: the leak outruns the refill, the plunger sinks") {
    DesignSpec d = hla_design();
    d.hlas[0].leak_clearance_mm = 0.02;
    const Run r = run(d, 3000, opt);
    INFO(r.status.str());
    REQUIRE(r.status.ok());
    const dynamics::FlexibleResult& res = r.res;
    const double drift = res.hla_plunger.back() - res.hla_plunger.front();
    const double leak = res.hla_leak_volume.back() - res.hla_leak_volume.front();
    INFO("drift " << drift << " mm, leak " << leak << " mm^3");
    CHECK(drift < -1e-3);
    CHECK(leak > 1.0);
  }
}
