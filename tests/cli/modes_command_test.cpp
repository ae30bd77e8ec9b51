// camopt dynamics --model modes end to end, on designs written here as TOML: the surge
// frequencies of a spring alone (lumped fixed-fixed chain and continuous coil), the mode
// shapes' mass normalisation, a valve hanging on its spring chain (fixed-free chain), and
// the Cam Design Handbook pushrod valve gear (CDH11) with the cam released; bad input exits 3
// naming the option and the value and writes nothing; --rpm stays required by the
// time-domain models only.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "cli/cli_support.hpp"
#include "support/compare.hpp"

using namespace camopt::test;

namespace {


// a number for a TOML file, read back to the same double
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// the direct-acting valve: eccentric disc (R 18 mm, e 4 mm; lift e (1 - cos theta)) on a
// 70 g flat tappet, steel line contact 8 mm wide; a 40 N/mm, 250 N spring of 45 g with
// `surge_masses` internal masses
constexpr double kValveMass = 0.07, kSpringMass = 0.045, kRate = 40.0, kEccentricity = 4.0;

std::string direct_valve_toml(int surge_masses) {
  return R"(schema = 1

[design]
name = "modes_direct_valve"
output_node = "tappet"

[driver]
node = "cam"

[[node]]
name = "cam"
type = "rotational"
pivot_mm = [0, 0]

[[node]]
name = "tappet"
type = "translational"
origin_mm = [0, 14]
direction = [0, 1]
mass_kg = )" + num(kValveMass) + R"(

[[profile]]
name = "disc"
form = "eccentric"
disc_radius_mm = 18
eccentricity_mm = )" + num(kEccentricity) + R"(

[[material]]
name = "steel"
youngs_modulus_GPa = 210
poisson_ratio = 0.3

[[connection]]
name = "cam_tappet"
type = "contact"
a = { node = "cam", shape = "profile", profile = "disc", orientation_deg = -90 }
b = { node = "tappet", shape = "line", point_mm = [0, 14], normal = [0, -1] }
materials = ["steel", "steel"]
width_mm = 8

[[spring]]
name = "valve_spring"
type = "compression"
node = "tappet"
rate_N_per_mm = )" + num(kRate) + R"(
preload_N = 250
mass_kg = )" + num(kSpringMass) + R"(
surge_masses = )" + std::to_string(surge_masses) + "\n";
}

// the published CDH11 data (lbm, in, lbf/in) in kg, mm, N/mm
struct Cdh11 {
  static constexpr double lbm = 0.45359237, in = 25.4, lbf_per_in = 4.4482216152605 / 25.4;
  double m_l = 0.270 * lbm, m_pr = 0.114 * lbm, j_ra = 0.132 * lbm * in * in, m_vs = 0.251 * lbm,
         m_cs = 0.153 * lbm, l_pr = 0.875 * in, l_vs = 1.4875 * in, k_cs = 230 * lbf_per_in,
         k_pr = 3.0e5 * lbf_per_in;
};

