// the feasibility phase (opt/feasibility.hpp): an infeasible set is explained by the same
// conflicting keys whatever the solver, each key's best achievable value is checked by solving
// the set again with that limit just looser (feasible) and just tighter (infeasible), a
// feasible set gets no diagnosis; and the progress reports of every backend (opt/solve.hpp).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/opt/feasibility.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/opt/solve.hpp"
#include "opt/opt_test_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
namespace tol = camopt::test::tol;

namespace {

const std::string kRoot = CAMOPT_SOURCE_DIR;

// the normalised violation that still counts as feasible (solve.cpp, feasibility.cpp)
constexpr double kFeasible = 1e-6;
// a best achievable value is checked this far (relative) to either side of it
constexpr double kMargin = 1e-3;

// the passenger-car intake set on the roller finger follower, `line` added under [limits]
struct Fixture {
  DesignSpec design;
  opt::OptimizationSpec set;
};
Fixture rff_set(const std::string& line) {
  std::ifstream in(kRoot + "/constraints/passenger_car_intake.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  if (!line.empty()) {
    const std::size_t at = s.find("[limits]\n");
    REQUIRE(at != std::string::npos);
    s.insert(at + 9, line + "\n");
  }
  return {io::load_design(kRoot + "/designs/roller_finger_follower.toml"),
          io::parse_constraints(s, "passenger_car_intake.toml", kRoot + "/constraints")};
}

// the field of LimitSpec that a constraint-set key sets
std::optional<double>* limit_field(opt::LimitSpec& l, const std::string& key) {
  static const std::pair<const char*, std::optional<double> opt::LimitSpec::*> fields[] = {
      {"limits.acc_max_mm_per_deg2", &opt::LimitSpec::acc_max_mm_per_deg2},
      {"limits.acc_min_mm_per_deg2", &opt::LimitSpec::acc_min_mm_per_deg2},
      {"limits.jerk_max_mm_per_deg3", &opt::LimitSpec::jerk_max_mm_per_deg3},
      {"limits.max_lift_mm", &opt::LimitSpec::max_lift_mm},
      {"limits.min_max_lift_mm", &opt::LimitSpec::min_max_lift_mm},
      {"limits.min_duration_deg", &opt::LimitSpec::min_duration_deg},
      {"limits.max_duration_deg", &opt::LimitSpec::max_duration_deg},
      {"limits.min_radius_of_curvature_mm", &opt::LimitSpec::min_radius_of_curvature_mm},
      {"limits.grinding_wheel_radius_mm", &opt::LimitSpec::grinding_wheel_radius_mm},
      {"limits.max_pressure_angle_deg", &opt::LimitSpec::max_pressure_angle_deg},
      {"limits.max_roller_speed_rpm", &opt::LimitSpec::max_roller_speed_rpm},
      {"limits.max_sliding_speed_m_per_s", &opt::LimitSpec::max_sliding_speed_m_per_s},
      {"limits.max_hertz_stress_MPa", &opt::LimitSpec::max_hertz_stress_MPa},
      {"limits.min_separation_speed_rpm", &opt::LimitSpec::min_separation_speed_rpm},
      {"limits.min_contact_force_N", &opt::LimitSpec::min_contact_force_N},
      {"limits.min_spring_margin", &opt::LimitSpec::min_spring_margin},
      {"limits.max_cam_torque_Nm", &opt::LimitSpec::max_cam_torque_Nm},
      {"limits.min_film_thickness_um", &opt::LimitSpec::min_film_thickness_um},
      {"limits.min_lambda", &opt::LimitSpec::min_lambda},
  };
  for (const auto& [name, field] : fields)
    if (key == name) return &(l.*field);
  return nullptr;
}

// slsqp on the set, without the feasibility phase: true when it ends at a design meeting
// every row (a certificate), false when it reports the set infeasible
bool solves_feasibly(const Fixture& f, const opt::OptimizationSpec& set) {
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(f.design, set, nullptr);
  opt::CamProblem& p = *made_p;
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  so.feasibility_phase = false;
  const opt::SolveResult r = opt::optimize(p, so);
  INFO(r.status.str());
  if (r.evaluated && r.max_violation <= kFeasible) return true;
  CHECK(r.status.code == StatusCode::infeasible);
  return false;
}

// the set with one conflicting key moved to `value`; the other keys of the conflict only (and
// the variable box the diagnosis had) when relaxing that key alone leaves another conflict
opt::OptimizationSpec with_limit(const Fixture& f, const std::vector<opt::ConflictingConstraint>& conflict,
                                 const opt::ConflictingConstraint& c, double value, double coefficient_bound) {
  opt::OptimizationSpec s = f.set;
  s.coefficient_bound = coefficient_bound;
  if (!c.alone_suffices) {
    opt::LimitSpec kept;
    for (const auto& k : conflict) *limit_field(kept, k.key) = *limit_field(s.limits, k.key);
    kept.duration_check_height_mm = s.limits.duration_check_height_mm;
    s.limits = kept;
  }
  *limit_field(s.limits, c.key) = value;
  return s;
}

struct Events {
  std::vector<opt::SolverProgress> all;
  int count(opt::SolverProgress::Event e, const std::string& prefix = "") const {
    return static_cast<int>(std::count_if(all.begin(), all.end(), [&](const opt::SolverProgress& p) {
      return p.event == e && p.phase.rfind(prefix, 0) == 0;
    }));
  }
};

}  // namespace

