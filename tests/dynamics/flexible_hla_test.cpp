// the flexible model with a hydraulic lash adjuster under the CVVL's finger pivot
// (designs/cvvl_swing_cam_hla.toml) and in series in a hydraulic bucket
// (designs/bucket_tappet_hla.toml): mass conservation of the chamber's oil, a rigid HLA
// against the fixed pivot or the solid bucket, the force balances of the bodies it joins,
// pump-up at over-speed and collapse under a fast leak, and the placements it refuses.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
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
  r.status = dynamics::run_flexible(mech, model, std::vector<double>(mech.controls.size(), 0.0), rpm, 0, 360, step, opt,
                                    r.res);
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

// the plunger's drift [mm] and the oil leaked and refilled [mm^3] over a run
struct Exchange {
  double drift, leak, refill;
};
Exchange exchange_of(const dynamics::FlexibleResult& res) {
  return {res.hla_plunger.back() - res.hla_plunger.front(), res.hla_leak_volume.back() - res.hla_leak_volume.front(),
          res.hla_refill_volume.back() - res.hla_refill_volume.front()};
}

}  // namespace

namespace {

// mass conservation over a run: the chamber's oil (content_mm3) changes by the refill minus the
// leak, within 1e-4 of the leak, and the ball opens
void check_oil_balance(const DesignSpec& d, double rpm) {
  const HlaSpec& h = d.hlas[0];
  const Run r = run(d, rpm, tight(1));
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
    content.push_back(content_mm3(h, res.hla_plunger[i], hs[1], hs[0]) -
                      content_mm3(h, res.hla_plunger[0], res.hydraulic_state[1], res.hydraulic_state[0]));
    exchanged.push_back((res.hla_refill_volume[i] - res.hla_refill_volume[0]) -
                        (res.hla_leak_volume[i] - res.hla_leak_volume[0]));
  }
  // the leak over the revolution is ~0.05 mm^3 of a 150 mm^3 chamber
  const double leak = res.hla_leak_volume.back() - res.hla_leak_volume.front();
  INFO("leak " << leak << " mm^3 over the revolution");
  CHECK(ball_opened);
  CHECK(leak > 0.01);
  CHECK_COMPARISON(test::compare_series("chamber content change [mm^3]", exchanged, content, {.abs = 1e-4 * leak},
                                        res.cam_deg, "cam [deg]"));
}

}  // namespace

TEST_CASE("flexible HLA: the chamber's oil changes by the refill minus the leak over the run", "[dynamics][flexible][hla]") {
  check_oil_balance(hla_design(), 6000);
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
    const Exchange e = exchange_of(res);
    const double drift = e.drift, refill = e.refill;
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
    const auto [drift, leak, refill] = exchange_of(res);
    INFO("drift " << drift << " mm, leak " << leak << " mm^3, refill " << refill << " mm^3");
    CHECK(drift < -0.05);
    CHECK(leak > 5.0);
    CHECK(refill == 0.0);
  }
}

// ---- in series: the hydraulic bucket (designs/bucket_tappet_hla.toml) ----

