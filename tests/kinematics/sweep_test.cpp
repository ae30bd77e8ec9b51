// kin::sweep: its error contract (a bad spec is an InputError naming the field, the value
// and the rule; an exception in a worker thread reaches the caller), and a run computes
// only the outputs it asked for, beyond what its continuation needs: the Taylor series to
// order 3 at every point (the predictor and the step control use them, whatever is requested, so every request
// takes the same steps and gives the same values). The solver's work counters show that a
// lift-only sweep and a derivative sweep do the same continuation work and compute no
// contact quantity, and that a lift-only sweep returns no derivative.
#include <atomic>
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::test::tol;

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
          for (int k = 1; k <= 3; ++k) CHECK(p.value(i, static_cast<int>(v), k) == 0.0);
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
        for (std::size_t v = 0; v < nv; ++v) CHECK(p.value(i, static_cast<int>(v), 0) == l.value(i, static_cast<int>(v), 0));
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

namespace {
kin::Mechanism bundled(const std::string& name) {
  return kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml"));
}
}  // namespace

TEST_CASE("sweep: a bad spec is an InputError naming the field, the value and the rule", "[kinematics][sweep]") {
  const kin::Mechanism m = bundled("bucket_tappet");
  kin::SweepSpec spec;
  spec.step = 0.0;
  CHECK_THROWS_AS(kin::sweep(m, spec), InputError);
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("sweep step = 0 must be > 0"));
  spec.step = 1.0;
  spec.start = 10.0;
  spec.stop = 5.0;
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("sweep stop = 5 must be >= start = 10"));
  spec.stop = NAN;
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("sweep stop = nan must be finite"));
  spec = {};
  spec.request = {4, false};
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("request.derivative_order = 4 must be in [0, 3]"));
  spec.request = {0, true};
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("request.contacts = true needs request.derivative_order >= 1"));
  spec = {};
  spec.control_positions = {{1.0, 2.0}};
  CHECK_THROWS_AS(kin::sweep(m, spec), InputError);
  CHECK_THROWS_WITH(kin::sweep(m, spec), Catch::Contains("sweep control_positions[0] has 2 value(s)"));
}

TEST_CASE("sweep: an exception in a worker thread reaches the caller", "[kinematics][sweep]") {
  const kin::Mechanism m = bundled("cvvl_swing_cam");
  REQUIRE(!m.controls.empty());
  kin::SweepSpec spec;
  spec.step = 30.0;
  spec.request = {0, false};
  spec.threads = 2;
  for (int k = 0; k < 4; ++k) spec.control_positions.push_back(m.default_controls());
  // the caller's thread waits in its first progress call until a worker thread has run one
  // (so the worker thread surely takes a position); the worker thread throws
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> worker_ran{false};
  spec.on_position_done = [&] {
    if (std::this_thread::get_id() != caller) {
      worker_ran = true;
      throw InputError("a bad argument found inside the worker");
    }
    for (int i = 0; i < 10000 && !worker_ran; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  CHECK_THROWS_AS(kin::sweep(m, spec), InputError);
  CHECK(worker_ran);
  worker_ran = false;  // the second run waits for its worker thread again
  CHECK_THROWS_WITH(kin::sweep(m, spec), "a bad argument found inside the worker");
  CHECK(worker_ran);
}

TEST_CASE("sweep: periodic_motion rejects a bad step and a node that is not a body", "[kinematics][sweep]") {
  const kin::Mechanism m = bundled("bucket_tappet");
  PeriodicSpline motion;
  CHECK_THROWS_AS((void)kin::periodic_motion(m, m.output_node, {}, 0.0, motion), InputError);
  CHECK_THROWS_WITH((void)kin::periodic_motion(m, m.output_node, {}, 0.0, motion),
                    Catch::Contains("periodic_motion: step_deg = 0 must be in (0, 360)"));
  CHECK_THROWS_WITH((void)kin::periodic_motion(m, 0, {}, 1.0, motion),
                    Catch::Contains("periodic_motion: node = 0 must be a body index"));
}

TEST_CASE("sweep: output_lift is the output node's travel from rest and value() its raw series", "[kinematics][sweep]") {
  // the rocker arm's valve (translational, mm) and the four-bar's rocker (rotational, deg)
  for (const char* name : {"rocker_arm", "four_bar"}) {
    INFO(name);
    const kin::Mechanism m = bundled(name);
    kin::SweepSpec spec;
    spec.step = 2.0;
    const kin::SweepResult r = kin::sweep(m, spec);
    const kin::PositionResult& p = r.positions.front();
    REQUIRE(p.status.ok());
    REQUIRE(p.variables == m.variables.size());
    const kin::Node& out = m.nodes[static_cast<std::size_t>(m.output_node)];
    const bool angle = m.variables[static_cast<std::size_t>(out.first_variable)].is_angle;
    const double rest = angle ? out.rest * 180.0 / std::numbers::pi : out.rest;  // [deg or mm]
    double peak = 0.0;
    for (std::size_t i = 0; i < r.driver.size(); ++i) {
      const double raw = p.data[(i * p.variables + static_cast<std::size_t>(out.first_variable)) * 4];
      CHECK(p.value(i, out.first_variable) == raw);
      CHECK_ABS(kin::output_lift(m, p, i), raw - rest, kOutputLiftRel * std::max(1.0, std::abs(raw)));
      for (int k = 1; k <= 3; ++k) CHECK(kin::output_lift(m, p, i, k) == p.value(i, out.first_variable, k));
      peak = std::max(peak, kin::output_lift(m, p, i));
    }
    // the summary's peak is refined between grid points: never below the grid's, and close to it
    const kin::PositionSummary s = kin::summarize(m, r, 0);
    CHECK(s.max_lift >= peak - kGridPeakAbs);
    CHECK_NEAR(s.max_lift, peak, kRefinedPeakAbs, kRefinedPeakRel);
  }
  const kin::Mechanism m = bundled("rocker_arm");
  kin::SweepSpec spec;
  spec.step = 90.0;
  const kin::SweepResult r = kin::sweep(m, spec);
  CHECK_THROWS_AS(kin::output_lift(m, r.positions[0], r.driver.size()), InputError);
  CHECK_THROWS_WITH(kin::output_lift(m, r.positions[0], 0, 4), Catch::Contains("order 4 must be 0..3"));
}