TEST_CASE("feasibility: 8.9 mm of peak lift, the same conflicting keys on ipopt, slsqp and global",
          "[opt][feasibility]") {
  // on a 2 deg grid to keep the test short: ipopt's restoration phase is long on an infeasible
  // set (the 0.5 deg set, same keys: tests/cli/optimize_cli_test.cpp)
  Fixture f = rff_set("min_max_lift_mm = 8.9");
  f.set.grid_step_deg = 2.0;
  std::vector<std::vector<opt::ConflictingConstraint>> found;
  double coefficient_bound = 0.0;
  for (const opt::SolverKind solver : {opt::SolverKind::ipopt, opt::SolverKind::slsqp, opt::SolverKind::global}) {
    const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(f.design, f.set, nullptr);
    opt::CamProblem& p = *made_p;
    coefficient_bound = p.coefficients(std::vector<double>(static_cast<std::size_t>(p.variables()), 1.0))[0];
    opt::SolverOptions so;
    so.solver = solver;
    Events events;
    so.progress = [&](const opt::SolverProgress& e) { events.all.push_back(e); };
    const opt::SolveResult r = opt::optimize(p, so);
    INFO(opt::to_string(solver) << ": " << r.status.str());
    REQUIRE(r.status.code == StatusCode::infeasible);
    REQUIRE(r.infeasibility.diagnosed);
    CHECK(r.infeasibility.infeasible);
    CHECK(r.infeasibility.elastic_slack > kFeasible);
    REQUIRE_FALSE(r.infeasibility.conflicts.empty());
    // the message names the user's keys, never an internal row
    for (const auto& c : r.infeasibility.conflicts) CHECK(r.status.message.find(c.key) != std::string::npos);
    CHECK(r.status.message.find("closure") == std::string::npos);
    // one progress phase per feasibility solve, each begun and ended
    CHECK(events.count(opt::SolverProgress::Event::begin, "feasibility: ") == r.infeasibility.solves);
    CHECK(events.count(opt::SolverProgress::Event::end, "feasibility: ") == r.infeasibility.solves);
    found.push_back(r.infeasibility.conflicts);
  }
  const auto& first = found.front();
  for (std::size_t s = 1; s < found.size(); ++s) {
    REQUIRE(found[s].size() == first.size());
    for (std::size_t k = 0; k < first.size(); ++k) {
      CHECK(found[s][k].key == first[k].key);
      CHECK(found[s][k].unit == first[k].unit);
      CHECK(found[s][k].limit == first[k].limit);
      CHECK_REL(found[s][k].best_achievable, first[k].best_achievable, tol::kSameDiagnosisRel);
      CHECK(found[s][k].alone_suffices == first[k].alone_suffices);
    }
  }
  const auto lift = std::find_if(first.begin(), first.end(),
                                 [](const opt::ConflictingConstraint& c) { return c.key == "limits.min_max_lift_mm"; });
  REQUIRE(lift != first.end());
  CHECK(lift->unit == "mm");
  CHECK(lift->limit == 8.9);
  CHECK_FALSE(lift->limit_is_max);
  CHECK(lift->best_achievable < 8.9);

  // each best achievable value, by solving the set again (slsqp, every row) with that limit
  // just looser: feasible, and (the nearest values) just tighter: infeasible
  for (const auto& c : first) {
    INFO(c.key << " = " << c.limit << " " << c.unit << ", best achievable " << c.best_achievable
                << (c.alone_suffices ? "" : " (with the conflict's other keys only)")
                << (c.nearest ? "" : " (achievable, maybe not the nearest)"));
    REQUIRE(std::isfinite(c.best_achievable));
    opt::LimitSpec probe;
    REQUIRE(limit_field(probe, c.key) != nullptr);
    // relaxing a maximum raises it, relaxing a minimum lowers it
    const double looser_side = c.limit_is_max ? 1.0 : -1.0;
    CHECK(looser_side * (c.best_achievable - c.limit) > 0.0);
    const double looser = c.best_achievable + looser_side * kMargin * std::abs(c.best_achievable);
    const double tighter = c.best_achievable - looser_side * kMargin * std::abs(c.best_achievable);
    CHECK(solves_feasibly(f, with_limit(f, first, c, looser, coefficient_bound)));
    if (c.nearest) CHECK_FALSE(solves_feasibly(f, with_limit(f, first, c, tighter, coefficient_bound)));
  }
}

