// the bench job: a design's stages timed at their default settings and at tighter ones, with
// the default run's error against the tight run (bench.hpp, docs/cli.md "camopt bench").
#include "camopt/jobs/bench.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <functional>

#include "camopt/core/units.hpp"
#include "camopt/jobs/dynamics.hpp"
#include "camopt/jobs/kinematics.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::jobs {

namespace {

// tight settings: kinematics and rigid dynamics a 4x and 10x finer step, synthesis 4x the
// table points, the flexible model CVODE at rtol 1e-10 / atol 1e-12 (the bench_dynamics reference)
constexpr double kKinematicsRefine = 4.0, kRigidRefine = 10.0;
constexpr int kSynthesisPoints = 1440, kSynthesisTightPoints = 5760;
constexpr double kTightRtol = 1e-10, kTightAtol = 1e-12;
// the target of the synthesis: the design's own lift, sampled at [cam deg]
constexpr double kTargetStepDeg = 0.25;

// shortest round-trip text of a number; "" for NaN
std::string number_text(double v) {
  if (std::isnan(v)) return "";
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

// a CSV cell: quoted when it holds a comma, a quote or a line break
std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char ch : text) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

// the best wall time [s] of `repeat` calls of run, whose own figure is the time it returns
double best_seconds(int repeat, const std::function<double()>& run) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeat; ++r) best = std::min(best, run());
  return best;
}

// a column of a job's table by name (InputError-free: the jobs always write these)
const std::vector<double>& column(const io::Columns& table, const std::string& name) {
  const auto it = std::find(table.header.begin(), table.header.end(), name);
  CAMOPT_ASSERT(it != table.header.end());
  return table.values[static_cast<std::size_t>(it - table.header.begin())];
}
// the output lift column's name: lift_mm, or lift_deg for a rotating output node
std::string lift_column(const kin::Mechanism& mech) {
  return mech.nodes[mech.output_node].kind == NodeKind::translational ? "lift_mm" : "lift_deg";
}

// a row of a stage's run, its numbers to come
BenchRow row_of(const std::string& stage, const std::string& run, const std::string& setting) {
  BenchRow row;
  row.stage = stage;
  row.run = run;
  row.setting = setting;
  return row;
}

void fill_time(BenchRow& row, double seconds, double points) {
  row.points = points;
  row.time_ms = seconds * 1e3;
  row.ns_per_point = seconds * 1e9 / points;
}

// the lift between the default grid's points by linear interpolation against the tight
// grid, which holds every default point and `refine` - 1 points between each pair
double interpolation_error(const std::vector<double>& coarse, const std::vector<double>& fine, int refine) {
  double worst = 0.0;
  for (std::size_t j = 0; j < fine.size(); ++j) {
    const std::size_t i = j / static_cast<std::size_t>(refine);
    const double f = static_cast<double>(j % static_cast<std::size_t>(refine)) / refine;
    const double between = f == 0.0 ? coarse[i] : (1.0 - f) * coarse[i] + f * coarse[i + 1];
    worst = std::max(worst, std::abs(between - fine[j]));
  }
  return worst;
}

// the kinematic sweep of one control position with `outputs`, at the design's step and 4x finer
void kinematics_stage(const LoadedDesign& design, const BenchOptions& o, const std::string& outputs,
                      Observer& observer, std::vector<BenchRow>& rows) {
  KinematicsOptions k;
  k.design_file = o.design_file;
  k.control = o.control;
  k.outputs = outputs;
  const double step = driver_range(design.mech, 0.0).step;
  KinematicsResult coarse, fine;
  const double seconds = best_seconds(o.repeat, [&] {
    coarse = run_kinematics(design, k, observer);
    return coarse.seconds;
  });
  k.step_deg = step / kKinematicsRefine;
  fine = run_kinematics(design, k, observer);
  const std::string stage = "kinematics " + std::string(outputs == "lift" ? "lift" : "all");
  const std::string unit = design.mech.driver_is_angle() ? " deg" : " mm";
  BenchRow def = row_of(stage, "default", "step " + number_text(step) + unit);
  fill_time(def, seconds, static_cast<double>(coarse.points));
  const std::string lift = lift_column(design.mech);
  def.lift_error_mm = interpolation_error(column(coarse.columns, lift), column(fine.columns, lift),
                                          static_cast<int>(kKinematicsRefine));
  BenchRow tight = row_of(stage, "tight", "step " + number_text(k.step_deg) + unit);
  fill_time(tight, fine.seconds, static_cast<double>(fine.points));
  rows.push_back(def);
  rows.push_back(tight);
}

