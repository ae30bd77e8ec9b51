// camopt lift: a target valve lift from the lift-law library, written
// as a one-cycle table for `camopt synthesize`.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

namespace {

constexpr double kCycleDeg = 360.0;   // one cam revolution [cam deg]
constexpr double kMaxStepDeg = 10.0;  // coarser tables cannot resolve a lift event [cam deg]

struct LiftOptions {
  std::string law, close_law, out, basis = "cam";
  ReportOptions report;  // --no-report, --figures
  double lift_mm = 10.0;
  double duration_deg = 130.0;  // whole event (ramps and dwell included) [cam deg]
  double open_deg = 0.0, close_deg = 0.0;
  double dwell_deg = 0.0;
  double ramp_height_mm = 0.0, ramp_length_deg = 0.0;
  double close_ramp_height_mm = 0.0, close_ramp_length_deg = 0.0;
  double ramp_blend = 0.5;
  double peak_deg = 180.0;
  double step_deg = 0.25;
  std::vector<double> acc_controls;
  int bspline_degree = 3;
  double polydyne_rpm = 0.0, polydyne_hz = 0.0;
  // set by setup: which options the user gave
  CLI::Option *duration = nullptr, *open = nullptr, *close = nullptr, *close_ramp_height = nullptr,
              *close_ramp_length = nullptr, *close_law_opt = nullptr, *acc = nullptr, *degree = nullptr,
              *polydyne_rpm_opt = nullptr, *polydyne_hz_opt = nullptr;
};

bool given(const CLI::Option* o) { return o != nullptr && o->count() > 0; }

std::string fmt(double v, int digits = 6) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::string::size_type at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

// the library names spec fields (opening.ramp_length_deg, ...); say which option set them
std::string with_option_names(std::string message, const LiftOptions& o) {
  const bool by_duration = !given(o.open);
  const std::vector<std::pair<std::string, std::string>> names = {
      {"opening.duration_deg", by_duration ? "opening flank (half of --duration minus --dwell)" : "--open"},
      {"closing.duration_deg", by_duration ? "closing flank (half of --duration minus --dwell)" : "--close"},
      {"opening.ramp_height_mm", "--ramp-height"},
      {"closing.ramp_height_mm", given(o.close_ramp_height) ? "--close-ramp-height" : "--ramp-height"},
      {"opening.ramp_length_deg", "--ramp-length"},
      {"closing.ramp_length_deg", given(o.close_ramp_length) ? "--close-ramp-length" : "--ramp-length"},
      {"opening.acc_controls", "--acc-bspline"},
      {"closing.acc_controls", "--acc-bspline"},
      {"opening.bspline_degree", "--bspline-degree"},
      {"closing.bspline_degree", "--bspline-degree"},
      {"opening.law", "--law"},
      {"closing.law", given(o.close_law_opt) ? "--close-law" : "--law"},
      {"max_lift_mm", "--lift"},
      {"peak_deg", "--peak-at"},
      {"dwell_deg", "--dwell"},
      {"ramp_blend", "--ramp-blend"},
      {"polydyne_engine_rpm", "--polydyne-rpm"},
      {"polydyne_natural_hz", "--polydyne-fn"},
  };
  for (const auto& [field, option] : names) replace_all(message, field, option);
  return message;
}

void require_finite(const char* option, double v) {
  if (!std::isfinite(v)) throw InputError(std::string(option) + " = " + fmt(v) + ": must be a finite number");
}

// options -> spec; rules that concern only the options themselves are checked here, the
// rest by synthesis::validate / compile
synthesis::LiftEventSpec build_spec(const LiftOptions& o) {
  using synthesis::LawKind;
  for (const auto& [name, v] :
       {std::pair<const char*, double>{"--lift", o.lift_mm}, {"--duration", o.duration_deg}, {"--open", o.open_deg},
        {"--close", o.close_deg}, {"--dwell", o.dwell_deg}, {"--ramp-height", o.ramp_height_mm},
        {"--ramp-length", o.ramp_length_deg}, {"--close-ramp-height", o.close_ramp_height_mm},
        {"--close-ramp-length", o.close_ramp_length_deg}, {"--ramp-blend", o.ramp_blend}, {"--peak-at", o.peak_deg},
        {"--step", o.step_deg}, {"--polydyne-rpm", o.polydyne_rpm}, {"--polydyne-fn", o.polydyne_hz}})
    require_finite(name, v);

  synthesis::LiftEventSpec spec;
  spec.opening.law = synthesis::parse_law(o.law, "--law");
  spec.closing.law = given(o.close_law_opt) ? synthesis::parse_law(o.close_law, "--close-law") : spec.opening.law;
  spec.max_lift_mm = o.lift_mm;
  spec.peak_deg = o.peak_deg;
  spec.dwell_deg = o.dwell_deg;
  spec.ramp_blend = o.ramp_blend;

  // durations: --duration (whole event, split evenly) or --open and --close
  if (given(o.duration) && (given(o.open) || given(o.close)))
    throw InputError("--duration: give either --duration (whole event) or --open and --close (each flank), not both");
  if (given(o.open) != given(o.close))
    throw InputError(std::string(given(o.open) ? "--open" : "--close") +
                     ": asymmetric events need both --open and --close [cam deg]");
  if (given(o.open)) {
    spec.opening.duration_deg = o.open_deg;
    spec.closing.duration_deg = o.close_deg;
  } else {
    if (!(o.duration_deg > 0.0))
      throw InputError("--duration = " + fmt(o.duration_deg) + " cam deg: must be positive");
    if (!(o.duration_deg < kCycleDeg))
      throw InputError("--duration = " + fmt(o.duration_deg) + " cam deg: the event must be shorter than 360 cam deg "
                       "(the cam needs a base circle)");
    if (!(o.duration_deg > o.dwell_deg))
      throw InputError("--duration = " + fmt(o.duration_deg) + " cam deg: must be longer than --dwell = " +
                       fmt(o.dwell_deg) + " cam deg (the duration includes the dwell)");
    spec.opening.duration_deg = spec.closing.duration_deg = 0.5 * (o.duration_deg - o.dwell_deg);
  }

  spec.opening.ramp_height_mm = o.ramp_height_mm;
  spec.opening.ramp_length_deg = o.ramp_length_deg;
  spec.closing.ramp_height_mm = given(o.close_ramp_height) ? o.close_ramp_height_mm : o.ramp_height_mm;
  spec.closing.ramp_length_deg = given(o.close_ramp_length) ? o.close_ramp_length_deg : o.ramp_length_deg;

  // law parameters go only where a flank uses them; a parameter no flank uses is a mistake
  const bool bspline = spec.opening.law == LawKind::bspline || spec.closing.law == LawKind::bspline;
  const bool polydyne = spec.opening.law == LawKind::polydyne || spec.closing.law == LawKind::polydyne;
  if (bspline && !given(o.acc))
    throw InputError("--acc-bspline: law bspline needs the acceleration control values, e.g. "
                     "--acc-bspline 0,1,2,1,-0.5,-1,-1,-0.5,0");
  if (!bspline && (given(o.acc) || given(o.degree)))
    throw InputError(std::string(given(o.acc) ? "--acc-bspline" : "--bspline-degree") +
                     ": only used by law bspline, but the laws are " + to_string(spec.opening.law) + " / " +
                     to_string(spec.closing.law));
  if (!polydyne && (given(o.polydyne_rpm_opt) || given(o.polydyne_hz_opt)))
    throw InputError(std::string(given(o.polydyne_rpm_opt) ? "--polydyne-rpm" : "--polydyne-fn") +
                     ": only used by law polydyne, but the laws are " + to_string(spec.opening.law) + " / " +
                     to_string(spec.closing.law));
  for (auto* flank : {&spec.opening, &spec.closing}) {
    if (flank->law != LawKind::bspline) continue;
    flank->acc_controls = o.acc_controls;
    flank->bspline_degree = o.bspline_degree;
  }
  spec.polydyne_engine_rpm = o.polydyne_rpm;
  spec.polydyne_natural_hz = o.polydyne_hz;
  return spec;
}

// the number of table rows over one cycle; InputError unless the step divides 360
int cycle_rows(double step_deg) {
  if (!(step_deg > 0.0) || step_deg > kMaxStepDeg)
    throw InputError("--step = " + fmt(step_deg) + " cam deg: must be in (0, " + fmt(kMaxStepDeg) + "]");
  const double n = kCycleDeg / step_deg;
  if (n > kMaxSweepPoints)
    throw InputError("--step = " + fmt(step_deg) + " cam deg: gives " + fmt(n) + " rows per cycle (at most " +
                     fmt(kMaxSweepPoints) + ")");
  const double rounded = std::round(n);
  if (std::abs(n - rounded) > 1e-9 * n)
    throw InputError("--step = " + fmt(step_deg, 10) + " cam deg: must divide 360 cam deg into whole steps (360 / " +
                     fmt(step_deg, 10) + " = " + fmt(n, 10) + ")");
  return static_cast<int>(rounded);
}

std::string describe_flank(const synthesis::Flank& f) {
  std::string s = std::string(to_string(f.law().kind())) + " over " + fmt(f.duration_deg()) + " cam deg";
  if (f.ramp_length_deg() > 0.0)
    s += " (ramp " + fmt(f.ramp_height_mm()) + " mm over " + fmt(f.ramp_length_deg()) + " cam deg at " +
         fmt(f.ramp_velocity()) + " mm/deg)";
  if (f.law().kind() == synthesis::LawKind::polydyne)
    s += " [polydyne K = " + fmt(static_cast<const synthesis::Polydyne&>(f.law()).dynamic_factor()) + "]";
  if (f.law().kind() == synthesis::LawKind::bspline)
    s += " [bspline closure changed the control values by " +
         fmt(100.0 * static_cast<const synthesis::BSplineAcceleration&>(f.law()).closure_change(), 3) + " % rms]";
  return s;
}

void run_lift(const LiftOptions& o) {
  // options -> spec -> event: every check before anything is written
  if (o.basis != "cam" && o.basis != "crank")
    throw InputError("--basis: unknown angle basis '" + o.basis + "' (allowed: cam, crank)");
  const synthesis::LiftEventSpec spec = build_spec(o);
  const synthesis::LiftEvent event = [&] {
    try {
      return synthesis::LiftEvent::compile(spec);
    } catch (const InputError& e) {
      throw InputError(with_option_names(e.what(), o));
    }
  }();
  const int rows = cycle_rows(o.step_deg);

  // one cycle, 0 <= cam angle < 360; crank basis: crank = crank_per_cam * cam, and
  // d^k/dcrank^k = d^k/dcam^k / crank_per_cam^k
  const bool crank = o.basis == "crank";
  const double per = crank ? 1.0 / spec.crank_per_cam : 1.0;
  std::vector<std::vector<double>> columns(5, std::vector<double>(static_cast<std::size_t>(rows)));
  for (int i = 0; i < rows; ++i) {
    const double cam = kCycleDeg * i / rows;
    const synthesis::Motion m = event.evaluate(cam);
    const auto r = static_cast<std::size_t>(i);
    columns[0][r] = crank ? cam * spec.crank_per_cam : cam;
    columns[1][r] = m.lift;
    columns[2][r] = m.vel * per;
    columns[3][r] = m.acc * per * per;
    columns[4][r] = m.jerk * per * per * per;
  }
  const std::vector<std::string> header = {crank ? "crank_deg" : "cam_deg", "lift_mm", "vel_mm_per_deg",
                                           "acc_mm_per_deg2", "jerk_mm_per_deg3"};
  io::write_csv(o.out, header, columns);

  // summary on stderr [cam deg]
  const synthesis::LiftEventSummary s = synthesis::summarize(event);
  const double c = spec.crank_per_cam;
  info("lift: opening " + describe_flank(event.opening()) + ", dwell " + fmt(spec.dwell_deg) + " cam deg, closing " +
       describe_flank(event.closing()));
  info("lift: max lift " + fmt(s.max_lift_mm) + " mm at " + fmt(s.max_lift_at_deg) + " cam deg; duration " +
       fmt(s.event_deg) + " cam deg (" + fmt(c * s.event_deg) + " crank deg) at 0 mm, " + fmt(s.duration_0p1mm_deg) +
       " (" + fmt(c * s.duration_0p1mm_deg) + ") at 0.1 mm, " + fmt(s.duration_1mm_deg) + " (" +
       fmt(c * s.duration_1mm_deg) + ") at 1 mm");
  info("lift: velocity " + fmt(s.min_vel) + " .. " + fmt(s.max_vel) + " mm/deg; acceleration max " + fmt(s.max_acc) +
       " mm/deg^2 at " + fmt(s.max_acc_at_deg) + " cam deg, min " + fmt(s.min_acc) + " mm/deg^2 at " +
       fmt(s.min_acc_at_deg) + " cam deg; max |jerk| " + fmt(s.max_abs_jerk) + " mm/deg^3 (per cam deg)");
  info("lift: wrote " + o.out + " (" + std::to_string(rows) + " rows, " + header[0] + " 0 .. " +
       fmt(columns[0].back()) + ")");
  // the page of the table, <stem>.report.html beside it
  write_run_report(o.out, o.report);
}

}  // namespace

