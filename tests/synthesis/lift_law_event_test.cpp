// lift events (lift_law_event.hpp): continuity at the ramp / flank / dwell joins, the jerk
// step the laws promise, derivatives against finite differences, closure on the base
// circle, ramps, asymmetric events, and input validation.
#include <array>
#include <string>
#include <vector>

#include "synthesis/lift_law_test_support.hpp"

using namespace camopt::lift_law_test;
// ---- lift events ------------------------------------------------------------------------

namespace {

// an asymmetric event with ramps and a dwell, wrapped around 0 cam deg
LiftEventSpec asymmetric_spec() {
  LiftEventSpec s;
  s.max_lift_mm = 9.5;
  s.peak_deg = 40.0;  // start = 40 - 3 - 72 = -35 -> 325: the event wraps through 0
  s.dwell_deg = 6.0;
  s.ramp_blend = 0.5;
  s.opening = {LawKind::polynomial_345, 72.0, 0.25, 22.0, {}, 3};
  s.closing = {LawKind::modified_sine, 64.0, 0.18, 18.0, {}, 3};
  return s;
}

std::vector<LiftEventSpec> event_variants() {
  std::vector<LiftEventSpec> v;
  for (LawKind law : kAllLaws) {
    LiftEventSpec s = asymmetric_spec();
    s.opening.law = law;
    s.closing.law = law == LawKind::cycloidal ? LawKind::polynomial_4567 : LawKind::cycloidal;
    if (law == LawKind::bspline) s.opening.acc_controls = kBsplineShape;
    if (law == LawKind::polydyne) {
      s.polydyne_engine_rpm = 6000.0;
      s.polydyne_natural_hz = 900.0;
    }
    v.push_back(s);
  }
  LiftEventSpec no_ramp_no_dwell = asymmetric_spec();
  no_ramp_no_dwell.opening.ramp_height_mm = no_ramp_no_dwell.opening.ramp_length_deg = 0.0;
  no_ramp_no_dwell.closing.ramp_height_mm = no_ramp_no_dwell.closing.ramp_length_deg = 0.0;
  no_ramp_no_dwell.dwell_deg = 0.0;
  v.push_back(no_ramp_no_dwell);
  return v;
}

std::string describe(const LiftEventSpec& s) {
  return std::string(to_string(s.opening.law)) + " / " + to_string(s.closing.law) + ", ramps " +
         std::to_string(s.opening.ramp_height_mm) + " / " + std::to_string(s.closing.ramp_height_mm) + " mm, dwell " +
         std::to_string(s.dwell_deg);
}

std::array<double, 4> event_peaks(const LiftEvent& ev) {
  std::array<double, 4> peak{};
  for (int i = 0; i < 36000; ++i)
    for (int k = 0; k <= 3; ++k) peak[static_cast<std::size_t>(k)] = std::max(peak[static_cast<std::size_t>(k)], std::abs(ev.evaluate(i * 0.01)[k]));
  return peak;
}

}  // namespace

TEST_CASE("event: lift, velocity and acceleration are continuous at every join", "[synthesis][lift_event]") {
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const auto peak = event_peaks(ev);
    const EventJoins j = ev.joins();
    const std::vector<std::pair<const char*, double>> joins = {
        {"base circle -> opening", j.opening_start},   {"velocity blend -> ramp", j.opening_blend_end},
        {"ramp -> opening flank", j.opening_ramp_end}, {"opening flank -> dwell", j.max_lift_start},
        {"dwell -> closing flank", j.max_lift_end},    {"closing flank -> ramp", j.closing_ramp_start},
        {"ramp -> velocity blend", j.closing_blend_start}, {"closing -> base circle", j.closing_end}};
    for (const auto& [name, at] : joins) {
      INFO("join " << name << " at " << at << " cam deg");
      const Motion left = ev.evaluate(at - kJoinEps), right = ev.evaluate(at + kJoinEps);
      for (int k = 0; k <= 2; ++k) {
        // a continuous d^k changes by at most 2 eps max|d^(k+1)| across the join
        const double allowed = 2.0 * kJoinEps * peak[static_cast<std::size_t>(k + 1)] * (1.0 + kJoinSlopeSlackRel) +
                               kJoinRoundOffRel * peak[static_cast<std::size_t>(k)];
        INFO("d^" << k);
        CHECK_ABS(right[k], left[k], allowed);
      }
      CHECK(std::isfinite(left.jerk));
      CHECK(std::isfinite(right.jerk));
    }
  }
}