// the design's cam made again from its own lift (lash removed), at the default table
// resolution and 4x finer; the error of each is its round trip. Skipped, with the reason,
// for a design whose valve does not translate or whose cam the synthesizer cannot make
void synthesis_stage(const LoadedDesign& design, const BenchOptions& o, const std::vector<double>& controls,
                     std::vector<BenchRow>& rows) {
  BenchRow def = row_of("synthesis", "default", "points " + std::to_string(kSynthesisPoints));
  BenchRow tight = row_of("synthesis", "tight", "points " + std::to_string(kSynthesisTightPoints));
  const auto skip = [&](const std::string& why) {
    def.note = tight.note = "skipped: " + why;
    rows.push_back(def);
    rows.push_back(tight);
  };
  if (design.mech.nodes[design.mech.output_node].kind != NodeKind::translational)
    return skip("the output node does not translate (the synthesis target is a valve lift in mm)");
  DesignSpec spec = design.spec;
  for (auto& conn : spec.connections) conn.lash_mm = 0.0;
  try {
    const kin::Mechanism mech = kin::compile(spec);
    PeriodicSpline target;
    Status st = kin::periodic_motion(mech, mech.output_node, controls, kTargetStepDeg, target);
    if (!st.ok()) return skip("the design's own lift: " + st.str());
    for (BenchRow* row : {&def, &tight}) {
      synthesis::SynthesisOptions so;
      so.controls = controls;
      so.points = so.samples = row == &def ? kSynthesisPoints : kSynthesisTightPoints;
      synthesis::SynthesisResult made;
      const double seconds = best_seconds(row == &def ? o.repeat : 1, [&] {
        const auto t0 = std::chrono::steady_clock::now();
        st = synthesis::synthesize(spec, target, so, made);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      });
      if (!st.ok()) return skip("the synthesis fails: " + st.str());
      synthesis::RoundTrip rt;
      st = synthesis::round_trip(synthesis::with_profile(spec, made.profile), target, controls, made.connection, rt);
      if (!st.ok()) return skip("the round trip fails: " + st.str());
      fill_time(*row, seconds, static_cast<double>(made.angle_deg.size()));
      row->lift_error_mm = rt.max_error_mm;
    }
  } catch (const InputError& e) {
    return skip(e.what());
  }
  rows.push_back(def);
  rows.push_back(tight);
}