// the handbook's pushrod valve gear as a design: lifter, pushrod with the axial stiffness
// K_pr, rocker (inertia J about its pivot, arms l_pr and l_vs), valve, a spring without surge
// masses (1/3 of its mass on the valve, as in the book); eccentric R 15 mm, e 3 mm. The
// book's contacts are rigid: linear contact laws of 1e8 N/mm
std::string cdh11_toml(const Cdh11& d) {
  const std::string valve_x = num(d.l_pr + d.l_vs);
  const std::string rigid = "materials = [\"steel\", \"steel\"]\nwidth_mm = 10\nlaw = \"linear\"\nstiffness_N_per_mm = 1e8\n";
  return R"(schema = 1

[design]
name = "cdh11_pushrod"
output_node = "valve"

[driver]
node = "cam"

[[node]]
name = "cam"
type = "rotational"
pivot_mm = [0, 0]

[[node]]
name = "lifter"
type = "translational"
origin_mm = [0, 12]
direction = [0, 1]
mass_kg = )" + num(d.m_l) + R"(

[[node]]
name = "pushrod"
type = "translational"
origin_mm = [0, 43]
direction = [0, 1]
mass_kg = )" + num(d.m_pr) + R"(
axial_stiffness_N_per_mm = )" + num(d.k_pr) + R"(

[[node]]
name = "rocker"
type = "rotational"
pivot_mm = [)" + num(d.l_pr) + R"(, 203]
inertia_kg_mm2 = )" + num(d.j_ra) + R"(

[[node]]
name = "valve"
type = "translational"
origin_mm = [)" + valve_x + R"(, 203]
direction = [0, -1]
mass_kg = )" + num(d.m_vs) + R"(

[[profile]]
name = "disc"
form = "eccentric"
disc_radius_mm = 15
eccentricity_mm = 3

[[material]]
name = "steel"
youngs_modulus_GPa = 210
poisson_ratio = 0.3

[[connection]]
name = "cam_lifter"
type = "contact"
a = { node = "cam", shape = "profile", profile = "disc", orientation_deg = -90 }
b = { node = "lifter", shape = "line", point_mm = [0, 12], normal = [0, -1] }
)" + rigid + R"(
[[connection]]
name = "lifter_pushrod"
type = "contact"
a = { node = "lifter", shape = "line", point_mm = [0, 40], normal = [0, 1] }
b = { node = "pushrod", shape = "circle", center_mm = [0, 43], radius_mm = 3 }
)" + rigid + R"(
[[connection]]
name = "pushrod_rocker"
type = "contact"
a = { node = "pushrod", shape = "circle", center_mm = [0, 200], radius_mm = 3 }
b = { node = "rocker", shape = "line", point_mm = [0, 203], normal = [0, -1] }
)" + rigid + R"(
[[connection]]
name = "rocker_valve"
type = "contact"
a = { node = "rocker", shape = "circle", center_mm = [)" + valve_x + R"(, 213], radius_mm = 10 }
b = { node = "valve", shape = "line", point_mm = [)" + valve_x + R"(, 203], normal = [0, 1] }
)" + rigid + R"(
[[spring]]
name = "valve_spring"
type = "compression"
node = "valve"
rate_N_per_mm = )" + num(d.k_cs) + R"(
preload_N = 400
mass_kg = )" + num(d.m_cs) + "\n";
}

std::vector<double> numbers(const nlohmann::json& j) { return j.get<std::vector<double>>(); }

// the valve (end mass M) hanging on a chain of N equal masses m and N + 1 springs K, the
// chain's other end held: u_n = sin(n theta) solves every chain mass's equation with
// w^2 = (4K/m) sin^2(theta/2), u_0 = 0; the valve's M w^2 u_{N+1} = K (u_{N+1} - u_N) gives
// 4 (M/m) sin^2(theta/2) sin((N+1) theta) = sin((N+1) theta) - sin(N theta): its N + 1
// roots in (0, pi) by sign changes on a fine grid and bisection -> frequencies [Hz]
std::vector<double> fixed_free_chain_Hz(int n, double k_N_per_m, double m_kg, double end_mass_kg) {
  const double mu = end_mass_kg / m_kg;
  auto g = [&](double t) {
    const double s = std::sin(0.5 * t);
    return 4 * mu * s * s * std::sin((n + 1) * t) - std::sin((n + 1) * t) + std::sin(n * t);
  };
  std::vector<double> f;
  const int grid = 200000;
  double a = 1e-9, ga = g(a);
  for (int i = 1; i <= grid; ++i) {
    const double b = camopt::pi * i / grid, gb = g(b);
    if ((ga > 0) != (gb > 0)) {
      double lo = a, hi = b;
      for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
        const double mid = 0.5 * (lo + hi);
        if ((g(mid) > 0) == (g(lo) > 0))
          lo = mid;
        else
          hi = mid;
      }
      f.push_back(2 * std::sqrt(k_N_per_m / m_kg) * std::sin(0.25 * (lo + hi)) / (2 * camopt::pi));
    }
    a = b;
    ga = gb;
  }
  return f;
}

}  // namespace