TEST_CASE("feasibility: a feasible set gets no diagnosis, the phase on it names nothing, and a solver cut short "
          "starts again from the phase's design",
          "[opt][feasibility]") {
  const Fixture f = rff_set("");
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(f.design, f.set, nullptr);
  opt::CamProblem& p = *made_p;
  opt::SolverOptions so;
  so.solver = opt::SolverKind::slsqp;
  const opt::SolveResult r = opt::optimize(p, so);
  REQUIRE(r.status.ok());
  CHECK_FALSE(r.infeasibility.diagnosed);
  CHECK(r.infeasibility.conflicts.empty());
  // the phase run directly finds a design that meets every row
  opt::InfeasibilityReport d;
  REQUIRE(opt::diagnose_infeasibility(p, so, d).ok());
  CHECK(d.diagnosed);
  CHECK_FALSE(d.infeasible);
  CHECK(d.conflicts.empty());
  CHECK(d.solves == 1);
  REQUIRE(d.feasible_u.size() == static_cast<std::size_t>(p.variables()));
  opt::Evaluation e;
  REQUIRE(p.evaluate(d.feasible_u, e, false).ok());
  CHECK(e.g.maxCoeff() <= kFeasible);
  CHECK(e.equality.cwiseAbs().maxCoeff() <= kFeasible);
  // slsqp cut at 2 evaluations ends short of feasibility: the phase finds the set feasible
  // and slsqp starts again from its design, which it keeps feasible
  so.max_iterations = 2;
  const opt::SolveResult cut = opt::optimize(p, so);
  INFO(cut.status.str() << " / " << cut.solver_message);
  CHECK(cut.infeasibility.diagnosed);
  CHECK_FALSE(cut.infeasibility.infeasible);
  CHECK(cut.infeasibility.conflicts.empty());
  CHECK(cut.status.code == StatusCode::no_convergence);  // its evaluation limit, not a conflict
  CHECK(cut.solver_message.find("from the feasibility phase's design") != std::string::npos);
  REQUIRE(cut.evaluated);
  CHECK(cut.max_violation <= kFeasible);
}