// the contacts' peak forces and separation speeds of a rigid or flexible summary's first result
struct DynamicsPeaks {
  std::vector<double> force, separation;
};
DynamicsPeaks peaks_of(const kin::Mechanism& mech, const nlohmann::json& summary) {
  DynamicsPeaks p;
  const nlohmann::json& result = summary["results"][0]["connections"];
  for (const auto& conn : mech.connections) {
    if (conn.kind != ConnectionKind::contact) continue;
    p.force.push_back(result[conn.name].value("max_force_N", 0.0));
    if (!summary.contains("separation")) continue;
    const nlohmann::json& sep = summary["separation"][0]["contacts"][conn.name]["separation_rpm"];
    p.separation.push_back(sep.is_null() ? std::numeric_limits<double>::infinity() : sep.get<double>());
  }
  return p;
}
// the largest peak-force error relative to the tight peak, and separation-speed error [rpm]
// (a contact that separates in one run only: +inf)
void peak_errors(const DynamicsPeaks& run, const DynamicsPeaks& tight, BenchRow& row) {
  row.force_error_rel = 0.0;
  for (std::size_t c = 0; c < run.force.size(); ++c)
    if (tight.force[c] != 0.0)
      row.force_error_rel = std::max(row.force_error_rel, std::abs(run.force[c] - tight.force[c]) / tight.force[c]);
  if (run.separation.empty()) return;
  row.separation_error_rpm = 0.0;
  for (std::size_t c = 0; c < run.separation.size(); ++c) {
    const double a = run.separation[c], b = tight.separation[c];
    if (a == b) continue;  // both +inf: never separates
    row.separation_error_rpm = std::max(row.separation_error_rpm, std::abs(a - b));
  }
}

// one cycle of the rigid model (mode a) at the design's step and 10x finer, or of the
// flexible model at the default tolerances and at rtol 1e-10 / atol 1e-12
void dynamics_stage(const LoadedDesign& design, const BenchOptions& o, bool flexible, Observer& observer,
                    std::vector<BenchRow>& rows) {
  DynamicsOptions d;
  d.design_file = o.design_file;
  d.model = flexible ? "flexible" : "rigid";
  d.rpm = number_text(o.rpm);
  d.control = o.control;
  const std::string stage = flexible ? "flexible" : "rigid";
  const double step = driver_range(design.mech, 0.0).step;
  const auto setting = [&] {
    return flexible ? "rtol " + number_text(d.flexible.relative_tolerance) + " atol " +
                          number_text(d.flexible.absolute_tolerance)
                    : "step " + number_text(d.step_deg > 0 ? d.step_deg : step) + " deg";
  };
  BenchRow def = row_of(stage, "default", setting());
  DynamicsResult coarse, fine;
  try {
    const double seconds = best_seconds(o.repeat, [&] {
      coarse = run_dynamics(design, d, observer);
      return coarse.seconds;
    });
    // per cam revolution integrated (the flexible model reports its last one)
    const auto per_cycle = [&](const DynamicsResult& r) {
      return flexible ? r.summary["results"][0].value("revolutions_integrated", 1.0) : 1.0;
    };
    // cam angles per run: the rows of its table at one speed and position
    const auto points = [&](const DynamicsResult& r) {
      return static_cast<double>(column(r.columns, lift_column(design.mech)).size());
    };
    fill_time(def, seconds / per_cycle(coarse), points(coarse));
    if (flexible) d.flexible.relative_tolerance = kTightRtol, d.flexible.absolute_tolerance = kTightAtol;
    else d.step_deg = step / kRigidRefine;
    fine = run_dynamics(design, d, observer);
    BenchRow tight = row_of(stage, "tight", setting());
    fill_time(tight, fine.seconds / per_cycle(fine), points(fine));
    peak_errors(peaks_of(design.mech, coarse.summary), peaks_of(design.mech, fine.summary), def);
    if (flexible) {
      const std::vector<double>&a = column(coarse.columns, lift_column(design.mech)),
                           &b = column(fine.columns, lift_column(design.mech));
      def.lift_error_mm = 0.0;
      for (std::size_t i = 0; i < a.size(); ++i) def.lift_error_mm = std::max(def.lift_error_mm, std::abs(a[i] - b[i]));
    }
    rows.push_back(def);
    rows.push_back(tight);
  } catch (const InputError& e) {  // no dynamics data in the design
    def.note = "skipped: " + std::string(e.what());
    BenchRow tight = def;
    tight.run = "tight";
    rows.push_back(def);
    rows.push_back(tight);
  }
}

// the stages' jobs report to this: their notes (a kinematics summary line per run) are not the
// bench's; Ctrl-C still stops them
class StageObserver : public Observer {
 public:
  explicit StageObserver(Observer& outer) : outer_(outer) {}
  bool cancel_requested() override { return outer_.cancel_requested(); }

