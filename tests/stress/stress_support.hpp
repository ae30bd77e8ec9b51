#pragma once
// shared pieces of the stress suite (tests/stress): the run count and seed (raised from the
// environment: CAMOPT_STRESS_COUNT, CAMOPT_STRESS_SEED), designs written as TOML text and
// read by the real parser, and a check that a result holds no NaN / Inf.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/sweep.hpp"

namespace camopt::stress {

inline long env_long(const char* name, long fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  REQUIRE(end != text);
  REQUIRE(*end == '\0');
  return value;
}

// number of random cases per family; CAMOPT_STRESS_COUNT raises it for a longer run
inline int stress_count(int fallback) { return static_cast<int>(env_long("CAMOPT_STRESS_COUNT", fallback)); }
inline std::mt19937_64 stress_rng() { return std::mt19937_64(static_cast<unsigned long>(env_long("CAMOPT_STRESS_SEED", 20261121))); }

// full precision for coordinates written into TOML
inline std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
inline std::string point(double x, double y) { return "[" + num(x) + ", " + num(y) + "]"; }

inline kin::Mechanism compile_text(const std::string& toml) {
  return kin::compile(io::parse_design(toml, "stress.toml", CAMOPT_SOURCE_DIR "/designs"));
}

// a sweep of the default control position over one revolution, every output
inline kin::SweepResult revolution(const kin::Mechanism& mech, double step_deg, bool contacts = true) {
  kin::SweepSpec spec;
  spec.start = 0;
  spec.stop = 360;
  spec.step = step_deg;
  spec.request.derivative_order = 3;
  spec.request.contacts = contacts;
  return kin::sweep(mech, spec);
}

// every number of a successful position is finite
inline void require_finite(const kin::PositionResult& position) {
  std::size_t bad = 0;
  for (const double v : position.data) bad += std::isfinite(v) ? 0 : 1;
  for (const auto& c : position.contacts)
    for (const double v : {c.pressure_angle, c.curvature_a, c.curvature_b, c.sliding, c.roller_speed, c.entrainment})
      bad += std::isfinite(v) ? 0 : 1;
  INFO("non-finite values in a position reported ok");
  REQUIRE(bad == 0);
}

}  // namespace camopt::stress