TEST_CASE("progress: every backend reports its phases, and a throwing callback never stops a solve",
          "[opt][progress]") {
  Fixture f = rff_set("");
  f.set.grid_step_deg = 2.0;
  const std::unique_ptr<opt::CamProblem> made_p = opt_test::make_problem(f.design, f.set, nullptr);
  opt::CamProblem& p = *made_p;
  auto run = [&](opt::SolverKind solver, Events& events) {
    opt::SolverOptions so;
    so.solver = solver;
    so.starts = 3;
    so.progress = [&](const opt::SolverProgress& e) { events.all.push_back(e); };
    opt::SolveResult r = opt::optimize(p, so);
    INFO(opt::to_string(solver) << ": " << r.status.str());
    REQUIRE(r.status.ok());
    // the clock never runs back, every phase begins before it ends
    for (std::size_t i = 1; i < events.all.size(); ++i) CHECK(events.all[i].elapsed_s >= events.all[i - 1].elapsed_s);
    CHECK(events.all.front().event == opt::SolverProgress::Event::begin);
    CHECK(events.all.back().event == opt::SolverProgress::Event::end);
    return r;
  };
  using Event = opt::SolverProgress::Event;
  {
    // nlopt: one phase, its evaluations reported at most every kProgressInterval, the last
    // report the final design's
    Events ev;
    const opt::SolveResult r = run(opt::SolverKind::slsqp, ev);
    CHECK(ev.count(Event::begin) == 1);
    CHECK(ev.count(Event::end, "slsqp") == 1);
    CHECK(ev.count(Event::iteration) >= 1);
    CHECK(ev.count(Event::iteration) <= r.evaluations);
    CHECK(ev.all.back().iteration == r.evaluations);
    CHECK(ev.all.back().objective == r.final.objective);
    CHECK(ev.all.back().violation == r.max_violation);
  }
  {
    // ipopt: a phase per working-set round, every iteration (0 included) of each
    Events ev;
    const opt::SolveResult r = run(opt::SolverKind::ipopt, ev);
    CHECK(r.rounds >= 2);
    CHECK(ev.count(Event::begin, "ipopt round ") == r.rounds);
    CHECK(ev.count(Event::end, "ipopt round ") == r.rounds);
    CHECK(ev.count(Event::iteration) == r.iterations + r.rounds);
  }
  {
    // global: a phase per start
    Events ev;
    run(opt::SolverKind::global, ev);
    CHECK(ev.count(Event::begin) == 3);
    for (int s = 1; s <= 3; ++s)
      CHECK(ev.count(Event::end, "global start " + std::to_string(s) + " of 3 (slsqp)") == 1);
  }
  // the reports never change a solve, and a callback that throws is called once: each on a
  // fresh problem (the contact model's warm starts carry over from one solve to the next)
  for (const opt::SolverKind solver : {opt::SolverKind::ipopt, opt::SolverKind::slsqp}) {
    opt::SolverOptions so;
    so.solver = solver;
    auto solve = [&] {
      const std::unique_ptr<opt::CamProblem> made_fresh = opt_test::make_problem(f.design, f.set, nullptr);
      opt::CamProblem& fresh = *made_fresh;
      return opt::optimize(fresh, so);
    };
    const opt::SolveResult quiet = solve();
    so.progress = [](const opt::SolverProgress&) {};
    const opt::SolveResult listened = solve();
    int calls = 0;
    so.progress = [&](const opt::SolverProgress&) {
      ++calls;
      throw std::runtime_error("progress callback");
    };
    const opt::SolveResult loud = solve();
    INFO(opt::to_string(solver));
    CHECK(calls == 1);
    REQUIRE(loud.status.ok());
    for (const opt::SolveResult* r : {&listened, &loud}) {
      CHECK(r->final.objective == quiet.final.objective);
      CHECK(r->iterations == quiet.iterations);
      CHECK(r->evaluations == quiet.evaluations);
    }
  }
}

TEST_CASE("stop: a stop request ends every backend at its next iteration and starts no later phase",
          "[opt][progress]") {
  Fixture f = rff_set("");
  f.set.grid_step_deg = 2.0;
  using Event = opt::SolverProgress::Event;
  for (const opt::SolverKind solver : {opt::SolverKind::ipopt, opt::SolverKind::slsqp, opt::SolverKind::global}) {
    auto solve = [&](std::function<bool()> stop, Events& events) {
      const std::unique_ptr<opt::CamProblem> made_fresh = opt_test::make_problem(f.design, f.set, nullptr);
      opt::SolverOptions so;
      so.solver = solver;
      so.starts = 3;
      so.progress = [&](const opt::SolverProgress& e) { events.all.push_back(e); };
      so.stop_requested = std::move(stop);
      return opt::optimize(*made_fresh, so);
    };
    INFO(opt::to_string(solver));
    Events never_ev, stop_ev;
    const opt::SolveResult full = solve({}, never_ev);
    int never_asks = 0;
    const opt::SolveResult never = solve([&] { return ++never_asks < 0; }, never_ev);
    // a stop never requested changes nothing; it is asked at every iteration (ipopt) or
    // evaluation (nlopt) at least
    CHECK(never.final.objective == full.final.objective);
    CHECK(never.iterations == full.iterations);
    CHECK(never.evaluations == full.evaluations);
    CHECK(never_asks >= (solver == opt::SolverKind::ipopt ? full.iterations : full.evaluations));
    // a stop requested at the 4th ask: asked no more, the run ends there
    int asks = 0;
    const opt::SolveResult stopped = solve([&] { return ++asks >= 4; }, stop_ev);
    CHECK(asks == 4);
    CHECK(!stopped.infeasibility.diagnosed);
    if (solver == opt::SolverKind::ipopt) {
      CHECK(full.iterations > 10);
      CHECK(stopped.iterations <= 3);
    } else {
      CHECK(stopped.evaluations <= 4);
      CHECK(stopped.evaluations < full.evaluations);
    }
    // every phase begun is ended, and none begins after the stopped one
    CHECK(stop_ev.count(Event::begin) == 1);
    CHECK(stop_ev.count(Event::end) == 1);
  }
}
