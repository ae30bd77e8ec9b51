// the synthesize job: envelope-theory cam synthesis from a target valve lift (synthesize.hpp).
#include "camopt/jobs/synthesize.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/io/design_rewrite.hpp"
#include "camopt/io/dxf.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"
#include "camopt/synthesis/target_lift.hpp"
#include "profile_exports.hpp"
#include "target_input.hpp"

namespace camopt::jobs {

namespace {

// a numerical failure names the target table's largest slope step above this fraction of
// its steepest slope (the bundled lifts computed with lash: 0.32 to 0.34; smooth tables
// ~1e-3; the real ICESym table's bump at 125 cam deg: 0.82, which synthesizes)
constexpr double kSlopeStepHint = 0.1;

// a target motion of another node than the valve (e.g. the swing cam's angle): exact
// periodic interpolation of one full cycle, in the node's internal unit (rad or mm)
PeriodicSpline fit_node_target(const io::CsvTable& table, const DesignSpec& spec, const std::string& node,
                               io::AngleBasis& basis) {
  const NodeSpec* n = nullptr;
  for (const auto& candidate : spec.nodes)
    if (candidate.name == node) n = &candidate;
  if (!n) throw InputError("--target-node: no node '" + node + "' in design '" + spec.name + "'");
  const bool angle = n->kind == NodeKind::rotational;
  const io::AngleTable at = io::read_angle_table(
      table, angle ? std::vector<std::string>{node + "_angle_deg", node + "_deg"}
                   : std::vector<std::string>{node + "_disp_mm", node + "_mm"});
  basis = at.basis;
  const double per_cam = at.basis == io::AngleBasis::crank ? spec.driver.crank_per_cam : 1.0;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < at.angle_deg.size(); ++i) {
    const double cam = at.angle_deg[i] / per_cam;
    if (!x.empty() && cam * pi / 180 - x.front() >= 2 * pi - 1e-9) break;  // a repeated closing row
    x.push_back(cam * pi / 180);
    y.push_back(angle ? at.value[i] * pi / 180 : at.value[i]);
  }
  io::require_full_cycle(at, 360.0 * per_cam);
  if (x.size() < 6) throw InputError(table.file + ": a target motion needs at least 6 rows over one cycle");
  return PeriodicSpline::interpolate(x, y, 2 * pi);
}

// the control position of largest lift of the design as it stands (the default control)
double max_lift_control(const kin::Mechanism& mech) {
  const auto& c0 = mech.controls[0];
  double best = c0.default_value, best_lift = -1e300;
  for (int i = 0; i <= 8; ++i) {
    const double v = c0.min + (c0.max - c0.min) * i / 8.0;
    std::vector<double> pos = mech.default_controls();
    pos[0] = v;
    kin::SweepSpec s;
    s.start = 0;
    s.stop = 360;
    s.step = 2.0;
    s.request = {0, false};
    s.control_positions = {pos};
    const auto r = kin::sweep(mech, s);
    if (!r.positions[0].status.ok()) continue;
    const double lift = kin::summarize(mech, r, 0).max_lift;
    if (lift > best_lift) best_lift = lift, best = v;
  }
  return best;
}

// the target motion: the valve lift (cam or crank degrees, explicit in the header), or the
// motion of another node with --target-node
struct Target {
  bool valve = true;           // the valve's lift (else --target-node's motion)
  io::AngleBasis basis = io::AngleBasis::cam;
  synthesis::TargetLift lift;  // the valve's lift fitted
  PeriodicSpline node_motion;  // --target-node's motion
  std::size_t points = 0;      // rows of the table
  const PeriodicSpline& motion() const { return valve ? lift.lift : node_motion; }
};

Target read_target(const SynthesizeOptions& o, const io::CsvTable& table, const DesignSpec& spec,
                   const kin::Mechanism& mech, Observer& observer) {
  Target t;
  t.valve = o.target_node.empty() || o.target_node == spec.output_node;
  if (t.valve && mech.nodes[mech.output_node].kind != NodeKind::translational)
    throw InputError("design.output_node '" + spec.output_node + "' is " +
                     to_string(mech.nodes[mech.output_node].kind) +
                     ", not a translating valve: give its motion with --target-node " + spec.output_node);
  t.points = table.rows();
  if (t.valve) {
    synthesis::TargetLiftOptions fit;
    fit.smooth = o.smooth;
    fit.smoothing_knot_spacing_deg = o.knot_spacing_deg;
    fit.closure_tolerance_mm = o.closure_tolerance_mm;
    ValveTarget vt = read_valve_target(table, o.target_file, spec, fit, observer);
    t.basis = vt.basis;
    t.lift = std::move(vt.fit);
  } else {
    t.node_motion = fit_node_target(table, spec, o.target_node, t.basis);
  }
  return t;
}

// the synthesis options: the cam, the resolution, the radius limits and the control
// position (--control, else the position of largest lift)
synthesis::SynthesisOptions synthesis_options(const SynthesizeOptions& o, const kin::Mechanism& mech, bool valve,
                                              Observer& observer) {
  synthesis::SynthesisOptions opt;
  opt.cam = o.cam;
  opt.points = o.points;
  opt.samples = o.points;
  opt.wheel_radius_mm = o.wheel_radius_mm;
  opt.min_radius_mm = o.min_radius_mm;
  if (!valve) opt.target_node = o.target_node;
  for (const auto& c : mech.controls) opt.controls.push_back(c.default_value);
  if (!mech.controls.empty()) {
    const auto& c0 = mech.controls[0];
    if (o.control) {
      if (*o.control < c0.min || *o.control > c0.max)
        throw InputError("--control: value " + std::to_string(*o.control) + " is outside control '" + c0.name +
                         "' range [" + std::to_string(c0.min) + ", " + std::to_string(c0.max) + "]");
      opt.controls[0] = *o.control;
    } else {
      opt.controls[0] = max_lift_control(mech);
      observer.note("synthesize: control '" + c0.name + "' at " + std::to_string(opt.controls[0]) +
           " (the position of largest lift of the current design)");
    }
  } else if (o.control) {
    throw InputError("--control: design '" + o.design_file + "' has no [[control]]");
  }
  return opt;
}

// a failure where the target table's slope steps (a lift computed with lash) names the step
Status with_slope_step(const Target& target, Status st) {
  if (target.valve && target.lift.slope_step_ratio > kSlopeStepHint)
    st.message += "; the target's slope steps by " + format_value(target.lift.slope_step_mm_per_deg, 3) +
                  " mm/deg at cam " + format_value(target.lift.slope_step_at_deg, 6) + " deg (" +
                  format_value(target.lift.slope_step_ratio, 3) +
                  " of its steepest slope): a lift computed with lash steps where the lash is taken up, which no "
                  "cam gives; give the lift without lash (lash_mm = 0), or smooth the table (--smooth)";
  return st;
}

// the round trip's unit: mm for the valve, deg for a rotational --target-node
struct RoundTripUnit {
  std::string name = "mm";
  double scale = 1.0;  // internal unit -> name
};

RoundTripUnit round_trip_unit(const SynthesizeOptions& o, const DesignSpec& spec, bool valve) {
  bool angle_target = false;
  for (const auto& n : spec.nodes)
    if (!valve && n.name == o.target_node) angle_target = n.kind == NodeKind::rotational;
  return {angle_target ? "deg" : "mm", angle_target ? deg_per_rad : 1.0};
}

// the forward kinematics of the synthesized profile against the target; a profile that does
// not follow the target is no answer (e.g. a target that steps in slope: the envelope folds,
// and the follower skips the fold)
synthesis::RoundTrip check_round_trip(const SynthesizeOptions& o, const DesignSpec& spec, const Target& target,
                                      const synthesis::SynthesisOptions& opt, const synthesis::SynthesisResult& res,
                                      const RoundTripUnit& unit) {
  synthesis::RoundTrip rt;
  Status st = synthesis::round_trip(synthesis::with_profile(spec, res.profile), target.motion(), opt.controls,
                                    res.connection, rt, opt.target_node);
  if (!st.ok()) {
    st.message = "forward kinematics of the synthesized profile: " + st.message;
    throw NumericalError(with_slope_step(target, st));
  }
  if (!(rt.max_error_mm * unit.scale <= o.max_round_trip_error))
    throw NumericalError(with_slope_step(
        target,
        {StatusCode::infeasible,
         "the synthesized profile does not give the target: its forward kinematics misses it by " +
             format_value(rt.max_error_mm * unit.scale, 3) + " " + unit.name + " (rms " +
             format_value(rt.rms_error_mm * unit.scale, 3) + " " + unit.name + "), more than --max-round-trip-error " +
             format_value(o.max_round_trip_error, 3) + " " + unit.name,
         "cam " + format_value(rt.max_error_at_deg, 6) + " deg"}));
  return rt;
}

// report.json's checks: undercut, radii against the limits, pressure angle, the flat
// follower's face width, the round trip
nlohmann::json checks_json(const SynthesizeOptions& o, const DesignSpec& spec, const synthesis::SynthesisResult& res,
                           const synthesis::RoundTrip& rt, const RoundTripUnit& unit) {
  const bool flat = res.follower_shape == "line";
  double half_width = 0.0;
  for (const auto& c : spec.connections)
    if (c.name == res.connection) {
      const auto& fs = c.surface_a.node == res.follower_node ? c.surface_a : c.surface_b;
      if (fs.half_width_mm) half_width = *fs.half_width_mm;
    }
  nlohmann::json checks;
  checks["undercut"] = false;
  checks["min_radius_of_curvature_mm"] = res.min_radius_of_curvature_mm;
  checks["min_radius_of_curvature_at_profile_deg"] = res.min_radius_of_curvature_at_deg;
  checks["min_radius_allowed_mm"] = o.min_radius_mm;
  checks["min_radius_ok"] = res.min_radius_of_curvature_mm >= o.min_radius_mm &&
                            (!res.has_concave || res.min_concave_radius_mm >= o.min_radius_mm);
  checks["concave"] = res.has_concave;
  if (res.has_concave) {
    checks["min_concave_radius_mm"] = res.min_concave_radius_mm;
    checks["min_concave_radius_at_profile_deg"] = res.min_concave_radius_at_deg;
  }
  checks["grinding_wheel_radius_mm"] = o.wheel_radius_mm;
  checks["concave_ok"] = !res.concave_narrower_than_wheel;
  checks["max_pressure_angle_deg"] = rt.max_pressure_angle_deg;
  checks["max_pressure_angle_at_cam_deg"] = rt.max_pressure_angle_at_deg;
  if (flat) {
    checks["face_contact_offset_min_mm"] = res.face_offset_min_mm;
    checks["face_contact_offset_max_mm"] = res.face_offset_max_mm;
    const double needed = 2.0 * std::max(std::abs(res.face_offset_min_mm), std::abs(res.face_offset_max_mm));
    checks["face_width_needed_mm"] = needed;
    if (half_width > 0) checks["face_width_ok"] = needed <= 2.0 * half_width;
  }
  checks["round_trip_max_error_" + unit.name] = rt.max_error_mm * unit.scale;
  checks["round_trip_max_error_at_cam_deg"] = rt.max_error_at_deg;
  checks["round_trip_rms_error_" + unit.name] = rt.rms_error_mm * unit.scale;
  return checks;
}

// report.json: the inputs, the synthesized cam, the target's fit, the checks and the notes
nlohmann::json report_json(const SynthesizeOptions& o, const kin::Mechanism& mech, const Target& target,
                           const synthesis::SynthesisOptions& opt, const synthesis::SynthesisResult& res,
                           nlohmann::json checks) {
  nlohmann::json report;
  report["design"] = mech.name;
  report["design_file"] = o.design_file;
  report["target_file"] = o.target_file;
  report["target_angle_basis"] = io::to_string(target.basis);
  report["target_node"] = target.valve ? mech.nodes[mech.output_node].name : o.target_node;
  report["cam"] = o.cam;
  report["connection"] = res.connection;
  report["cam_node"] = res.cam_node;
  report["follower_node"] = res.follower_node;
  report["follower_shape"] = res.follower_shape;
  if (!mech.controls.empty()) report["control_" + std::string(mech.controls[0].is_angle ? "deg" : "mm")] = opt.controls[0];
  const synthesis::TargetLift& fit = target.lift;
  report["target"] = {{"points", target.points},
                      {"closed_on_base_circle", fit.closed_on_base_circle},
                      {"closure_message", fit.closure_message},
                      {"smoothed", o.smooth},
                      {"residual_rms_mm", fit.residual_rms_mm},
                      {"residual_max_mm", fit.residual_max_mm},
                      {"residual_max_at_cam_deg", fit.residual_max_at_deg},
                      {"max_lift_mm", fit.max_lift_mm},
                      {"max_lift_at_cam_deg", fit.max_lift_at_deg}};
  report["checks"] = std::move(checks);
  report["notes"] = res.notes;
  return report;
}

// each window of profile angle where a radius is too small, with the smallest there
void warn_radii(const SynthesizeOptions& o, const synthesis::SynthesisResult& res, const nlohmann::json& checks,
                Observer& observer) {
  auto smallest = [](const synthesis::FailureWindow& w) {
    return "down to " + format_value(w.worst, 4) + " mm at " + format_value(w.worst_at_deg, 5) + " deg";
  };
  if (!checks["min_radius_ok"].get<bool>())
    observer.note("warning: radius of curvature below the allowed " + std::to_string(o.min_radius_mm) + " mm in " +
         synthesis::describe_windows(res.below_min_radius, smallest) + " of profile angle");
  if (!checks["concave_ok"].get<bool>())
    observer.note("warning: concave radius " + std::to_string(res.min_concave_radius_mm) + " mm is below the grinding wheel "
         "radius " + std::to_string(o.wheel_radius_mm) + " mm in " +
         synthesis::describe_windows(res.concave_below_wheel, smallest) + " of profile angle");
}

}  // namespace

