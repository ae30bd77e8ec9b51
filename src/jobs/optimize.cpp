// the optimize job: constrained cam optimisation with Ipopt / NLopt (optimize.hpp).
#include "camopt/jobs/optimize.hpp"

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/kinematics/cam_profile.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/opt/solve.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "optimize_verify.hpp"
#include "profile_exports.hpp"
#include "target_input.hpp"

namespace camopt::jobs {

namespace {

// [mm] convex radius of a swing cam's untouched nose when the set has no radius limit
constexpr double kNoseConvexRadius = 1.0;

// contiguous runs of active rows of one kind as "a..b" cam-degree ranges
std::vector<std::string> active_ranges(const opt::CamProblem& p, const opt::Evaluation& e, opt::ConstraintKind kind) {
  std::vector<std::string> out;
  double first = 0, last = 0;
  bool open = false;
  auto close = [&] {
    if (!open) return;
    char buf[64];
    std::snprintf(buf, sizeof buf, first == last ? "%.1f" : "%.1f..%.1f", first, last);
    out.emplace_back(buf);
    open = false;
  };
  for (std::size_t r = 0; r < p.rows().size(); ++r) {
    if (p.rows()[r].kind != kind) continue;
    const bool active = e.g(static_cast<Eigen::Index>(r)) > -1e-5;
    if (active && !open) {
      first = p.rows()[r].cam_deg;
      open = true;
    }
    if (active) last = p.rows()[r].cam_deg;
    if (!active) close();
  }
  close();
  return out;
}

nlohmann::json constraint_report(const opt::CamProblem& p, const opt::Evaluation& e) {
  nlohmann::json out = nlohmann::json::object();
  for (std::size_t r = 0; r < p.rows().size(); ++r) {
    const opt::ConstraintKind kind = p.rows()[r].kind;
    if (kind == opt::ConstraintKind::peak_bound) continue;
    const std::string name = opt::to_string(kind);
    const double g = e.g(static_cast<Eigen::Index>(r));
    if (out.contains(name) && out[name]["normalised"].get<double>() >= g) continue;
    const double value = e.physical(static_cast<Eigen::Index>(r));
    const double limit = p.limit_of(kind);
    const bool upper = p.is_upper_limit(kind);
    nlohmann::json c;
    c["unit"] = p.unit_of(kind);
    c["limit"] = limit;
    c["limit_is"] = upper ? "max" : "min";
    c["worst"] = value;
    c["worst_at_cam_deg"] = p.rows()[r].cam_deg;
    if (const std::string item = p.item_name(p.rows()[r]); !item.empty()) c["worst_at"] = item;
    if (p.is_swing()) c["worst_at_control"] = p.swing()->positions()[static_cast<std::size_t>(p.rows()[r].position)];
    c["normalised"] = g;  // (value - limit) / limit, <= 0 feasible
    c["satisfied"] = g <= 1e-6;
    out[name] = c;
  }
  for (auto& [name, c] : out.items()) {
    for (std::size_t r = 0; r < p.rows().size(); ++r)
      if (name == opt::to_string(p.rows()[r].kind)) {
        c["active_at_cam_deg"] = active_ranges(p, e, p.rows()[r].kind);
        break;
      }
    // margin in the quantity's unit: how far the worst value is inside its limit
    const double worst = c["worst"].get<double>(), limit = c["limit"].get<double>();
    c["margin"] = c["limit_is"] == "max" ? limit - worst : worst - limit;
  }
  return out;
}

// swing cam: the valve lift at every control position on the optimiser's grid (lift.csv),
// the pitch curve (swing_pitch.csv) and the working curve in the report; peak: the largest
// lift per position, lift: the lift at every grid point [mm]
void stage_swing_lift(OptimizeResult& out, opt::SwingCamLift& model, const std::vector<double>& c,
                      nlohmann::json& report, std::vector<double>& peak, std::vector<double>& lift) {
  std::vector<double> control, cam_deg, l1, l2, l3;
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows(4, model.variables());
  peak.assign(model.positions().size(), 0.0);
  lift.clear();
  for (std::size_t i = 0; i < model.points().size(); ++i) {
    const opt::SwingPoint& sp = model.points()[i];
    double m[4];
    Status st = model.evaluate(static_cast<int>(i), c, m, rows);
    if (!st.ok()) throw NumericalError(st);
    control.push_back(model.positions()[static_cast<std::size_t>(sp.position)]);
    cam_deg.push_back(std::fmod(sp.cam_deg, 360.0));
    lift.push_back(m[0]);
    l1.push_back(m[1]);
    l2.push_back(m[2]);
    l3.push_back(m[3]);
    peak[static_cast<std::size_t>(sp.position)] = std::max(peak[static_cast<std::size_t>(sp.position)], m[0]);
  }
  out.tables.emplace_back("lift.csv", io::Columns{{"control", "cam_deg", "lift_mm", "vel_mm_per_deg", "acc_mm_per_deg2",
                                                   "jerk_mm_per_deg3"},
                                                  {control, cam_deg, lift, l1, l2, l3},
                                                  {}});
  std::vector<double> swing_deg, pitch_lift;
  for (int i = 0; i <= 400; ++i) {
    const double s = model.start_rad() + (model.end_rad() - model.start_rad()) * i / 400.0;
    double h[5];
    model.pitch_lift(c, s, h);
    swing_deg.push_back(s * 180.0 / pi);
    pitch_lift.push_back(h[0]);
  }
  out.tables.emplace_back("swing_pitch.csv", io::Columns{{"swing_deg", "pitch_lift_mm"}, {swing_deg, pitch_lift}, {}});
  nlohmann::json per_position = nlohmann::json::array();
  for (std::size_t k = 0; k < peak.size(); ++k)
    per_position.push_back({{"control", model.positions()[k]}, {"max_lift_mm", peak[k]}});
  report["swing"] = {{"connection", model.connection()},
                     {"working_curve_deg", {model.start_rad() * 180.0 / pi, model.end_rad() * 180.0 / pi}},
                     {"dwell_pitch_radius_mm", model.dwell_radius_mm()},
                     {"positions", per_position}};
}

// the swing cam's surface as a polar table, with what synthesize reports of a profile
synthesis::SynthesisResult swing_profile(const OptimizeOptions& o, const DesignSpec& spec,
                                         const opt::OptimizationSpec& set, opt::SwingCamLift& model,
                                         const std::vector<double>& c) {
  synthesis::SynthesisResult res;
  for (const auto& p : spec.profiles)
    if (p.name == model.profile_name()) res.profile = p;
  res.profile.source_file.clear();
  res.profile.form = ProfileForm::polar;
  // the free nose keeps the set's convex radius limit (else kNoseConvexRadius), so the
  // surface never folds where no contact constrains it
  const double nose_radius = set.limits.min_radius_of_curvature_mm.value_or(kNoseConvexRadius);
  if (Status st = model.profile_table(c, std::max(o.points, 3600), nose_radius, res.profile.angle_deg,
                                      res.profile.radius_mm);
      !st.ok())
    throw NumericalError(st);
  res.connection = model.connection();
  for (const auto& k : spec.connections)
    if (k.name == res.connection) res.follower_node = k.surface_a.shape == SurfaceShape::profile ? k.surface_b.node : k.surface_a.node;
  const kin::CamProfile cam = kin::CamProfile::build(res.profile);
  res.base_radius_mm = 1e300;
  for (std::size_t i = 0; i < res.profile.angle_deg.size(); ++i) {
    const double a = res.profile.angle_deg[i] * pi / 180.0, r = res.profile.radius_mm[i];
    const kin::CurvePoint<double> pt = cam.point(a, true);
    const double speed = std::hypot(pt.dx, pt.dy);
    const double cross = pt.dx * pt.ddy - pt.dy * pt.ddx;  // > 0 convex (counter-clockwise curve)
    res.angle_deg.push_back(res.profile.angle_deg[i]);
    res.radius_mm.push_back(r);
    res.x_mm.push_back(r * std::cos(a));
    res.y_mm.push_back(r * std::sin(a));
    res.radius_of_curvature_mm.push_back(cross != 0.0 ? speed * speed * speed / cross : 1e12);
    res.base_radius_mm = std::min(res.base_radius_mm, r);
    res.max_radius_mm = std::max(res.max_radius_mm, r);
  }
  return res;
}

// --verify of a swing cam: the kinematic solver on the made design at every position, on the
// optimiser's grid: its peak lift and its lift at every working point against the model's
void verify_swing_kinematics(const kin::Mechanism& mech, const opt::CamProblem& problem, const opt::SwingCamLift& model,
                             const std::vector<double>& peak, const std::vector<double>& lift,
                             const opt::OptimizationSpec& set, nlohmann::json& report, Verdict& verdict) {
  const int out_var = mech.nodes[static_cast<std::size_t>(mech.output_node)].first_variable;
  const double rest = mech.nodes[static_cast<std::size_t>(mech.output_node)].rest;  // translational valve [mm]
  nlohmann::json v = nlohmann::json::array();
  double worst = 0.0, worst_curve = 0.0;
  for (std::size_t k = 0; k < peak.size(); ++k) {
    kin::SweepSpec sw;
    sw.start = 0;
    sw.stop = 360;
    sw.step = problem.spec().grid_step_deg;
    sw.control_positions = {model.controls(static_cast<int>(k))};
    sw.request = {3, true};
    const kin::SweepResult sr = kin::sweep(mech, sw);
    if (!sr.positions[0].status.ok()) throw NumericalError(sr.positions[0].status);
    const kin::PositionSummary sum = kin::summarize(mech, sr, 0);
    // the optimiser's peak is the largest of its grid points: compare with the same grid's
    double grid_peak = -1e300;
    for (std::size_t i = 0; i < sr.driver.size(); ++i)
      grid_peak = std::max(grid_peak, sr.positions[0].value(i, out_var, 0) - rest);
    worst = std::max(worst, std::abs(grid_peak - peak[k]));
    // the model's points of this position sit on the sweep's grid (cam angles unwrapped past 360)
    for (std::size_t i = 0; i < model.points().size(); ++i) {
      if (model.points()[i].position != static_cast<int>(k)) continue;
      const double deg = std::fmod(model.points()[i].cam_deg, 360.0);
      const auto at = static_cast<std::size_t>(std::lround(deg / sw.step));
      if (at >= sr.driver.size() || std::abs(sr.driver[at] - deg) > 1e-9) continue;
      worst_curve = std::max(worst_curve, std::abs(sr.positions[0].value(at, out_var, 0) - rest - lift[i]));
    }
    v.push_back({{"control", model.positions()[k]},
                 {"max_lift_mm", sum.max_lift},
                 {"max_pressure_angle_deg", sum.max_pressure_angle_deg},
                 {"duration_at_1mm_deg", sum.duration_at(1.0)}});
  }
  report["verify"]["kinematics"] = {
      {"positions", v}, {"max_lift_difference_mm", worst}, {"max_lift_curve_difference_mm", worst_curve}};
  verdict.note("optimize --verify: the kinematic solver's peak lifts match the optimiser's to " + format_value(worst, 3) +
       " mm, its lift at every working point to " + format_value(worst_curve, 3) + " mm, at " +
       std::to_string(peak.size()) + " control positions");
  verdict.bound("kinematic", "lift of the made cam against the optimised lift", "mm", worst_curve,
                set.verify.max_lift_error_mm, true, "every working point");
}

// swing cam: the lift tables, the new swing profile with its exports, and (--verify) the
// kinematic solver and the dynamics on the new design
void stage_swing_outputs(OptimizeResult& out, const OptimizeOptions& o, const DesignSpec& spec,
                         const opt::OptimizationSpec& set, opt::CamProblem& problem, const opt::SolveResult& result,
                         nlohmann::json& report, Verdict& verdict) {
  opt::SwingCamLift& model = *problem.swing();
  const std::vector<double> c = problem.coefficients(result.u);
  std::vector<double> peak, lift;
  stage_swing_lift(out, model, c, report, peak, lift);
  // the grinding table (a roller master around the whole swing cam, its unused far side
  // included) is reported, not fatal
  const synthesis::SynthesisResult res = swing_profile(o, spec, set, model, c);
  out.exports = profile_exports(o.out_dir, o.design_file, o.overrides, spec, res, std::nullopt, 0.25, report, true);
  if (!o.verify) return;
  const DesignSpec made = synthesis::with_profile(spec, res.profile);
  verify_swing_kinematics(kin::compile(made), problem, model, peak, lift, set, report, verdict);
  verify_swing_dynamics(made, problem, report, verdict);
  record_verdict(verdict, report);
}

// report.json's run: the inputs, the solver's outcome, the objective, the constraints with
// their worst values and margins, the ramps fixed by [event], and the loads' source
nlohmann::json run_report(const OptimizeOptions& o, const DesignSpec& spec, const opt::OptimizationSpec& set,
                          const opt::CamProblem& problem, const opt::SolveResult& result) {
  nlohmann::json report;
  report["design"] = spec.name;
  report["design_file"] = o.design_file;
  report["constraints_file"] = o.constraints_file;
  report["constraint_set"] = set.name;
  report["solver"] = o.solver;
  report["status"] = result.status.ok() ? "converged" : to_string(result.status.code);
  report["message"] = result.status.ok() ? result.solver_message : result.status.str();
  report["solver_message"] = result.solver_message;
  report["iterations"] = result.iterations;
  report["evaluations"] = result.evaluations;
  report["time_s"] = result.seconds;
  report["variables"] = problem.variables();
  report["inequality_constraints"] = problem.rows().size();
  report["max_violation_normalised"] = result.max_violation;
  report["objective"] = {{"value", result.final.objective},
                         {"target_weight", set.objective.target_weight},
                         {"area_weight", set.objective.area_weight},
                         {"peak_weight", set.objective.peak_weight},
                         {"peak", opt::to_string(set.objective.peak)}};
  if (result.final.g.size() > 0) report["constraints"] = constraint_report(problem, result.final);
  // the ramps are fixed by [event]: their velocities at rpm, held before the solve
  if (!problem.is_swing()) {
    const double to_m_per_s = problem.cam_speed_rad_per_s() * 180.0 / pi * 1e-3;  // [mm/deg] -> [m/s]
    auto ramp = [&](const char* name, double velocity, const std::optional<double>& limit) {
      if (!limit) return;
      report["constraints"][name] = {{"unit", "m/s"}, {"limit", *limit}, {"limit_is", "max"},
                                     {"worst", velocity * to_m_per_s}, {"margin", *limit - velocity * to_m_per_s},
                                     {"normalised", (velocity * to_m_per_s - *limit) / *limit},
                                     {"satisfied", velocity * to_m_per_s <= *limit}, {"fixed_by", "event"}};
    };
    ramp("seating_velocity_max", problem.lift_model().closing_ramp().velocity(), set.limits.max_seating_velocity_m_per_s);
    ramp("opening_ramp_velocity_max", problem.lift_model().opening_ramp().velocity(),
         set.limits.max_opening_ramp_velocity_m_per_s);
  }
  if (const std::string source = problem.load_source(); !source.empty()) {
    report["loads"]["source"] = source;
    for (const opt::LoadOverride& ov : problem.load_overrides())
      report["loads"]["overrides"][ov.key] = {{"constraint_set", ov.set_value}, {"design", ov.design_value}};
  }
  return report;
}

// an infeasible set: which limits conflict, from the feasibility phase (opt/feasibility.hpp):
// an irreducible set of the user's keys, each with the nearest value at which the other
// limits hold; in the report and as a table on stderr
void report_conflicts(const opt::SolveResult& result, nlohmann::json& report, Observer& observer) {
  nlohmann::json conflicts = nlohmann::json::array();
  std::string table;
  for (const opt::ConflictingConstraint& c : result.infeasibility.conflicts) {
    const bool known = std::isfinite(c.best_achievable);
    conflicts.push_back({{"key", c.key},
                         {"unit", c.unit},
                         {"limit", c.limit},
                         {"limit_is", c.limit_is_max ? "max" : "min"},
                         {"best_achievable", known ? nlohmann::json(c.best_achievable) : nlohmann::json()},
                         {"alone_suffices", c.alone_suffices},
                         {"nearest", c.nearest}});
    char row[240];
    std::snprintf(row, sizeof row, "\n  %-36s %12s %-9s %15s%s%s", c.key.c_str(), format_value(c.limit, 6).c_str(),
                  c.unit.c_str(), known ? format_value(c.best_achievable, 6).c_str() : "-",
                  c.alone_suffices ? "" : "  (this conflict only; another remains)",
                  c.nearest ? "" : "  (achievable, a nearer value may exist)");
    table += row;
  }
  report["conflicting_constraints"] = conflicts;
  report["feasibility_phase"] = {{"ran", result.infeasibility.diagnosed},
                                 {"elastic_slack_normalised", result.infeasibility.elastic_slack},
                                 {"solves", result.infeasibility.solves},
                                 {"time_s", result.infeasibility.seconds}};
  if (!table.empty())
    observer.note("optimize: these limits conflict; a best achievable value is the nearest setting of that limit alone at "
         "which every other limit can be met:\n  " +
         std::string("key                                         limit unit      best achievable") + table);
}

// the optimised lift over the cycle every 0.25 deg (lift.csv), and its quintic periodic
// interpolation (the synthesis target)
PeriodicSpline stage_rotational_lift(OptimizeResult& out, const opt::CamProblem& problem,
                                     const opt::SolveResult& result) {
  const auto coef = problem.coefficients(result.u);
  const auto& lift = problem.lift_model();
  std::vector<double> cam_deg, l0, l1, l2, l3, knots, values;
  for (int i = 0; i < 1440; ++i) {
    const double deg = 0.25 * i;
    const auto m = lift.evaluate(coef, deg);
    cam_deg.push_back(deg);
    l0.push_back(m.lift);
    l1.push_back(m.vel);
    l2.push_back(m.acc);
    l3.push_back(m.jerk);
  }
  for (int i = 0; i < 1440; ++i) {
    knots.push_back(2 * pi * i / 1440);
    values.push_back(l0[static_cast<std::size_t>(i)]);
  }
  out.tables.emplace_back("lift.csv", io::Columns{{"cam_deg", "lift_mm", "vel_mm_per_deg", "acc_mm_per_deg2",
                                                   "jerk_mm_per_deg3"},
                                                  {cam_deg, l0, l1, l2, l3},
                                                  {}});
  return PeriodicSpline::interpolate(knots, values, 2 * pi);
}

// rotational cam: the lift, the cam synthesized for it as synthesize delivers it, and
// (--verify) the made design checked
void stage_rotational_outputs(OptimizeResult& out, const OptimizeOptions& o, const DesignSpec& spec,
                              const opt::OptimizationSpec& set, const opt::CamProblem& problem,
                              const opt::SolveResult& result, nlohmann::json& report, Verdict& verdict) {
  const PeriodicSpline lift_spline = stage_rotational_lift(out, problem, result);
  synthesis::SynthesisOptions so_syn;
  so_syn.points = o.points;
  so_syn.samples = o.points;
  so_syn.controls = problem.contact().controls();
  so_syn.wheel_radius_mm = set.limits.grinding_wheel_radius_mm.value_or(0.0);
  synthesis::SynthesisResult res;
  Status st = synthesis::synthesize(spec, lift_spline, so_syn, res);
  if (!st.ok()) {
    st.message = "synthesizing the optimised lift: " + st.message;
    throw NumericalError(st);
  }
  out.exports = profile_exports(o.out_dir, o.design_file, o.overrides, spec, res, std::nullopt, 0.25, report);
  if (!o.verify) return;
  verify_rotational(synthesis::with_profile(spec, res.profile), res, lift_spline, so_syn.controls, problem, report,
                    verdict);
  record_verdict(verdict, report);
}

// the solver's options; its progress to the caller's printer, the observer's runs and
// report.json's "convergence"; the observer's cancel check at every report, remembered
opt::SolverOptions solver_options(const OptimizeOptions& o, Observer& observer, nlohmann::json& convergence,
                                  bool& cancelled) {
  opt::SolverOptions so;
  so.solver = opt::parse_solver(o.solver);
  so.max_iterations = o.max_iterations;
  so.starts = o.starts;
  so.progress = [&observer, &convergence, printer = o.progress](const opt::SolverProgress& p) {
    if (printer) printer(p);
    if (p.event == opt::SolverProgress::Event::begin) {
      observer.begin(p.phase, 0);
      return;
    }
    if (p.event == opt::SolverProgress::Event::end) observer.end();
    convergence.push_back({{"phase", p.phase}, {"iteration", p.iteration}, {"objective", p.objective},
                           {"violation_normalised", p.violation}, {"elapsed_s", p.elapsed_s}});
  };
  so.stop_requested = [&observer, &cancelled] { return cancelled || (cancelled = observer.cancel_requested()); };
  return so;
}

// the problem of the set: the design, the set's limits and its target lift, if any
std::unique_ptr<opt::CamProblem> make_problem(const DesignSpec& spec, const opt::OptimizationSpec& set,
                                              Observer& observer) {
  std::unique_ptr<ValveTarget> target;
  if (!set.objective.target_file.empty()) {
    const io::CsvTable table = io::read_csv(set.objective.target_file);
    target = std::make_unique<ValveTarget>(read_valve_target(table, set.objective.target_file, spec, {}, observer));
  }
  std::unique_ptr<opt::CamProblem> problem;
  if (Status st = opt::CamProblem::create(spec, set, target ? &target->fit.lift : nullptr, problem); !st.ok())
    throw NumericalError(st);
  return problem;
}

}  // namespace

void validate(const OptimizeOptions& o) {
  (void)opt::parse_solver(o.solver);
  if (o.cam != "rotational" && o.cam != "swing")
    throw InputError("--cam: value '" + o.cam + "' is not one of rotational, swing");
  if (o.points < 36 || o.points > 100000)
    throw InputError("--points: value " + std::to_string(o.points) + " must be in [36, 100000]");
  if (o.max_iterations < 1 || o.max_iterations > 1000000)
    throw InputError("--max-iterations: value " + std::to_string(o.max_iterations) + " must be in [1, 1000000]");
  if (o.starts < 1 || o.starts > 1000)
    throw InputError("--starts: value " + std::to_string(o.starts) + " must be in [1, 1000]");
}

OptimizeResult run_optimize(const DesignSpec& spec, opt::OptimizationSpec set, const OptimizeOptions& o,
                            Observer& observer) {
  // the solver, the problem and its solution
  set.cam = o.cam;
  nlohmann::json convergence = nlohmann::json::array();
  bool cancelled = false;
  const opt::SolverOptions so = solver_options(o, observer, convergence, cancelled);
  const std::unique_ptr<opt::CamProblem> made_problem = make_problem(spec, set, observer);
  opt::CamProblem& problem = *made_problem;
  observer.note("optimize: " + std::to_string(problem.variables()) + " variables, " +
                std::to_string(problem.rows().size()) + " inequality constraints on a " +
                std::to_string(set.grid_step_deg) + " deg grid, solver " + o.solver);
  const opt::SolveResult solved = opt::optimize(problem, so);
  if (cancelled) throw Cancelled();
  OptimizeResult out;
  out.status = solved.status;
  out.report = run_report(o, spec, set, problem, solved);
  out.report["convergence"] = std::move(convergence);
  record_overrides(out.report, o.overrides);
  // an infeasible set: the report with the conflicting limits
  if (solved.status.code == StatusCode::infeasible || solved.u.empty()) {
    report_conflicts(solved, out.report, observer);
    return out;
  }
  // the lift, the profile and its exports, and verify
  Verdict verdict(set.verify.relative_tolerance, observer);
  if (problem.is_swing())
    stage_swing_outputs(out, o, spec, set, problem, solved, out.report, verdict);
  else
    stage_rotational_outputs(out, o, spec, set, problem, solved, out.report, verdict);
  out.verified = !o.verify || verdict.passed();
  if (!out.verified) out.verification_failures = verdict.failure_table();
  out.summary = "optimize: " + std::string(solved.status.ok() ? "converged" : solved.status.str()) + " in " +
                std::to_string(solved.iterations) + " iterations, " + std::to_string(solved.seconds) +
                " s; objective " + std::to_string(solved.final.objective);
  return out;
}
}  // namespace camopt::jobs
