// a run computes only the outputs it asked for (the brief: "skip what a scene doesn't
// need"): the solver's work counters show that a lift-only sweep solves no Taylor order,
// runs no closed form on jets and computes no contact quantity, and that derivatives
// without contact outputs compute no contact quantity.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"

using namespace camopt;

namespace {
int contact_count(const kin::Mechanism& m) {
  int n = 0;
  for (const auto& c : m.connections) n += c.kind == ConnectionKind::contact ? 1 : 0;
  return n;
}
}  // namespace

TEST_CASE("sweeps compute only the requested outputs, on every bundled design", "[kinematics][outputs]") {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CAMOPT_SOURCE_DIR) + "/designs"))
    if (e.path().extension() == ".toml") files.push_back(e.path().string());
  REQUIRE(files.size() >= 11);
  for (const auto& file : files) {
    INFO(file);
    const auto m = kin::compile(io::load_design(file));
    const std::size_t nv = m.variables.size();
    kin::SweepSpec spec;
    spec.step = 2.0;
    // a position away from the drawing too: its continuation must not compute outputs either
    if (!m.controls.empty()) spec.control_positions = {{m.controls[0].default_value}, {m.controls[0].max}};

    spec.request = {0, false};
    const auto lift = kin::sweep(m, spec);
    for (const auto& p : lift.positions) {
      REQUIRE(p.status.ok());
      CHECK(p.stats.points >= static_cast<long>(lift.driver.size()));
      // the continuation from the drawing and the points of a halved step are solved with
      // derivatives (their predictor needs them); the requested points are not. Lift only
      // from the drawing without a halved step: no derivative at all.
      const bool from_drawing = m.controls.empty() || p.controls == std::vector<double>{m.controls[0].default_value};
      if (from_drawing && p.stats.rejected_steps == 0) {
        CHECK(p.stats.taylor_orders == 0);
        CHECK(p.stats.jet_closed_forms == 0);
      }
      CHECK(p.stats.contact_outputs == 0);
      CHECK(p.contacts.empty());
      for (std::size_t i = 0; i < lift.driver.size(); ++i)
        for (std::size_t v = 0; v < nv; ++v)
          for (int k = 1; k <= 3; ++k) CHECK(p.at(i, nv, static_cast<int>(v), k) == 0.0);
    }

    spec.request = {3, false};
    const auto deriv = kin::sweep(m, spec);
    for (const auto& p : deriv.positions) {
      REQUIRE(p.status.ok());
      CHECK(p.stats.taylor_orders + p.stats.jet_closed_forms > 0);
      CHECK(p.stats.contact_outputs == 0);
      CHECK(p.contacts.empty());
    }

    spec.request = {3, true};
    const auto all = kin::sweep(m, spec);
    const long contacts = contact_count(m);
    for (const auto& p : all.positions) {
      REQUIRE(p.status.ok());
      // every requested point, every contact, once (continuation points: none)
      CHECK(p.stats.contact_outputs == contacts * static_cast<long>(all.driver.size()));
    }
  }
}