namespace {

DesignSpec bucket_design() { return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/bucket_tappet_hla.toml"); }

std::size_t tappet_index(const DesignSpec& d) {
  const auto it = std::find_if(d.nodes.begin(), d.nodes.end(), [](const NodeSpec& n) { return n.name == "tappet"; });
  REQUIRE(it != d.nodes.end());
  return static_cast<std::size_t>(it - d.nodes.begin());
}

// the valve side's free body along the tappet's direction +y, written here: the HLA pushes it
// along -axis = +y, the valve spring's top end pushes it back, the seat pushes it off the seat,
// its mass (the node's minus the series body's) takes the rest: F_hla = F_spring - F_seat + m_v a
std::vector<double> valve_side_balance(const DesignSpec& d, const dynamics::FlexibleResult& res) {
  const double m_valve = (*d.nodes[tappet_index(d)].mass_kg - *d.hlas[0].series_body_mass_kg) * 1e-3;
  REQUIRE(res.coil_force_top.size() == res.cam_deg.size());
  REQUIRE(res.seat_forces.size() == res.cam_deg.size());
  std::vector<double> out;
  for (std::size_t i = 0; i < res.cam_deg.size(); ++i)
    out.push_back(res.coil_force_top[i] - res.seat_forces[i] + m_valve * res.acceleration[i]);
  return out;
}

// the largest differences of a stiff, sealed element (bulk modulus beta, no air, a ball that
// never opens, a gallery far above the loads' pull) from the solid bucket of the same mass
struct SeriesGap {
  double z = 0.0, lift = 0.0, force = 0.0, element_force = 0.0;  // [mm], [mm], [N], [N]
};
SeriesGap rigid_series_gap(double beta) {
  // the stem's compliance is removed from both: with it the series body rides on the near end
  // while the solid tappet splits its whole mass between the halves (a different lumping). The
  // seat too: with it and no lash the cam and the seat share the spring's load on the base
  // circle by their approaches, and a z of 1e-4 mm against their ~1e6 N/mm moves 100 N
  // between them; without it the cam carries the spring on the base circle in both
  DesignSpec rigid = bucket_design();
  rigid.nodes[tappet_index(rigid)].axial_stiffness_N_per_mm.reset();
  rigid.nodes[tappet_index(rigid)].seat.enabled = false;
  DesignSpec solid = rigid;
  solid.hlas.clear();
  HlaSpec& h = rigid.hlas[0];
  h.bulk_modulus_MPa = beta;
  h.air_volume_fraction = 0.0;
  h.leak_clearance_mm = 1e-5;
  h.return_spring_preload_N = 0.0;
  h.return_spring_rate_N_per_mm = 0.0;
  h.ball_spring_preload_N = 1e3;
  h.supply_pressure_MPa = 20.0;
  dynamics::FlexibleOptions opt = tight(2);
  opt.relative_tolerance = 1e-8;
  opt.absolute_tolerance = 1e-10;
  const Run a = run(solid, 3000, opt), b = run(rigid, 3000, opt);
  INFO(a.status.str() << "\n" << b.status.str());
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  SeriesGap g;
  for (std::size_t i = 0; i < a.res.cam_deg.size(); ++i) {
    g.z = std::max(g.z, std::abs(b.res.hla_plunger[i]));
    g.element_force = std::max(g.element_force, std::abs(b.res.hla_force[i]));
    g.lift = std::max(g.lift, std::abs(a.res.lift[i] - b.res.lift[i]));
    g.force = std::max(g.force, std::abs(a.res.force[i] - b.res.force[i]));
  }
  return g;
}

}  // namespace

TEST_CASE("flexible series HLA: a rigid element moves the valve as the solid bucket of the same mass",
          "[dynamics][flexible][hla][series]") {
  // 2e6 MPa in 330 mm^3: A^2 beta / V = 2.03e7 N/mm, 40 times the cam contact's stiffness
  const SeriesGap stiff = rigid_series_gap(2e6), softer = rigid_series_gap(2e5);
  INFO("2e6 MPa: z " << stiff.z << " mm, lift " << stiff.lift << " mm, cam force " << stiff.force << " N; 2e5 MPa: z "
                     << softer.z << " mm, lift " << softer.lift << " mm, cam force " << softer.force << " N");
  CHECK(stiff.element_force > 400.0);
  // the element gives by F / 2.03e7 N/mm: 2.4e-5 mm at its 495 N peak; the valve is shorter
  // by z on the same cam
  CHECK(stiff.z < 3e-5);
  CHECK(stiff.lift < stiff.z + 1e-6);
  // the cam force rings (+-40 N at the nose flanks); the element's compliance shifts the
  // ringing's frequency by about k_contact / (2 k_element): 1.3 % here, 2 N of its amplitude;
  // the difference is the compliance's: ten times the compliance, about ten times the difference
  CHECK(stiff.force < 2.0);
  CHECK(softer.force > 5.0 * stiff.force);
  CHECK(softer.force < 20.0 * stiff.force);
}

TEST_CASE("flexible series HLA: at 250 rpm the element carries the valve side",
          "[dynamics][flexible][hla][series]") {
  // the bundled element (1500 MPa oil, its leak and ball) on the compliant stem
  const DesignSpec d = bucket_design();
  dynamics::FlexibleOptions opt = tight(2);
  const Run r = run(d, 250, opt);
  INFO(r.status.str());
  REQUIRE(r.status.ok());
  const dynamics::FlexibleResult& res = r.res;
  // the valve side: spring, seat and its inertia
  const std::vector<double> valve = valve_side_balance(d, res);
  double peak = 0.0;
  for (double f : res.hla_force) peak = std::max(peak, std::abs(f));
  INFO("peak element force " << peak << " N");
  CHECK(peak > 450.0);
  CHECK_COMPARISON(test::compare_series("HLA force against the valve side [N]", valve, res.hla_force,
                                        {.abs = 1e-3 * peak}, res.cam_deg, "cam [deg]"));
}

TEST_CASE("flexible series HLA: the work of the drive and the element is the energy change and the losses",
          "[dynamics][flexible][hla][series]") {
  // the kinetic energy from the mass matrix (the series body on the stem's top, the valve
  // side's mass halved) against the work of the forces (the kinematic inertia split the same
  // way) at 6000 rpm, where the inertia is a third of the cam force
  const Run r = run(bucket_design(), 6000, tight(1));
  INFO(r.status.str());
  REQUIRE(r.status.ok());
  CHECK(std::abs(r.res.hla_work.back() - r.res.hla_work.front()) > 0.1);  // 0.33 N mm
  CHECK_COMPARISON(dyn_test::power_balance(r.res, tol::kPowerBalanceRel));
}

TEST_CASE("flexible series HLA: the chamber's oil changes by the refill minus the leak", "[dynamics][flexible][hla][series]") {
  check_oil_balance(bucket_design(), 3000);
}

TEST_CASE("flexible series HLA: a worn element on a starved gallery collapses", "[dynamics][flexible][hla][series]") {
  // a 10 um clearance (20 um bottoms the plunger on its stop within the first revolutions),
  // 0.15 MPa in the gallery against a ball that needs 0.25 MPa across it to open: the leak is
  // never refilled and the bucket sinks onto the valve
  DesignSpec d = bucket_design();
  HlaSpec& h = d.hlas[0];
  h.leak_clearance_mm = 0.01;
  h.supply_pressure_MPa = 0.15;
  h.seat_diameter_mm = 0.8;
  h.ball_spring_preload_N = 0.125;
  h.ball_travel_mm = 0.1;
  dynamics::FlexibleOptions opt;
  opt.revolutions = 3;
  opt.periodic_tolerance = 0.0;
  const Run r = run(d, 3000, opt);
  INFO(r.status.str());
  REQUIRE(r.status.ok());
  const dynamics::FlexibleResult& res = r.res;
  const auto [drift, leak, refill] = exchange_of(res);
  INFO("drift " << drift << " mm, leak " << leak << " mm^3, refill " << refill << " mm^3");
  CHECK(refill == 0.0);
  CHECK(leak > 1.0);
  // 3.2 mm^3 out of the chamber; on the base circle the return spring cannot draw the bucket
  // back onto the cam against the chamber's floor (a void opens), so the plunger sinks by less
  // than leak / A_p (0.056 mm)
  CHECK(drift < -0.005);
}

TEST_CASE("flexible series HLA: the placements the model refuses name the file and the key",
          "[dynamics][flexible][hla][series]") {
  const std::string path = std::string(CAMOPT_SOURCE_DIR) + "/designs/bucket_tappet_hla.toml";
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "series_body_mass_kg = 0.035\n";
  const std::size_t at = text.find(key);
  REQUIRE(at != std::string::npos);
  const auto line_of = [&](std::size_t pos) {
    return std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
  };
  const auto error_of = [&](const std::string& t) {
    try {
      (void)io::parse_design(t, "bucket_tappet_hla.toml", std::string(CAMOPT_SOURCE_DIR) + "/designs");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SECTION("a translational node's HLA without series_body_mass_kg: at its table") {
    std::string t = text;
    t.erase(at, key.size());
    CHECK_THAT(error_of(t), Catch::Contains("bucket_tappet_hla.toml:" + line_of(text.find("\n[[hla]]") + 1) + ":") &&
                                Catch::Contains("hla[0]: missing required key 'series_body_mass_kg'"));
  }
  SECTION("a series body as heavy as the node: at the key") {
    std::string t = text;
    t.replace(at, key.size(), "series_body_mass_kg = 0.0648\n");
    CHECK_THAT(error_of(t), Catch::Contains("bucket_tappet_hla.toml:" + line_of(at) + ":") &&
                                Catch::Contains("hla[0].series_body_mass_kg: value 0.0648 must be < node \"tappet\"'s "
                                                "mass_kg (0.0648)"));
  }
  SECTION("the flexible model: an axis across the node's direction, naming the table") {
    DesignSpec d = bucket_design();
    d.hlas[0].axis = {1.0, -1.0};
    const kin::Mechanism mech = kin::compile(d);
    const dynamics::Model model = dynamics::compile_dynamics(d, mech);
    dynamics::FlexibleResult res;
    CHECK_THROWS_WITH(dynamics::run_flexible(mech, model, {}, 3000, 0, 360, 1, dynamics::FlexibleOptions{}, res),
                      Catch::Contains("bucket_tappet_hla.toml:" + line_of(text.find("\n[[hla]]") + 1) + ":") &&
                          Catch::Contains("hla 'bucket_hla' in series on node 'tappet': axis") &&
                          Catch::Contains("must be along the node's direction"));
  }
}