TEST_CASE("event: the jerk step at a join is what the laws promise", "[synthesis][lift_event]") {
  LiftEventSpec s = asymmetric_spec();
  const LiftEvent ev = LiftEvent::compile(s);
  const EventJoins j = ev.joins();
  auto jump = [&](double at) { return ev.evaluate(at + kJoinEps).jerk - ev.evaluate(at - kJoinEps).jerk; };
  const double jerk_scale = event_peaks(ev)[3];
  // cycloidal velocity blend: jerk continuous at the base circle and at the blend end
  CHECK_ABS(jump(j.opening_start), 0.0, kJerkJoinRel * jerk_scale);
  CHECK_ABS(jump(j.opening_blend_end), 0.0, kJerkJoinRel * jerk_scale);
  CHECK_ABS(jump(j.closing_end), 0.0, kJerkJoinRel * jerk_scale);
  // ramp -> 3-4-5 flank: the jerk steps (c2 join), finite
  CHECK(std::abs(jump(j.opening_ramp_end)) > 1e-3 * jerk_scale);
  // a 4-5-6-7 flank without ramp meets the base circle and the dwell with zero jerk (c3)
  s.opening = {LawKind::polynomial_4567, 72.0, 0.0, 0.0, {}, 3};
  const LiftEvent c3 = LiftEvent::compile(s);
  const EventJoins j3 = c3.joins();
  CHECK_ABS(c3.evaluate(j3.opening_start + kJoinEps).jerk, 0.0, kJerkJoinRel * jerk_scale);
  CHECK_ABS(c3.evaluate(j3.max_lift_start - kJoinEps).jerk, 0.0, kJerkJoinRel * jerk_scale);
}

TEST_CASE("event derivatives agree with high-order finite differences", "[synthesis][lift_event]") {
  constexpr int kHalfWidth = 4;
  constexpr double kStep = 0.02;  // [cam deg]
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const auto peak = event_peaks(ev);
    const EventJoins j = ev.joins();
    std::vector<double> avoid = {j.opening_start,      j.opening_blend_end,   j.opening_ramp_end,
                                 j.max_lift_start,     j.max_lift_end,        j.closing_ramp_start,
                                 j.closing_blend_start, j.closing_end};
    for (const auto* flank : {&ev.opening(), &ev.closing()}) {
      for (double b : flank->law().breakpoints()) {
        const double off = flank->ramp_length_deg() + b * flank->law().duration_deg();
        avoid.push_back(flank == &ev.opening() ? j.opening_start + off : j.closing_end - off);
      }
    }
    for (int i = 0; i < 720; ++i) {
      const double theta = j.opening_start + ev.length_deg() * (i + 0.37) / 720.0;
      bool near = false;
      for (double a : avoid) near |= std::abs(theta - a) < (kHalfWidth + 1) * kStep;
      if (near) continue;
      const Motion m = ev.evaluate(theta);
      for (int k = 1; k <= 3; ++k) {
        const double fd = camopt::oracles::central_difference([&](double t) { return ev.evaluate(t)[k - 1]; }, theta,
                                                              1, kHalfWidth, kStep);
        check_close(m[k], fd, kLawFdRel, peak[static_cast<std::size_t>(k)], "d^" + std::to_string(k) + " at " + std::to_string(theta));
      }
    }
  }
}