TEST_CASE("camopt dynamics --model modes: spring alone, mass-normalised shapes (direct-acting valve, 8 coil masses)",
          "[dynamics][cli][modes]") {
  TempDir tmp;
  const fs::path design = tmp / "valve.toml", out = tmp / "out";
  const int n = 8;
  write_text(design, direct_valve_toml(n));
  // 90 cam deg: the valve 4 mm open (its seat open), the cam contact held; no --rpm needed
  const auto r = run_camopt({"dynamics", design.string(), "--model", "modes", "--cam-deg", "90", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);

  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  CHECK(j["model"] == "modes");
  CHECK(j["design"] == "modes_direct_valve");
  CHECK(j["driver_contacts"] == "held");
  REQUIRE(j["results"].size() == 1);
  const auto& res = j["results"][0];
  CHECK(res["cam_deg"].get<double>() == 90.0);
  CHECK_ABS(res["lift_kinematic_mm"].get<double>(), kEccentricity * (1 - std::cos(camopt::pi / 2)), tol::kEccentricSolveAbs);
  const std::vector<double> f = numbers(res["frequencies_Hz"]);
  REQUIRE(f.size() == static_cast<std::size_t>(n + 1));
  CHECK(res["first_frequency_Hz"].get<double>() == f[0]);
  for (std::size_t k = 1; k < f.size(); ++k) CHECK(f[k] >= f[k - 1]);

  // the spring alone, both ends held: N masses m_i = m/(N+1), N+1 segments K = (N+1) k;
  // w_j = 2 sqrt(K/m_i) sin(j pi / (2 (N+1))); the continuous coil f_j = (j/2) sqrt(k/m)
  const auto& spring = j["springs_alone"]["valve_spring"];
  CHECK(spring["surge_masses"] == n);
  const double k = kRate * 1e3, m_i = kSpringMass / (n + 1), seg = (n + 1) * k;  // [N/m], [kg]
  CHECK_REL(spring["coil_mass_kg"].get<double>(), m_i, tol::kUlpRel);
  CHECK_REL(spring["segment_stiffness_N_per_mm"].get<double>(), seg * 1e-3, tol::kUlpRel);
  const std::vector<double> lumped = numbers(spring["surge_frequencies_Hz"]);
  REQUIRE(lumped.size() == static_cast<std::size_t>(n));
  for (int jm = 1; jm <= n; ++jm) {
    const double w = 2 * std::sqrt(seg / m_i) * std::sin(jm * camopt::pi / (2.0 * (n + 1)));
    CHECK_REL(lumped[jm - 1], w / (2 * camopt::pi), tol::kChainEigenRel);
  }
  const std::vector<double> continuum = numbers(spring["continuum_frequencies_Hz"]);
  REQUIRE(continuum.size() == 5u);
  for (int jm = 1; jm <= 5; ++jm)
    CHECK_REL(continuum[jm - 1], 0.5 * jm * std::sqrt(k / kSpringMass), tol::kRearrangedLawRel);

  // modes.csv: one row per mode, a shape column per coordinate with its unit
  const camopt::io::CsvTable csv = camopt::io::parse_csv(read_file(out / "modes.csv"), "modes.csv");
  std::vector<std::string> expected = {"control_deg", "cam_deg", "mode", "frequency_Hz", "tappet_mm_per_sqrt_kg"};
  for (int c = 1; c <= n; ++c) expected.push_back("valve_spring.coil" + std::to_string(c) + "_mm_per_sqrt_kg");
  CHECK(csv.columns == expected);
  REQUIRE(csv.rows() == static_cast<std::size_t>(n + 1));
  for (std::size_t row = 0; row < csv.rows(); ++row) {
    CHECK(csv.values[1][row] == 90.0);
    CHECK(csv.values[2][row] == static_cast<double>(row + 1));
    CHECK(csv.values[3][row] == f[row]);
  }
  // the shapes are M-orthonormal, M from the design's masses [kg]: the valve with half a
  // segment's spring mass, each coil mass m/(N+1)
  std::vector<double> mass = {kValveMass + 0.5 * m_i};
  for (int c = 0; c < n; ++c) mass.push_back(m_i);
  const std::size_t modes = csv.rows(), coords = mass.size();
  for (std::size_t a = 0; a < modes; ++a)
    for (std::size_t b = 0; b < modes; ++b) {
      double p = 0.0;
      for (std::size_t i = 0; i < coords; ++i) p += csv.values[4 + i][a] * mass[i] * csv.values[4 + i][b];
      INFO("modes " << a + 1 << ", " << b + 1);
      CHECK_ABS(p, a == b ? 1.0 : 0.0, tol::kModeOrthonormalAbs);
    }
}

TEST_CASE("camopt dynamics --model modes --release-cam: the valve hangs on its spring chain (fixed-free chain)",
          "[dynamics][cli][modes]") {
  TempDir tmp;
  const fs::path design = tmp / "valve.toml", out = tmp / "out";
  const int n = 8;
  write_text(design, direct_valve_toml(n));
  // the valve open (seat open) and the cam released: only the chain holds the valve, at
  // any lift (the spring is linear)
  const auto r = run_camopt({"dynamics", design.string(), "--model", "modes", "--cam-deg", "90,180", "--release-cam",
                             "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  CHECK(j["driver_contacts"] == "released");
  REQUIRE(j["results"].size() == 2);
  const double m_i = kSpringMass / (n + 1);
  const std::vector<double> expected = fixed_free_chain_Hz(n, (n + 1) * kRate * 1e3, m_i, kValveMass + 0.5 * m_i);
  REQUIRE(expected.size() == static_cast<std::size_t>(n + 1));
  for (const auto& res : j["results"]) {
    const std::vector<double> f = numbers(res["frequencies_Hz"]);
    REQUIRE(f.size() == expected.size());
    for (std::size_t m = 0; m < f.size(); ++m) {
      INFO("cam " << res["cam_deg"].get<double>() << " deg, mode " << m + 1);
      CHECK_REL(f[m], expected[m], tol::kChainEigenRel);
    }
  }
  CHECK(split_lines(read_file(out / "modes.csv")).size() == 1 + 2 * expected.size());
}

TEST_CASE("camopt dynamics --model modes: default cam angles are the driver start and the peak lift",
          "[dynamics][cli][modes]") {
  TempDir tmp;
  const fs::path design = tmp / "valve.toml", out = tmp / "out";
  write_text(design, direct_valve_toml(2));
  const auto r = run_camopt({"dynamics", design.string(), "--model", "modes", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  REQUIRE(j["results"].size() == 2);
  // the eccentric's lift e (1 - cos theta): at rest at 0 deg, 2 e at 180 deg
  CHECK(j["results"][0]["cam_deg"].get<double>() == 0.0);
  CHECK(j["results"][0]["cam_angle_from"] == "driver start");
  CHECK_ABS(j["results"][0]["lift_kinematic_mm"].get<double>(), 0.0, tol::kEccentricSolveAbs);
  CHECK(j["results"][1]["cam_deg"].get<double>() == 180.0);
  CHECK(j["results"][1]["cam_angle_from"] == "peak lift");
  CHECK_ABS(j["results"][1]["lift_kinematic_mm"].get<double>(), 2 * kEccentricity, tol::kEccentricSolveAbs);
  // the valve and 2 coil masses at each angle
  CHECK(split_lines(read_file(out / "modes.csv")).size() == 1 + 2 * 3);
}

TEST_CASE("camopt dynamics --model modes --release-cam: the Cam Design Handbook pushrod valve gear (CDH11)",
          "[dynamics][cli][modes]") {
  TempDir tmp;
  const Cdh11 d;
  const fs::path design = tmp / "cdh11.toml", out = tmp / "out";
  write_text(design, cdh11_toml(d));
  // 10 cam deg: the valve 0.08 mm off its seat, the rocker within 0.2 deg of its drawing
  // position (the book's linear model is the drawing's geometry; at full lift the rocker has
  // turned ~15 deg and the lever ratio with it)
  const auto r = run_camopt({"dynamics", design.string(), "--model", "modes", "--cam-deg", "10", "--release-cam",
                             "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  REQUIRE(j["results"].size() == 1);
  const auto& res = j["results"][0];
  // the valve's kinematic lift, the seat open: lifter and pushrod y = e (1 - cos theta); the
  // rocker's face (a line through its pivot) turned by phi touches the pushrod's 3 mm ball:
  // y = 3 - (3 + l_pr sin phi) / cos phi; its 10 mm pad on the valve: v = 10 - l_vs sin phi - 10 cos phi
  const double y = 3 * (1 - std::cos(10 * camopt::pi / 180));
  double phi = 0.0;
  for (int it = 0; it < 50; ++it)
    phi -= (3 - (3 + d.l_pr * std::sin(phi)) / std::cos(phi) - y) /
           (-(d.l_pr + 3 * std::sin(phi)) / (std::cos(phi) * std::cos(phi)));
  const double lift = 10 - d.l_vs * std::sin(phi) - 10 * std::cos(phi);
  CHECK_REL(res["lift_kinematic_mm"].get<double>(), lift, tol::kTwoSolvePathsRel);
  CHECK(lift > 0.07);
  const std::vector<double> f = numbers(res["frequencies_Hz"]);
  // lifter, pushrod (both ends), rocker, valve
  REQUIRE(f.size() == 5u);
  const auto header = split_lines(read_file(out / "modes.csv"))[0];
  CHECK(header == "control_deg,cam_deg,mode,frequency_Hz,lifter_mm_per_sqrt_kg,pushrod_mm_per_sqrt_kg,rocker_rad_per_sqrt_kg,"
                  "valve_mm_per_sqrt_kg,pushrod.far_mm_per_sqrt_kg");
  INFO("modes " << f[0] << ", " << f[1] << ", " << f[2] << " Hz");
  // two-mass model from the same data: m1 = m_l + m_pr/2 (cam released), K1 = K_pr,
  // m2 = m_pr/2 + (J + (m_vs + m_cs/3) l_vs^2) / l_pr^2, K2 = K_cs (l_vs/l_pr)^2 [kg, N/mm -> t, N/mm]
  const double ratio = d.l_vs / d.l_pr;
  const double m1 = 1e-3 * (d.m_l + d.m_pr / 2),
               m2 = 1e-3 * (d.m_pr / 2 + d.j_ra / (d.l_pr * d.l_pr) + (d.m_vs + d.m_cs / 3) * ratio * ratio);
  const double k1 = d.k_pr, k2 = d.k_cs * ratio * ratio;
  const double a = m1 * m2, b = -(k1 * m2 + (k1 + k2) * m1), c = k1 * k2;
  const double w_lo = std::sqrt((-b - std::sqrt(b * b - 4 * a * c)) / (2 * a)),
               w_hi = std::sqrt((-b + std::sqrt(b * b - 4 * a * c)) / (2 * a));
  CHECK_REL(f[0], w_lo / (2 * camopt::pi), tol::kTwoMassTurnedRockerRel);
  CHECK_REL(f[1], w_hi / (2 * camopt::pi), tol::kTwoMassTurnedRockerRel);
  // the book: 67 and 3400 Hz (recomputed from its rounded m1, m2, K: 67.2, 3411)
  CHECK_REL(f[0], 67.2, tol::kHandbookRoundedDataRel);
  CHECK_REL(f[1], 3411, tol::kHandbookRoundedDataRel);
}

namespace {
bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
const std::string kCvvlDesign = (source_dir() / "designs/cvvl_swing_cam.toml").string();
}  // namespace

TEST_CASE("dynamics --model modes: a cam angle that is not a number is an input error naming --cam-deg",
          "[cli][dynamics][modes]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  for (const std::string& angles : {std::string("abc"), std::string("30,abc")}) {
    const auto r = run_camopt({"dynamics", kCvvlDesign, "--model", "modes", "--cam-deg", angles, "--out", out.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(has(r.err, "--cam-deg"));
    CHECK(has(r.err, "'abc'"));
    CHECK(files_under(out).empty());
  }
}

TEST_CASE("dynamics --model modes: a control position out of range is an input error naming --control",
          "[cli][dynamics][modes]") {
  TempDir tmp;
  const fs::path out = tmp / "out";
  // the CVVL's control shaft runs from 0 to 16 deg
  const auto r = run_camopt({"dynamics", kCvvlDesign, "--model", "modes", "--control", "99", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(has(r.err, "--control: value 99 is outside control 'shaft' range [0, 16]"));
  CHECK(files_under(out).empty());
}

TEST_CASE("dynamics: --rpm is required by the rigid and flexible models, not by modes", "[cli][dynamics][modes]") {
  TempDir tmp;
  for (const char* model : {"rigid", "flexible"}) {
    const fs::path out = tmp / model;
    const auto r = run_camopt({"dynamics", kCvvlDesign, "--model", model, "--out", out.string()});
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_usage_error);
    CHECK(has(r.err, "--rpm is required"));
    CHECK(files_under(out).empty());
  }
  const fs::path out = tmp / "modes";
  const auto r = run_camopt({"dynamics", kCvvlDesign, "--model", "modes", "--control", "0,16", "--out", out.string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  // two control positions x (driver start, peak lift), a row per mode, as many modes as
  // coordinates (the shape columns after the first four)
  const auto lines = split_lines(read_file(out / "modes.csv"));
  REQUIRE(lines.size() > 1);
  CHECK(lines[0].rfind("control_deg,cam_deg,mode,frequency_Hz,", 0) == 0);
  const auto columns = static_cast<std::size_t>(std::count(lines[0].begin(), lines[0].end(), ',') + 1);
  CHECK(lines.size() - 1 == 2 * 2 * (columns - 4));
}
