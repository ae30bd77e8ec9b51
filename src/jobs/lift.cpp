// the lift job: the options as a lift event of the lift-law library, the event tabulated over
// one cam revolution, and its summary.
#include "camopt/jobs/lift.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

#include "camopt/core/error.hpp"
#include "camopt/synthesis/lift_law_event.hpp"

namespace camopt::jobs {

namespace {

constexpr double kCycleDeg = 360.0;   // one cam revolution [cam deg]
constexpr double kMaxStepDeg = 10.0;  // coarser tables cannot resolve a lift event [cam deg]

// a number in a message or a note (%g, `digits` significant)
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
  const bool by_duration = !o.open_deg;
  const std::vector<std::pair<std::string, std::string>> names = {
      {"opening.duration_deg", by_duration ? "opening flank (half of --duration minus --dwell)" : "--open"},
      {"closing.duration_deg", by_duration ? "closing flank (half of --duration minus --dwell)" : "--close"},
      {"opening.ramp_height_mm", "--ramp-height"},
      {"closing.ramp_height_mm", o.close_ramp_height_mm ? "--close-ramp-height" : "--ramp-height"},
      {"opening.ramp_length_deg", "--ramp-length"},
      {"closing.ramp_length_deg", o.close_ramp_length_deg ? "--close-ramp-length" : "--ramp-length"},
      {"opening.acc_controls", "--acc-bspline"},
      {"closing.acc_controls", "--acc-bspline"},
      {"opening.bspline_degree", "--bspline-degree"},
      {"closing.bspline_degree", "--bspline-degree"},
      {"opening.law", "--law"},
      {"closing.law", o.close_law ? "--close-law" : "--law"},
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

// the flanks' durations: --duration (whole event, split evenly) or --open and --close
void set_durations(const LiftOptions& o, synthesis::LiftEventSpec& spec) {
  if (o.duration_deg && (o.open_deg || o.close_deg))
    throw InputError("--duration: give either --duration (whole event) or --open and --close (each flank), not both");
  if (o.open_deg.has_value() != o.close_deg.has_value())
    throw InputError(std::string(o.open_deg ? "--open" : "--close") +
                     ": asymmetric events need both --open and --close [cam deg]");
  if (o.open_deg) {
    spec.opening.duration_deg = *o.open_deg;
    spec.closing.duration_deg = *o.close_deg;
    return;
  }
  const double duration = o.duration_deg.value_or(130.0);
  if (!(duration > 0.0)) throw InputError("--duration = " + fmt(duration) + " cam deg: must be positive");
  if (!(duration < kCycleDeg))
    throw InputError("--duration = " + fmt(duration) + " cam deg: the event must be shorter than 360 cam deg "
                     "(the cam needs a base circle)");
  if (!(duration > o.dwell_deg))
    throw InputError("--duration = " + fmt(duration) + " cam deg: must be longer than --dwell = " + fmt(o.dwell_deg) +
                     " cam deg (the duration includes the dwell)");
  spec.opening.duration_deg = spec.closing.duration_deg = 0.5 * (duration - o.dwell_deg);
}

// law parameters go only where a flank uses them; a parameter no flank uses is a mistake
void set_law_parameters(const LiftOptions& o, synthesis::LiftEventSpec& spec) {
  using synthesis::LawKind;
  const bool bspline = spec.opening.law == LawKind::bspline || spec.closing.law == LawKind::bspline;
  const bool polydyne = spec.opening.law == LawKind::polydyne || spec.closing.law == LawKind::polydyne;
  if (bspline && !o.acc_controls)
    throw InputError("--acc-bspline: law bspline needs the acceleration control values, e.g. "
                     "--acc-bspline 0,1,2,1,-0.5,-1,-1,-0.5,0");
  if (!bspline && (o.acc_controls || o.bspline_degree))
    throw InputError(std::string(o.acc_controls ? "--acc-bspline" : "--bspline-degree") +
                     ": only used by law bspline, but the laws are " + to_string(spec.opening.law) + " / " +
                     to_string(spec.closing.law));
  if (!polydyne && (o.polydyne_rpm || o.polydyne_hz))
    throw InputError(std::string(o.polydyne_rpm ? "--polydyne-rpm" : "--polydyne-fn") +
                     ": only used by law polydyne, but the laws are " + to_string(spec.opening.law) + " / " +
                     to_string(spec.closing.law));
  for (auto* flank : {&spec.opening, &spec.closing}) {
    if (flank->law != LawKind::bspline) continue;
    flank->acc_controls = *o.acc_controls;
    flank->bspline_degree = o.bspline_degree.value_or(3);
  }
  spec.polydyne_engine_rpm = o.polydyne_rpm.value_or(0.0);
  spec.polydyne_natural_hz = o.polydyne_hz.value_or(0.0);
}

// options -> spec; rules that concern only the options themselves are checked here, the
// rest by synthesis::validate / compile
synthesis::LiftEventSpec build_spec(const LiftOptions& o) {
  for (const auto& [name, v] :
       {std::pair<const char*, std::optional<double>>{"--lift", o.lift_mm}, {"--duration", o.duration_deg},
        {"--open", o.open_deg}, {"--close", o.close_deg}, {"--dwell", o.dwell_deg},
        {"--ramp-height", o.ramp_height_mm}, {"--ramp-length", o.ramp_length_deg},
        {"--close-ramp-height", o.close_ramp_height_mm}, {"--close-ramp-length", o.close_ramp_length_deg},
        {"--ramp-blend", o.ramp_blend}, {"--peak-at", o.peak_deg}, {"--step", o.step_deg},
        {"--polydyne-rpm", o.polydyne_rpm}, {"--polydyne-fn", o.polydyne_hz}})
    if (v) require_finite(name, *v);

  synthesis::LiftEventSpec spec;
  spec.opening.law = synthesis::parse_law(o.law, "--law");
  spec.closing.law = o.close_law ? synthesis::parse_law(*o.close_law, "--close-law") : spec.opening.law;
  spec.max_lift_mm = o.lift_mm;
  spec.peak_deg = o.peak_deg;
  spec.dwell_deg = o.dwell_deg;
  spec.ramp_blend = o.ramp_blend;
  set_durations(o, spec);
  spec.opening.ramp_height_mm = o.ramp_height_mm;
  spec.opening.ramp_length_deg = o.ramp_length_deg;
  spec.closing.ramp_height_mm = o.close_ramp_height_mm.value_or(o.ramp_height_mm);
  spec.closing.ramp_length_deg = o.close_ramp_length_deg.value_or(o.ramp_length_deg);
  set_law_parameters(o, spec);
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

// one cycle, 0 <= cam angle < 360; crank basis: crank = crank_per_cam * cam, and
// d^k/dcrank^k = d^k/dcam^k / crank_per_cam^k
io::Columns cycle_table(const synthesis::LiftEvent& event, double crank_per_cam, int rows, bool crank) {
  const double per = crank ? 1.0 / crank_per_cam : 1.0;
  io::Columns table;
  table.header = {crank ? "crank_deg" : "cam_deg", "lift_mm", "vel_mm_per_deg", "acc_mm_per_deg2", "jerk_mm_per_deg3"};
  table.values.assign(5, std::vector<double>(static_cast<std::size_t>(rows)));
  auto& columns = table.values;
  for (int i = 0; i < rows; ++i) {
    const double cam = kCycleDeg * i / rows;
    const synthesis::Motion m = event.evaluate(cam);
    const auto r = static_cast<std::size_t>(i);
    columns[0][r] = crank ? cam * crank_per_cam : cam;
    columns[1][r] = m.lift;
    columns[2][r] = m.vel * per;
    columns[3][r] = m.acc * per * per;
    columns[4][r] = m.jerk * per * per * per;
  }
  return table;
}

// the event's figures [cam deg, mm, per cam deg], and their lines as notes
nlohmann::json summarize(const synthesis::LiftEventSpec& spec, const synthesis::LiftEvent& event, Observer& observer) {
  const synthesis::LiftEventSummary s = synthesis::summarize(event);
  const double c = spec.crank_per_cam;
  observer.note("lift: opening " + describe_flank(event.opening()) + ", dwell " + fmt(spec.dwell_deg) +
                " cam deg, closing " + describe_flank(event.closing()));
  observer.note("lift: max lift " + fmt(s.max_lift_mm) + " mm at " + fmt(s.max_lift_at_deg) + " cam deg; duration " +
                fmt(s.event_deg) + " cam deg (" + fmt(c * s.event_deg) + " crank deg) at 0 mm, " +
                fmt(s.duration_0p1mm_deg) + " (" + fmt(c * s.duration_0p1mm_deg) + ") at 0.1 mm, " +
                fmt(s.duration_1mm_deg) + " (" + fmt(c * s.duration_1mm_deg) + ") at 1 mm");
  observer.note("lift: velocity " + fmt(s.min_vel) + " .. " + fmt(s.max_vel) + " mm/deg; acceleration max " +
                fmt(s.max_acc) + " mm/deg^2 at " + fmt(s.max_acc_at_deg) + " cam deg, min " + fmt(s.min_acc) +
                " mm/deg^2 at " + fmt(s.min_acc_at_deg) + " cam deg; max |jerk| " + fmt(s.max_abs_jerk) +
                " mm/deg^3 (per cam deg)");
  return {{"opening", describe_flank(event.opening())},
          {"closing", describe_flank(event.closing())},
          {"dwell_cam_deg", spec.dwell_deg},
          {"crank_per_cam", c},
          {"max_lift_mm", s.max_lift_mm},
          {"max_lift_at_cam_deg", s.max_lift_at_deg},
          {"duration_0mm_cam_deg", s.event_deg},
          {"duration_0p1mm_cam_deg", s.duration_0p1mm_deg},
          {"duration_1mm_cam_deg", s.duration_1mm_deg},
          {"min_vel_mm_per_deg", s.min_vel},
          {"max_vel_mm_per_deg", s.max_vel},
          {"max_acc_mm_per_deg2", s.max_acc},
          {"max_acc_at_cam_deg", s.max_acc_at_deg},
          {"min_acc_mm_per_deg2", s.min_acc},
          {"min_acc_at_cam_deg", s.min_acc_at_deg},
          {"max_abs_jerk_mm_per_deg3", s.max_abs_jerk}};
}

}  // namespace

LiftResult run_lift(const LiftOptions& o, Observer& observer) {
  // options -> spec -> event: every check before anything is computed
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
  // the table, then its summary (the notes)
  LiftResult out;
  out.table = cycle_table(event, spec.crank_per_cam, rows, o.basis == "crank");
  out.summary = summarize(spec, event, observer);
  return out;
}

}  // namespace camopt::jobs