TEST_CASE("event closes on the base circle and repeats every 360 cam deg", "[synthesis][lift_event]") {
  for (const auto& spec : event_variants()) {
    INFO(describe(spec));
    const LiftEvent ev = LiftEvent::compile(spec);
    const EventJoins j = ev.joins();
    CHECK_ABS(ev.evaluate(j.opening_start).lift, 0.0, kUlpAbs);
    CHECK_ABS(ev.evaluate(j.closing_end).lift, 0.0, kUlpAbs);
    // approaching the end of the closing ramp: lift and velocity go to zero
    const Motion end = ev.evaluate(j.closing_end - 1e-6);
    CHECK_ABS(end.lift, 0.0, kRampEndLiftAbs);
    CHECK_ABS(end.vel, 0.0, kRampEndVelocityAbs);
    // the base circle is exactly zero
    for (double a = j.closing_end + 0.5; a < j.opening_start + 360.0; a += 0.5) {
      const Motion m = ev.evaluate(a);
      CHECK(m.lift == 0.0);
      CHECK(m.vel == 0.0);
      CHECK(m.acc == 0.0);
    }
    // max lift at the peak angle, with zero velocity
    CHECK_REL(ev.evaluate(spec.peak_deg).lift, spec.max_lift_mm, kPeakLiftRel);
    CHECK_ABS(ev.evaluate(spec.peak_deg).vel, 0.0, kPeakVelocityAbs);
    // periodic, and the lift never exceeds the max lift nor goes negative
    for (int i = 0; i < 3600; ++i) {
      const double a = 0.1 * i;
      const Motion m = ev.evaluate(a), m2 = ev.evaluate(a + 360.0), m3 = ev.evaluate(a - 720.0);
      CHECK_ABS(m2.lift, m.lift, kPeriodShiftAbs);
      CHECK_ABS(m3.acc, m.acc, kPeriodShiftAbs);
      CHECK(m.lift >= -1e-15);
      CHECK(m.lift <= spec.max_lift_mm * (1 + 1e-14));
    }
  }
}

TEST_CASE("event ramps: constant velocity, the given height at the given length", "[synthesis][lift_event]") {
  const LiftEventSpec s = asymmetric_spec();
  const LiftEvent ev = LiftEvent::compile(s);
  const EventJoins j = ev.joins();
  // vr = Hr / (Lr (1 - b/2))
  const double vr_open = 0.25 / (22.0 * 0.75), vr_close = 0.18 / (18.0 * 0.75);
  check_close(ev.opening().ramp_velocity(), vr_open, kLawIdentityRel, vr_open, "opening ramp velocity");
  check_close(ev.closing().ramp_velocity(), vr_close, kLawIdentityRel, vr_close, "closing ramp velocity");
  check_close(ev.evaluate(j.opening_ramp_end).lift, 0.25, kLawIdentityRel, 1.0, "lift at the end of the opening ramp");
  check_close(ev.evaluate(j.closing_ramp_start).lift, 0.18, kLawIdentityRel, 1.0, "lift at the start of the closing ramp");
  for (double f : {0.55, 0.7, 0.9, 0.99}) {
    const Motion o = ev.evaluate(j.opening_start + f * 22.0);
    check_close(o.vel, vr_open, kLawIdentityRel, vr_open, "opening ramp velocity at " + std::to_string(f));
    CHECK(o.acc == 0.0);
    const Motion c = ev.evaluate(j.closing_end - f * 18.0);
    check_close(c.vel, -vr_close, kLawIdentityRel, vr_close, "closing ramp velocity at " + std::to_string(f));
  }
  // the main flank starts at the ramp velocity with zero acceleration
  const Motion start = ev.evaluate(j.opening_ramp_end);
  check_close(start.vel, vr_open, kLawIdentityRel, vr_open, "flank start velocity");
  CHECK_ABS(start.acc, 0.0, kUlpAbs);
}

