// camopt dynamics --model rigid with an [oil] table: the EHL columns and summary fields.
// The flat (bucket) tappet's entrainment column against the closed form of a flat-faced
// translating follower, u_e = omega (r_b + L + 2 L'') / 2: the cam surface moves past the
// contact at omega (r_b + L + L''), the face at omega L'' (the contact sits L' off the axis)
// (Dowson, Harrison & Taylor, "The lubrication of automotive cams and followers", Leeds-Lyon
// Symposium 1986; the same speeds in the EHL study behind the bundled design), and its film
// column against the Dowson-Higginson formula evaluated here from that closed form, the
// cam's radius of curvature r_b + L + L'' and the force column.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "cli/cli_support.hpp"
#include "support/compare.hpp"

using namespace camopt::test;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// the columns of a CSV by name; an empty cell reads as NaN
std::map<std::string, std::vector<double>> columns_of(const std::string& csv) {
  const auto lines = split_lines(csv);
  std::vector<std::string> names;
  std::stringstream head(lines[0]);
  for (std::string n; std::getline(head, n, ',');) names.push_back(n);
  std::map<std::string, std::vector<double>> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::size_t k = 0, from = 0;
    for (;; ++k) {
      const std::size_t to = lines[i].find(',', from);
      const std::string cell = lines[i].substr(from, to == std::string::npos ? std::string::npos : to - from);
      out[names.at(k)].push_back(cell.empty() ? kNaN : std::stod(cell));
      if (to == std::string::npos) break;
      from = to + 1;
    }
    REQUIRE(k + 1 == names.size());
  }
  return out;
}

// Dowson-Higginson in dimensional form [m]: 2.65 alpha^0.54 (eta0 u)^0.7 R^0.43 / (E'^0.03 w^0.13)
double film_m(double u, double w, double r, double eta, double alpha, double e_prime) {
  return 2.65 * std::pow(alpha, 0.54) * std::pow(eta * std::abs(u), 0.70) * std::pow(r, 0.43) /
         (std::pow(e_prime, 0.03) * std::pow(w, 0.13));
}

}  // namespace