void setup_lift(CLI::App& app) {
  auto opts = std::make_shared<LiftOptions>();
  auto* cmd = app.add_subcommand(
      "lift", "generate a target valve lift over one cam revolution from a lift law: opening ramp, rise, dwell, "
              "fall, closing ramp, base circle. Every angle option is in cam degrees.");
  LiftOptions& o = *opts;
  cmd->add_option("--law", o.law, "lift law of the opening flank (and of the closing flank unless --close-law): " +
                                      synthesis::law_names())
      ->required();
  o.close_law_opt = cmd->add_option("--close-law", o.close_law, "lift law of the closing flank (default: --law)");
  cmd->add_option("--lift", o.lift_mm, "maximum lift [mm] (default 10)");
  o.duration = cmd->add_option("--duration", o.duration_deg,
                               "whole event at zero lift: opening ramp + rise + dwell + fall + closing ramp [cam deg]; "
                               "symmetric (default 130)");
  o.open = cmd->add_option("--open", o.open_deg,
                           "opening flank: start of the opening ramp to max lift [cam deg] (with --close, "
                           "instead of --duration)");
  o.close = cmd->add_option("--close", o.close_deg, "closing flank: max lift (end of dwell) to end of the closing ramp "
                                                    "[cam deg] (with --open)");
  cmd->add_option("--dwell", o.dwell_deg, "dwell at maximum lift [cam deg] (default 0)");
  cmd->add_option("--ramp-height", o.ramp_height_mm, "ramp height, lift at the end of each ramp [mm] (default 0: no ramp)");
  cmd->add_option("--ramp-length", o.ramp_length_deg, "ramp length of each ramp [cam deg] (default 0: no ramp)");
  o.close_ramp_height = cmd->add_option("--close-ramp-height", o.close_ramp_height_mm,
                                        "closing ramp height [mm] (default: --ramp-height)");
  o.close_ramp_length = cmd->add_option("--close-ramp-length", o.close_ramp_length_deg,
                                        "closing ramp length [cam deg] (default: --ramp-length)");
  cmd->add_option("--ramp-blend", o.ramp_blend,
                  "fraction of each ramp spent reaching the constant ramp velocity [fraction, 0 < f <= 1] (default 0.5)");
  cmd->add_option("--peak-at", o.peak_deg, "cam angle of maximum lift, the middle of the dwell [cam deg], "
                                           "0 <= angle < 360 (default 180)");
  o.acc = cmd->add_option("--acc-bspline", o.acc_controls,
                          "law bspline: acceleration b-spline control values, a shape [any unit, comma list]; "
                          "closed to zero end acceleration and velocity and scaled to the lift")
              ->delimiter(',');
  o.degree = cmd->add_option("--bspline-degree", o.bspline_degree,
                             "law bspline: degree of the acceleration b-spline [polynomial degree, 2..5] (default 3)");
  o.polydyne_rpm_opt = cmd->add_option("--polydyne-rpm", o.polydyne_rpm,
                                       "law polydyne: design engine speed [rpm, crankshaft]");
  o.polydyne_hz_opt = cmd->add_option("--polydyne-fn", o.polydyne_hz,
                                      "law polydyne: natural frequency of the valvetrain [Hz]");
  cmd->add_option("--step", o.step_deg, "table step [cam deg]; must divide 360 (default 0.25)");
  cmd->add_option("--basis", o.basis, "angle column of the table: cam (cam_deg) or crank (crank_deg = 2 x cam, "
                                      "derivatives per crank deg) (default cam)");
  cmd->add_option("--out", o.out, "output CSV: cam_deg (or crank_deg), lift_mm, vel_mm_per_deg, acc_mm_per_deg2, "
                                  "jerk_mm_per_deg3")
      ->required();
  add_report_options(*cmd, o.report, "<stem>.report.html beside the CSV",
                     "<stem>.<plot id>.svg or .png beside the CSV");
  cmd->callback([opts] { run_lift(*opts); });
}

}  // namespace camopt::cli