TEST_CASE("asymmetric event: each side follows its own law and duration", "[synthesis][lift_event]") {
  LiftEventSpec s;
  s.max_lift_mm = 11.0;
  s.peak_deg = 200.0;
  s.dwell_deg = 4.0;
  s.opening = {LawKind::cycloidal, 75.0, 0.0, 0.0, {}, 3};
  s.closing = {LawKind::modified_trapezoid, 55.0, 0.0, 0.0, {}, 3};
  const LiftEvent ev = LiftEvent::compile(s);
  CHECK_REL(ev.length_deg(), 75.0 + 4.0 + 55.0, kUlpRel);
  CHECK_REL(ev.start_deg(), 200.0 - 2.0 - 75.0, kUlpRel);
  const ModifiedTrapezoid trap(1.0, 1.0);
  for (double phi : {1.0, 10.0, 30.0, 50.0, 70.0}) {
    // opening side: phi cam deg before the dwell
    const double xo = 1.0 - phi / 75.0;
    check_close(ev.evaluate(198.0 - phi).lift, 11.0 * ref_cycloidal(xo).lift, kLawIdentityRel, 11.0, "opening lift");
    check_close(ev.evaluate(198.0 - phi).acc, 11.0 / (75.0 * 75.0) * ref_cycloidal(xo).acc, kLawIdentityRel,
                11.0 / (75.0 * 75.0) * 2 * pi, "opening acceleration");
    if (phi < 55.0) {
      // closing side: phi cam deg after the dwell, mirrored (velocity and jerk change sign)
      const double xc = 1.0 - phi / 55.0;
      const Motion m = ev.evaluate(202.0 + phi);
      check_close(m.lift, 11.0 * trap.unit(xc).lift, kLawIdentityRel, 11.0, "closing lift");
      check_close(m.vel, -11.0 / 55.0 * trap.unit(xc).vel, kLawIdentityRel, 11.0 / 55.0 * 2.0, "closing velocity");
      check_close(m.acc, 11.0 / (55.0 * 55.0) * ref_modified_trapezoid_acc(xc), kLawIdentityRel, 11.0 / (55.0 * 55.0) * 5.0,
                  "closing acceleration");
    }
  }
  // dwell
  for (double a : {198.0, 199.0, 201.9}) CHECK(ev.evaluate(a).lift == 11.0);

  // durations at a lift level, against an independent bisection on the reference laws
  for (double level : {0.1, 1.0, 5.5, 10.9}) {
    auto solve = [&](const std::function<double(double)>& y) {
      double lo = 0.0, hi = 1.0;
      for (int i = 0; i < 200; ++i) (y(0.5 * (lo + hi)) < level / 11.0 ? lo : hi) = 0.5 * (lo + hi);
      return 0.5 * (lo + hi);
    };
    const double xo = solve([](double x) { return ref_cycloidal(x).lift; });
    const double xc = solve([](double x) { return norton_modified_trapezoid(x); });
    const double expected = 75.0 * (1 - xo) + 4.0 + 55.0 * (1 - xc);
    // norton's decimals are good to ~1e-7 in lift, i.e. ~1e-5 deg near the base
    CHECK_ABS(ev.duration_above(level), expected, kNortonDurationAbs);
  }
  CHECK_REL(ev.duration_above(0.0), 134.0, kUlpRel);
  CHECK(ev.duration_above(11.5) == 0.0);

  const LiftEventSummary sum = summarize(ev);
  CHECK(sum.max_lift_mm == 11.0);
  CHECK(sum.max_lift_at_deg == 200.0);
  CHECK_REL(sum.event_deg, 134.0, kUlpRel);
  // peak accelerations: cycloidal 2 pi h / beta_o^2 (opening), modified trapezoid C_a h / beta_c^2
  const double peak_acc = std::max(2 * pi * 11.0 / (75.0 * 75.0), 8 * pi / (2 + pi) * 11.0 / (55.0 * 55.0));
  CHECK_REL(sum.max_acc, peak_acc, kSummaryPeakAccRel);
  CHECK_REL(sum.min_acc, -peak_acc, kSummaryPeakAccRel);
}

// ---- validation ------------------------------------------------------------------------