void validate(const SynthesizeOptions& o) {
  if (o.cam != "rotational" && o.cam != "swing")
    throw InputError("--cam: value '" + o.cam + "' is not one of rotational, swing");
  if (o.points < 36 || o.points > 36000)
    throw InputError("--points: value " + std::to_string(o.points) + " must be in [36, 36000]");
  check_positive("--knot-spacing", o.knot_spacing_deg);
  check_positive("--wheel-radius", o.wheel_radius_mm, false);
  check_positive("--min-radius", o.min_radius_mm, false);
  check_positive("--closure-tolerance", o.closure_tolerance_mm, false);
  check_positive("--max-round-trip-error", o.max_round_trip_error);
  if (o.master_radius_mm) check_positive("--master-radius", *o.master_radius_mm, false);
  if (!(o.grinding_step_deg >= 0.01 && o.grinding_step_deg <= 10.0))
    throw InputError("--grinding-step: value " + format_value(o.grinding_step_deg) + " must be in [0.01, 10]");
}

SynthesizeResult run_synthesize(const DesignSpec& spec, const io::CsvTable& table, const SynthesizeOptions& o,
                                Observer& observer) {
  // the design, and the target motion
  const kin::Mechanism mech = kin::compile(spec);
  const Target target = read_target(o, table, spec, mech, observer);
  // the synthesis at the chosen control position
  const synthesis::SynthesisOptions opt = synthesis_options(o, mech, target.valve, observer);
  synthesis::SynthesisResult res;
  if (const Status st = synthesis::synthesize(spec, target.motion(), opt, res); !st.ok())
    throw NumericalError(with_slope_step(target, st));
  // the forward kinematics of the profile against the target
  const RoundTripUnit unit = round_trip_unit(o, spec, target.valve);
  const synthesis::RoundTrip rt = check_round_trip(o, spec, target, opt, res, unit);
  // the checks, the report and the files of the profile
  const nlohmann::json checks = checks_json(o, spec, res, rt, unit);
  SynthesizeResult result;
  result.report = report_json(o, mech, target, opt, res, checks);
  record_overrides(result.report, o.overrides);
  result.exports =
      profile_exports(o.out_dir, o.design_file, o.overrides, spec, res, o.master_radius_mm, o.grinding_step_deg, result.report);
  // warnings on the radii, and the summary line
  warn_radii(o, res, checks, observer);
  result.summary = "synthesize: profile '" + res.profile.name + "' on '" + res.cam_node + "' (" + res.connection +
                   "), base circle " + std::to_string(res.base_radius_mm) + " mm, min radius of curvature " +
                   std::to_string(res.min_radius_of_curvature_mm) + " mm; round trip max error " +
                   std::to_string(rt.max_error_mm * unit.scale) + " " + unit.name;
  return result;
}

}  // namespace camopt::jobs