 private:
  Observer& outer_;
};

}  // namespace

void validate(const BenchOptions& o) {
  if (!(o.rpm > 0 && o.rpm <= 1e6)) throw InputError("--rpm: value " + format_value(o.rpm) + " must be in (0, 1e6]");
  if (o.repeat < 1 || o.repeat > 1000)
    throw InputError("--repeat: value " + std::to_string(o.repeat) + " must be in [1, 1000]");
}

BenchResult run_bench(const LoadedDesign& design, const BenchOptions& o, Observer& observer) {
  // the options and the one control position
  validate(o);
  const ControlPositions controls = resolve_controls(design.mech, o.design_file, o.control);
  if (controls.positions.size() != 1)
    throw InputError("--control: value '" + o.control + "' must be one position (the bench times one)");
  // the stages, each at its default and its tight setting
  BenchResult out;
  StageObserver stage(observer);
  observer.begin("bench", 5);
  kinematics_stage(design, o, "lift", stage, out.rows);
  observer.advance();
  kinematics_stage(design, o, "all", stage, out.rows);
  observer.advance();
  synthesis_stage(design, o, controls.positions[0], out.rows);
  observer.advance();
  dynamics_stage(design, o, false, stage, out.rows);
  observer.advance();
  dynamics_stage(design, o, true, stage, out.rows);
  observer.advance();
  observer.end();
  return out;
}

namespace {
const std::vector<std::string> kBenchHeader = {"stage", "run", "setting", "points", "time_ms", "ns_per_point",
                                               "lift_error_mm", "force_error_rel", "separation_error_rpm", "note"};
// a row's cells, in kBenchHeader's order
std::vector<std::string> cells_of(const BenchRow& r) {
  return {r.stage, r.run, r.setting, number_text(r.points), number_text(r.time_ms), number_text(r.ns_per_point),
          number_text(r.lift_error_mm), number_text(r.force_error_rel), number_text(r.separation_error_rpm), r.note};
}
}  // namespace

std::string bench_csv(const BenchResult& result) {
  std::string text;
  for (std::size_t h = 0; h < kBenchHeader.size(); ++h) text += (h ? "," : "") + kBenchHeader[h];
  text += "\n";
  for (const BenchRow& r : result.rows) {
    const std::vector<std::string> cells = cells_of(r);
    for (std::size_t h = 0; h < cells.size(); ++h) text += (h ? "," : "") + csv_cell(cells[h]);
    text += "\n";
  }
  return text;
}

std::string bench_text(const BenchResult& result) {
  // the numbers to 3 significant digits, columns as wide as their widest cell
  const auto short_number = [](double v) {
    if (std::isnan(v)) return std::string("-");
    char buffer[32];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 3).ptr);
  };
  std::vector<std::vector<std::string>> table{kBenchHeader};
  table[0].pop_back();  // the note goes after the row
  for (const BenchRow& r : result.rows)
    table.push_back({r.stage, r.run, r.setting, short_number(r.points), short_number(r.time_ms),
                     short_number(r.ns_per_point), short_number(r.lift_error_mm), short_number(r.force_error_rel),
                     short_number(r.separation_error_rpm)});
  std::vector<std::size_t> width(table[0].size(), 0);
  for (const auto& row : table)
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::string text;
  for (std::size_t i = 0; i < table.size(); ++i) {
    for (std::size_t c = 0; c < table[i].size(); ++c)
      text += table[i][c] + std::string(width[c] - table[i][c].size() + (c + 1 < table[i].size() ? 2 : 0), ' ');
    if (i > 0 && !result.rows[i - 1].note.empty() && result.rows[i - 1].run == "default")
      text += "  (" + result.rows[i - 1].note + ")";
    text += "\n";
  }
  return text;
}

}  // namespace camopt::jobs