TEST_CASE("event validation names the field, the value and the rule", "[synthesis][lift_event]") {
  using Catch::Matchers::Contains;
  struct Case {
    const char* what;
    std::function<void(LiftEventSpec&)> edit;
    std::vector<std::string> expect;  // substrings of the message
  };
  const std::vector<Case> cases = {
      {"negative lift", [](LiftEventSpec& s) { s.max_lift_mm = -1.0; }, {"max_lift_mm", "-1", "positive"}},
      {"nan lift", [](LiftEventSpec& s) { s.max_lift_mm = NAN; }, {"max_lift_mm", "finite"}},
      {"zero duration", [](LiftEventSpec& s) { s.opening.duration_deg = 0.0; }, {"opening.duration_deg", "positive"}},
      {"negative closing duration", [](LiftEventSpec& s) { s.closing.duration_deg = -5.0; },
       {"closing.duration_deg", "-5"}},
      {"ramp longer than flank", [](LiftEventSpec& s) { s.opening.ramp_length_deg = 80.0; },
       {"opening.ramp_length_deg", "80", "shorter than opening.duration_deg"}},
      {"ramp as high as the lift", [](LiftEventSpec& s) { s.closing.ramp_height_mm = 9.5; },
       {"closing.ramp_height_mm", "below max_lift_mm"}},
      {"ramp without length", [](LiftEventSpec& s) { s.opening.ramp_length_deg = 0.0; },
       {"opening.ramp_height_mm", "needs a length"}},
      {"ramp without height", [](LiftEventSpec& s) { s.closing.ramp_height_mm = 0.0; },
       {"closing.ramp_length_deg", "needs a height"}},
      {"event of 360 deg", [](LiftEventSpec& s) { s.opening.duration_deg = 200.0; s.closing.duration_deg = 154.0; },
       {"opening.duration_deg + dwell_deg + closing.duration_deg", "360"}},
      {"negative dwell", [](LiftEventSpec& s) { s.dwell_deg = -1.0; }, {"dwell_deg", ">= 0"}},
      {"peak outside the cycle", [](LiftEventSpec& s) { s.peak_deg = 360.0; }, {"peak_deg", "[0, 360)"}},
      {"zero blend", [](LiftEventSpec& s) { s.ramp_blend = 0.0; }, {"ramp_blend", "(0, 1]"}},
      {"polydyne without speed", [](LiftEventSpec& s) { s.opening.law = LawKind::polydyne; },
       {"polydyne_engine_rpm", "positive"}},
      {"bspline without controls", [](LiftEventSpec& s) { s.closing.law = LawKind::bspline; },
       {"closing.acc_controls", "at least 4"}},
      {"controls for another law", [](LiftEventSpec& s) { s.opening.acc_controls = {0, 1, -1, 0}; },
       {"opening.acc_controls", "bspline only"}},
      {"bspline shape without rise",
       [](LiftEventSpec& s) {
         s.opening.law = LawKind::bspline;
         s.opening.acc_controls = {0, -1, 1, 0};
       },
       {"opening.acc_controls", "net rise"}},
      {"ramp too fast for the flank",
       [](LiftEventSpec& s) {
         s.opening.law = LawKind::polynomial_4567;
         s.opening.ramp_height_mm = 3.0;
         s.opening.ramp_length_deg = 6.0;
       },
       {"opening", "monotonically", "ramp_height_mm"}},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    LiftEventSpec s = asymmetric_spec();
    c.edit(s);
    try {
      (void)LiftEvent::compile(s);
      FAIL_CHECK("no InputError");
    } catch (const InputError& e) {
      const std::string message = e.what();
      INFO("message: " << message);
      for (const auto& part : c.expect) CHECK_THAT(message, Contains(part));
    }
  }
  CHECK_THROWS_WITH(parse_law("parabolic", "--law"), Contains("parabolic") && Contains("cycloidal"));
  for (LawKind k : kAllLaws) CHECK(parse_law(to_string(k), "law") == k);
  CHECK_THROWS_AS(Cycloidal(0.0, 10.0), InputError);
  CHECK_THROWS_AS(Cycloidal(1.0, -10.0), InputError);
}
