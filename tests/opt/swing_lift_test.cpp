// the swing-cam lift model (opt::SwingCamLift) on the bundled CVVL: its valve motion
// against the kinematic solver run on the profile it writes, and its coefficient
// sensitivities against central finite differences.
#include <catch2/catch.hpp>
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/opt/cam_contact.hpp"
#include "camopt/opt/swing_lift.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

DesignSpec cvvl() { return io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml"); }

opt::SwingProfileSpec three_positions() {
  opt::SwingProfileSpec s;
  s.positions = {0.0, 8.0, 16.0};
  return s;
}

// the initial coefficients with a smooth change, so the check does not sit on the fit
std::vector<double> perturbed(const opt::SwingCamLift& m) {
  std::vector<double> c = m.initial();
  for (std::size_t j = 0; j < c.size(); ++j) c[j] *= 1.0 + 0.03 * std::sin(0.7 * static_cast<double>(j));
  return c;
}

// the model's valve motion against the kinematic solver run on the profile the model writes,
// at every working point of every position where the valve is open
struct SolverComparison {
  test::Series lift{"valve lift [mm]", "cam [deg]"};
  test::Series acc{"valve acceleration [mm/deg^2]", "cam [deg]"};
  double peak = 0.0;
};

SolverComparison compare_with_kinematic_solver(const DesignSpec& d, opt::SwingCamLift& model,
                                               const std::vector<double>& c) {
  // the new design: the swing profile replaced by the model's polar table
  ProfileSpec prof;
  for (const auto& p : d.profiles)
    if (p.name == model.profile_name()) prof = p;
  prof.source_file.clear();
  REQUIRE(model.profile_table(c, 7200, 3.0, prof.angle_deg, prof.radius_mm).ok());
  const DesignSpec made = synthesis::with_profile(d, prof);
  const kin::Mechanism mech = kin::compile(made);
  const int valve = mech.nodes[static_cast<std::size_t>(mech.node_index("valve"))].first_variable;
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows(4, model.variables());
  SolverComparison out;
  for (int k = 0; k < static_cast<int>(model.positions().size()); ++k) {
    kin::Workspace ws(mech);
    ws.set_controls(model.controls(k));
    // the kinematic solver sweeps every degree from the dwell before the position's first
    // working point (its warm starts follow the contact); compare where the valve is open
    std::size_t first = 0;
    while (model.points()[first].position != k) ++first;
    const double start = model.points()[first].cam_deg - 20.0;
    std::size_t i = first;
    for (int step = 0; step <= 360; ++step) {
      const double deg = start + step;
      const Status st = kin::solve(mech, ws, deg * camopt::pi / 180.0, {3, false});
      INFO(st.str() << " at cam " << deg << " position " << k);
      REQUIRE(st.ok());
      if (i >= model.points().size() || model.points()[i].position != k ||
          std::abs(model.points()[i].cam_deg - deg) > 1e-9)
        continue;
      double mo[4];
      REQUIRE(model.evaluate(static_cast<int>(i), c, mo, rows).ok());
      ++i;
      const double lift = mo[0];
      const auto& v = ws.vars[static_cast<std::size_t>(valve)];
      if (lift < 1e-3) continue;  // the valve on its seat
      out.lift.add(deg, v.value(), lift);
      // [mm/rad^2] -> [mm/deg^2]
      out.acc.add(deg, v.derivative(2) * std::pow(camopt::pi / 180.0, 2), mo[2]);
      out.peak = std::max(out.peak, lift);
    }
  }
  return out;
}

// the model at perturbed coefficients against the kinematic solver: over 150 open-valve
// points, a peak above min_peak_mm; the profile table (7200 points, quintic spline) is the only
// approximation in between
void check_against_kinematic_solver(const DesignSpec& d, opt::SwingCamLift& model, double min_peak_mm) {
  const SolverComparison r = compare_with_kinematic_solver(d, model, perturbed(model));
  INFO("compared " << r.lift.size() << " points, peak lift " << r.peak);
  CHECK(r.lift.size() > 150);
  CHECK(r.peak > min_peak_mm);
  CHECK_SERIES(r.lift.compare({.abs = tol::kSwingTableLiftAbs}));
  CHECK_SERIES(r.acc.compare({.abs = tol::kSwingTableAccAbs}));
}

}  // namespace

TEST_CASE("swing lift: valve motion equals the kinematic solver on the written profile", "[opt][swing]") {
  const DesignSpec d = cvvl();
  opt::SwingCamLift model(d, three_positions(), 1.0);
  REQUIRE(model.variables() == 16);
  check_against_kinematic_solver(d, model, 8.0);
}

TEST_CASE("swing lift: the VVLD's control arm (pivot moved by the control shaft) against the kinematic solver",
          "[opt][swing][vvld]") {
  // the VVLD's "swing cam" is its control arm: a profile on a node whose pivot the control
  // shaft carries along an arc, two contacts downstream of the driver; the rocker follows it
  const DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/vvld.toml");
  opt::SwingProfileSpec spec;
  spec.positions = {0.0, 50.0, 100.0};
  opt::SwingCamLift model(d, spec, 1.0);
  REQUIRE(model.connection() == "arm_roller");
  REQUIRE_REL(model.dwell_radius_mm(), 32.0, tol::kDrawnDwellRadiusRel);  // |Q - Rr| of the drawing
  check_against_kinematic_solver(d, model, 9.0);
}

