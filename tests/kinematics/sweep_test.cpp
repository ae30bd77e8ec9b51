// a run computes only the outputs it asked for (the brief: "skip what a scene doesn't
// need"), beyond what its continuation needs: the Taylor series to order 3 at every point
// (the predictor and the step control use them, whatever is requested, so every request
// takes the same steps and gives the same values). The solver's work counters show that a
// lift-only sweep and a derivative sweep do the same continuation work and compute no
// contact quantity, and that a lift-only sweep returns no derivative.
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
      CHECK(p.stats.contact_outputs == 0);
      CHECK(p.contacts.empty());
      for (std::size_t i = 0; i < lift.driver.size(); ++i)
        for (std::size_t v = 0; v < nv; ++v)
          for (int k = 1; k <= 3; ++k) CHECK(p.at(i, nv, static_cast<int>(v), k) == 0.0);
    }

    spec.request = {3, false};
    const auto deriv = kin::sweep(m, spec);
    for (std::size_t q = 0; q < deriv.positions.size(); ++q) {
      const auto& p = deriv.positions[q];
      REQUIRE(p.status.ok());
      CHECK(p.stats.taylor_orders + p.stats.jet_closed_forms > 0);
      CHECK(p.stats.contact_outputs == 0);
      CHECK(p.contacts.empty());
      // the same continuation as lift only: the same work and the same values
      const auto& l = lift.positions[q];
      CHECK(p.stats.points == l.stats.points);
      CHECK(p.stats.rejected_steps == l.stats.rejected_steps);
      CHECK(p.stats.taylor_orders == l.stats.taylor_orders);
      CHECK(p.stats.jet_closed_forms == l.stats.jet_closed_forms);
      for (std::size_t i = 0; i < deriv.driver.size(); ++i)
        for (std::size_t v = 0; v < nv; ++v) CHECK(p.at(i, nv, static_cast<int>(v), 0) == l.at(i, nv, static_cast<int>(v), 0));
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