TEST_CASE("camopt dynamics --model rigid: a flat tappet's entrainment and film against the closed form",
          "[dynamics][cli][ehl]") {
  TempDir tmp;
  const std::string design = (source_dir() / "designs/bucket_tappet.toml").string();
  const auto k = run_camopt({"kinematics", design, "--step", "0.5", "--outputs", "lift,velocity,acceleration",
                             "--out", (tmp / "kin").string()});
  INFO(k.command << "\n" << k.all());
  REQUIRE(k.exit_code == cli_ok);
  // 2000 rpm: below the separation speed (11140 rpm); 13000 rpm: the contact opens on the nose
  const auto r = run_camopt({"dynamics", design, "--model", "rigid", "--rpm", "2000,13000", "--step", "0.5", "--out",
                             (tmp / "dyn").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  auto kin = columns_of(read_file(tmp / "kin/kinematics.csv"));
  auto dyn = columns_of(read_file(tmp / "dyn/dynamics.csv"));
  for (const char* name : {"contact_cam_tappet_entrainment_m_per_s", "contact_cam_tappet_film_thickness_um",
                           "contact_cam_tappet_lambda", "contact_cam_tappet_force_N"})
    REQUIRE(dyn.count(name) == 1);
  const std::size_t np = kin["cam_deg"].size();
  REQUIRE(np == 721);
  REQUIRE(dyn["cam_deg"].size() == 2 * np);

  // the design: base circle and face at 18.5 mm, contact 7.2 mm wide, steel on steel, oil
  // 9.1 mPa s and 15.8 /GPa, composite roughness 0.25 um
  const double rb = 18.5, width = 7.2, sigma = 0.25;
  const double e_prime = 2 * 210e9 / (2 * (1 - 0.3 * 0.3));  // [Pa]
  const double deg = camopt::pi / 180;
  Series entrainment("contact_cam_tappet_entrainment_m_per_s", "row"),
      film_um("contact_cam_tappet_film_thickness_um", "row");
  int empty = 0, sign_changes = 0;
  std::vector<double> crossings;
  for (std::size_t row = 0; row < 2 * np; ++row) {
    const std::size_t i = row % np;
    REQUIRE(dyn["cam_deg"][row] == kin["cam_deg"][i]);
    const double w = dyn["rpm"][row] / 2 * 2 * camopt::pi / 60;  // cam speed [rad/s]
    const double L = kin["lift_mm"][i], L2 = kin["acc_mm_per_deg2"][i] / (deg * deg);  // [mm], [mm/rad^2]
    const double ue = w * (rb + L + 2 * L2) / 2 * 1e-3;                                   // [m/s]
    const double u_col = dyn["contact_cam_tappet_entrainment_m_per_s"][row];
    entrainment.add(static_cast<double>(row), u_col, ue);
    if (row % np > 0 && u_col * dyn["contact_cam_tappet_entrainment_m_per_s"][row - 1] < 0) {
      ++sign_changes;
      if (row < np) crossings.push_back(dyn["cam_deg"][row]);
    }
    const double force = dyn["contact_cam_tappet_force_N"][row];
    const double h_col = dyn["contact_cam_tappet_film_thickness_um"][row];
    const double lambda = dyn["contact_cam_tappet_lambda"][row];
    if (!(force > 0)) {
      // a separated contact has no film: an empty cell, never NaN text
      CHECK(std::isnan(h_col));
      CHECK(std::isnan(lambda));
      ++empty;
      continue;
    }
    const double rho = rb + L + L2;  // cam radius of curvature, the face flat [mm]
    REQUIRE(rho > 0);
    const double h = film_m(ue, force / (width * 1e-3), rho * 1e-3, 9.1e-3, 15.8e-9, e_prime) * 1e6;  // [um]
    film_um.add(static_cast<double>(row), h_col, h);
    CHECK_REL(lambda, h_col / sigma, tol::kCsvDerivedRel);
  }
  INFO(empty << " separated points; u_e changes sign at 2000 rpm near cam "
             << (crossings.empty() ? -1.0 : crossings.front()) << " and "
             << (crossings.size() > 1 ? crossings[1] : -1.0) << " deg");
  // the kinematic solver's contact geometry against the lift's own exact derivatives, both
  // read from CSVs of shortest round-trip numbers: 3.0e-11 of 40.5 m/s (7.5e-13) measured
  CHECK_SERIES(entrainment.compare({.rel = tol::kCsvContactRel}));
  // the formula on the closed-form kinematics: 2.4e-12 of 2.36 um (1.0e-12) measured
  CHECK_SERIES(film_um.compare({.rel = tol::kCsvContactRel}));
  // the contact opens over the nose at 13000 rpm, never at 2000 rpm
  CHECK(empty > 0);
  for (std::size_t i = 0; i < np; ++i) CHECK(dyn["contact_cam_tappet_force_N"][i] > 0);
  // the entrainment reverses where 2 L'' < -(r_b + L), twice on the way over the nose, at
  // every speed (it scales with omega)
  CHECK(sign_changes == 4);
  REQUIRE(crossings.size() == 2);

  // summary: per (rpm, control) the thinnest film and lambda with their cam angle; per
  // control position over every rpm, with the rpm
  const auto j = nlohmann::json::parse(read_file(tmp / "dyn/summary.json"));
  for (int run = 0; run < 2; ++run) {
    double thinnest = std::numeric_limits<double>::infinity(), at = 0;
    for (std::size_t i = 0; i < np; ++i) {
      const double h = dyn["contact_cam_tappet_film_thickness_um"][run * np + i];
      if (h < thinnest) thinnest = h, at = dyn["cam_deg"][run * np + i];
    }
    const auto& c = j["results"][run]["connections"]["cam_tappet"];
    CHECK_REL(c["min_film_thickness_um"].get<double>(), thinnest, tol::kCsvDerivedRel);
    CHECK(c["min_film_thickness_at_cam_deg"].get<double>() == at);
    CHECK_REL(c["min_lambda"].get<double>(), thinnest / sigma, tol::kCsvDerivedRel);
    CHECK(c["min_lambda_at_cam_deg"].get<double>() == at);
  }
  const auto& film = j["film"][0]["contacts"]["cam_tappet"];
  const double f2000 = j["results"][0]["connections"]["cam_tappet"]["min_film_thickness_um"].get<double>();
  const double f13000 = j["results"][1]["connections"]["cam_tappet"]["min_film_thickness_um"].get<double>();
  CHECK(film["min_film_thickness_um"].get<double>() == std::min(f2000, f13000));
  CHECK(film["at_rpm"].get<double>() == (f2000 <= f13000 ? 2000.0 : 13000.0));
  CHECK_REL(film["min_lambda"].get<double>(), std::min(f2000, f13000) / sigma, tol::kSummaryOfSameRel);
}

TEST_CASE("camopt dynamics --model rigid: film columns for every Hertz contact with [oil], none without it",
          "[dynamics][cli][ehl]") {
  TempDir tmp;
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/roller_finger_follower.toml").string(), "--model",
                             "rigid", "--rpm", "6000", "--step", "1", "--out", (tmp / "rff").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string csv = read_file(tmp / "rff/dynamics.csv");
  CHECK(csv.find("nan") == std::string::npos);
  auto c = columns_of(csv);
  for (const char* contact : {"cam_roller", "pad_valve"}) {
    INFO(contact);
    const std::string n = std::string("contact_") + contact + "_";
    REQUIRE(c.count(n + "film_thickness_um") == 1);
    REQUIRE(c.count(n + "lambda") == 1);
    // a film wherever the contact pushes (both surfaces convex or flat), none elsewhere
    for (std::size_t i = 0; i < c["cam_deg"].size(); ++i)
      CHECK(std::isnan(c[n + "film_thickness_um"][i]) == !(c[n + "force_N"][i] > 0));
  }
  const auto j = nlohmann::json::parse(read_file(tmp / "rff/summary.json"));
  CHECK(j["film"][0]["contacts"]["cam_roller"]["min_film_thickness_um"].get<double>() > 0);
  // the valve at rest on the base circle: neither the pad nor the tip moves, no film
  CHECK(j["film"][0]["contacts"]["pad_valve"]["min_film_thickness_um"].get<double>() == 0.0);
  CHECK(j["film"][0]["contacts"]["pad_valve"]["at_rpm"].get<double>() == 6000.0);

  // without composite_roughness_um: the film but no lambda; without [oil]: neither
  std::string text = read_file(source_dir() / "designs/bucket_tappet.toml");
  const std::string profiles = (source_dir() / "designs/profiles/").string();
  text = std::regex_replace(text, std::regex("file = \"profiles/"), "file = \"" + profiles);
  const std::string no_roughness = std::regex_replace(text, std::regex("composite_roughness_um = [^\n]*\n"), "");
  write_text(tmp / "no_roughness.toml", no_roughness);
  const std::string no_oil = std::regex_replace(no_roughness, std::regex("\\[oil\\][^\\[]*$"), "");
  write_text(tmp / "no_oil.toml", no_oil);
  for (const char* name : {"no_roughness", "no_oil"}) {
    const auto run = run_camopt({"dynamics", (tmp / (std::string(name) + ".toml")).string(), "--rpm", "2000", "--step",
                                 "2", "--out", (tmp / name).string()});
    INFO(run.command << "\n" << run.all());
    REQUIRE(run.exit_code == cli_ok);
    const std::string header = split_lines(read_file(tmp / name / "dynamics.csv"))[0];
    const bool has_oil = name == std::string("no_roughness");
    CHECK((header.find("contact_cam_tappet_film_thickness_um") != std::string::npos) == has_oil);
    CHECK(header.find("lambda") == std::string::npos);
    const auto s = nlohmann::json::parse(read_file(tmp / name / "summary.json"));
    CHECK(s.contains("film") == has_oil);
  }
}

TEST_CASE("camopt validate shows the design's oil", "[dynamics][cli][ehl]") {
  const auto r = run_camopt({"validate", (source_dir() / "designs/bucket_tappet.toml").string()});
  INFO(r.command << "\n" << r.all());
  REQUIRE(r.exit_code == cli_ok);
  CHECK(r.out.find("oil: viscosity 9.1 mPa s, pressure-viscosity 15.8 /GPa, composite roughness 0.25 um") !=
        std::string::npos);
}