TEST_CASE("swing lift: coefficient sensitivities match central finite differences", "[opt][swing]") {
  const DesignSpec d = cvvl();
  opt::SwingCamLift model(d, three_positions(), 2.0);
  const std::vector<double> c = perturbed(model);
  const int n = model.variables();
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows(4, n), scratch(4, n);
  const double h = 1e-5;  // [mm]
  int checked = 0;
  std::vector<test::Series> order;
  for (const char* name : {"d lift / d c", "d velocity / d c", "d acceleration / d c", "d jerk / d c"})
    order.emplace_back(name, "point x variables + variable");
  for (std::size_t i = 0; i < model.points().size(); i += 3) {
    double mo[4];
    REQUIRE(model.evaluate(static_cast<int>(i), c, mo, rows).ok());
    for (int j = 0; j < n; ++j) {
      std::vector<double> cp = c, cm = c;
      cp[static_cast<std::size_t>(j)] += h;
      cm[static_cast<std::size_t>(j)] -= h;
      double mp[4], mm[4];
      REQUIRE(model.evaluate(static_cast<int>(i), cp, mp, scratch).ok());
      REQUIRE(model.evaluate(static_cast<int>(i), cm, mm, scratch).ok());
      for (std::size_t k = 0; k < 4; ++k) {
        const double fd = (mp[k] - mm[k]) / (2 * h);
        order[k].add(static_cast<double>(i) * n + j, rows(static_cast<Eigen::Index>(k), j), fd);
      }
    }
    ++checked;
  }
  // per derivative order: the largest error against the largest sensitivity
  for (const test::Series& s : order) CHECK_SERIES(s.compare({.rel = tol::kSwingSensitivityFdRel}));
  CHECK(checked > 40);
}

TEST_CASE("swing lift: contact quantities agree with the envelope model away from the swing's reversal",
          "[opt][swing]") {
  // opt::CamContactModel finds the same quantities from the valve motion by envelope theory;
  // it loses accuracy where the swing reverses (the roller's relative speed -> 0)
  const DesignSpec d = cvvl();
  opt::SwingCamLift model(d, three_positions(), 1.0);
  const std::vector<double> c = perturbed(model);
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows(4, model.variables());
  int compared = 0;
  for (int k = 0; k < 3; ++k) {
    opt::CamContactModel env(d, model.controls(k), "swing");
    opt::ContactWorkspace ws = env.make_workspace();
    for (std::size_t i = 0; i < model.points().size(); ++i) {
      const opt::SwingPoint& sp = model.points()[i];
      if (sp.position != k) continue;
      double mo[4];
      opt::SwingContact sc;
      REQUIRE(model.evaluate(static_cast<int>(i), c, mo, rows, &sc).ok());
      if (mo[0] < 0.05 || sc.s_rad <= model.start_rad()) continue;
      const double r1 = 180.0 / camopt::pi, lift[3] = {mo[0], mo[1] * r1, mo[2] * r1 * r1};
      opt::ContactQuantities cq;
      REQUIRE(env.evaluate(sp.cam_deg * camopt::pi / 180.0, lift, ws, cq).ok());
      if (std::abs(mo[1]) < 0.02) continue;  // near the reversal at peak lift
      INFO("position " << k << " cam " << sp.cam_deg << " lift " << mo[0]);
      CHECK_REL(sc.curvature, cq.pitch_curvature.v, tol::kSwingEnvelopeRel);
      CHECK_ABS(sc.pressure_angle, cq.pressure_angle.v, tol::kSwingEnvelopePressureAngleAbs);
      CHECK_REL(sc.force_ratio, cq.force_ratio.v, tol::kSwingEnvelopeRel);
      CHECK_REL(sc.roller_speed, cq.roller_speed.v, tol::kSwingEnvelopeRel);
      ++compared;
    }
  }
  CHECK(compared > 100);
}

TEST_CASE("swing lift: a nose that cannot keep the asked convex radius is reported with its swing angle",
          "[opt][swing]") {
  // the CVVL's pitch radius is ~36 mm: no nose keeps a 1000 mm convex surface radius, while a
  // 3 mm one is met (the CLI test checks that radius on the written surface)
  const DesignSpec d = cvvl();
  opt::SwingCamLift model(d, three_positions(), 1.0);
  const std::vector<double> c = perturbed(model);
  std::vector<double> angle, radius;
  REQUIRE(model.profile_table(c, 3600, 3.0, angle, radius).ok());
  CHECK(angle.size() == 3600);
  const Status st = model.profile_table(c, 3600, 1000.0, angle, radius);
  REQUIRE_FALSE(st.ok());
  CHECK(st.code == StatusCode::undercut);
  CHECK_THAT(st.message, Catch::Contains("nose") && Catch::Contains("1000 mm"));
  CHECK_THAT(st.where, Catch::StartsWith("swing "));
}
