#include "fuzz_entry.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "camopt/core/error.hpp"
#include "camopt/io/constraint_file.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/target_lift.hpp"

#ifndef CAMOPT_SOURCE_DIR
#error "CAMOPT_SOURCE_DIR must name the source tree (relative profile files resolve in designs/)"
#endif

namespace camopt::fuzz {
namespace {

[[noreturn]] void fail(const char* target, const std::string& why) {
  std::fprintf(stderr, "fuzz target %s: %s\n", target, why.c_str());
  std::abort();
}

// runs `body`: true when it returns, false on InputError (the one way to reject an
// input); anything else aborts
template <class Body>
bool run(const char* target, Body&& body) {
  try {
    body();
    return true;
  } catch (const InputError&) {
    return false;
  } catch (const std::exception& e) {
    fail(target, std::string("unexpected exception: ") + e.what());
  }
}

}  // namespace

bool target_lift_csv(std::string_view bytes) {
  io::AngleTable at;
  if (!run("target_lift_csv", [&] {
        at = io::read_angle_table(io::parse_csv(bytes, "fuzz.csv"), {"lift_mm", "valve_lift_mm", "tappet_lift_mm"});
        if (at.basis == io::AngleBasis::crank)
          for (double& a : at.angle_deg) a /= 2;  // a four-stroke camshaft
      }))
    return false;
  bool accepted = false;
  for (const bool smooth : {false, true}) {
    accepted |= run("target_lift_csv", [&] {
      synthesis::TargetLiftOptions options;
      options.smooth = smooth;
      options.source = "fuzz.csv";
      const synthesis::TargetLift fit = synthesis::fit_target_lift(at.angle_deg, at.value, at.lines, options);
      for (double deg = 0; deg < 360; deg += 7.5)
        if (!std::isfinite(fit.lift_at(deg))) fail("target_lift_csv", "non-finite lift at " + std::to_string(deg));
      if (!std::isfinite(fit.max_lift_mm) || !std::isfinite(fit.residual_max_mm))
        fail("target_lift_csv", "non-finite fit summary");
    });
  }
  return accepted;
}

bool design_toml(std::string_view bytes) {
  return run("design_toml", [&] {
    const DesignSpec spec = io::parse_design(bytes, "fuzz.toml", CAMOPT_SOURCE_DIR "/designs");
    const kin::Mechanism mech = kin::compile(spec);
    (void)kin::describe(mech);
    kin::SweepSpec sweep;
    sweep.start = 0;
    sweep.stop = 330;
    sweep.step = 30;
    sweep.request.derivative_order = 3;
    sweep.request.contacts = true;
    const kin::SweepResult result = kin::sweep(mech, sweep);
    for (const kin::PositionResult& position : result.positions) {
      if (!position.status.ok()) continue;  // a numerical outcome, reported with its angle
      for (const double v : position.data)
        if (!std::isfinite(v)) fail("design_toml", "solve reported ok with a non-finite output");
    }
  });
}

bool constraint_toml(std::string_view bytes) {
  return run("constraint_toml", [&] { (void)io::parse_constraints(bytes, "fuzz.toml", CAMOPT_SOURCE_DIR "/constraints"); });
}

}  // namespace camopt::fuzz
