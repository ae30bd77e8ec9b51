// camopt lift: a target valve lift from the lift-law library (the lift job), written
// as a one-cycle table for `camopt synthesize`.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "camopt/io/csv.hpp"
#include "camopt/jobs/lift.hpp"
#include "camopt/synthesis/lift_law_event.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

namespace {

struct LiftOptions {
  jobs::LiftOptions job;  // --law, --lift, the flanks, the ramps, the law parameters, --step, --basis
  std::string out;
  ReportOptions report;  // --no-report, --figures
  // the job's options that have a "not given" (std::nullopt): read from CLI11 once parsed
  std::string close_law;
  double duration_deg = 130.0, open_deg = 0.0, close_deg = 0.0;
  double close_ramp_height_mm = 0.0, close_ramp_length_deg = 0.0;
  std::vector<double> acc_controls;
  int bspline_degree = 3;
  double polydyne_rpm = 0.0, polydyne_hz = 0.0;
  CLI::Option *duration = nullptr, *open = nullptr, *close = nullptr, *close_ramp_height = nullptr,
              *close_ramp_length = nullptr, *close_law_opt = nullptr, *acc = nullptr, *degree = nullptr,
              *polydyne_rpm_opt = nullptr, *polydyne_hz_opt = nullptr;
};

// the value of an option the user gave, else nothing
template <class T>
std::optional<T> given(const CLI::Option* option, const T& value) {
  return option != nullptr && option->count() > 0 ? std::optional<T>(value) : std::nullopt;
}

// the job's notes, kept until the table is written (then printed, as before the job existed)
class HeldNotes : public jobs::Observer {
 public:
  void note(const std::string& message) override { notes_.push_back(message); }
  void print() const {
    for (const std::string& n : notes_) info(n);
  }

 private:
  std::vector<std::string> notes_;
};

std::string fmt(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

void run_lift(LiftOptions& o) {
  // the options the user gave, the job, then the table and its summary on stderr
  jobs::LiftOptions& job = o.job;
  job.close_law = given(o.close_law_opt, o.close_law);
  job.duration_deg = given(o.duration, o.duration_deg);
  job.open_deg = given(o.open, o.open_deg);
  job.close_deg = given(o.close, o.close_deg);
  job.close_ramp_height_mm = given(o.close_ramp_height, o.close_ramp_height_mm);
  job.close_ramp_length_deg = given(o.close_ramp_length, o.close_ramp_length_deg);
  job.acc_controls = given(o.acc, o.acc_controls);
  job.bspline_degree = given(o.degree, o.bspline_degree);
  job.polydyne_rpm = given(o.polydyne_rpm_opt, o.polydyne_rpm);
  job.polydyne_hz = given(o.polydyne_hz_opt, o.polydyne_hz);
  HeldNotes notes;
  const jobs::LiftResult result = jobs::run_lift(job, notes);
  const io::Columns& table = result.table;
  io::write_csv(o.out, table.header, table.values);
  notes.print();
  info("lift: wrote " + o.out + " (" + std::to_string(table.values[0].size()) + " rows, " + table.header[0] +
       " 0 .. " + fmt(table.values[0].back()) + ")");
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
  cmd->add_option("--law", o.job.law, "lift law of the opening flank (and of the closing flank unless --close-law): " +
                                      synthesis::law_names())
      ->required();
  o.close_law_opt = cmd->add_option("--close-law", o.close_law, "lift law of the closing flank (default: --law)");
  cmd->add_option("--lift", o.job.lift_mm, "maximum lift [mm] (default 10)");
  o.duration = cmd->add_option("--duration", o.duration_deg,
                               "whole event at zero lift: opening ramp + rise + dwell + fall + closing ramp [cam deg]; "
                               "symmetric (default 130)");
  o.open = cmd->add_option("--open", o.open_deg,
                           "opening flank: start of the opening ramp to max lift [cam deg] (with --close, "
                           "instead of --duration)");
  o.close = cmd->add_option("--close", o.close_deg, "closing flank: max lift (end of dwell) to end of the closing ramp "
                                                    "[cam deg] (with --open)");
  cmd->add_option("--dwell", o.job.dwell_deg, "dwell at maximum lift [cam deg] (default 0)");
  cmd->add_option("--ramp-height", o.job.ramp_height_mm, "ramp height, lift at the end of each ramp [mm] (default 0: no ramp)");
  cmd->add_option("--ramp-length", o.job.ramp_length_deg, "ramp length of each ramp [cam deg] (default 0: no ramp)");
  o.close_ramp_height = cmd->add_option("--close-ramp-height", o.close_ramp_height_mm,
                                        "closing ramp height [mm] (default: --ramp-height)");
  o.close_ramp_length = cmd->add_option("--close-ramp-length", o.close_ramp_length_deg,
                                        "closing ramp length [cam deg] (default: --ramp-length)");
  cmd->add_option("--ramp-blend", o.job.ramp_blend,
                  "fraction of each ramp spent reaching the constant ramp velocity [fraction, 0 < f <= 1] (default 0.5)");
  cmd->add_option("--peak-at", o.job.peak_deg, "cam angle of maximum lift, the middle of the dwell [cam deg], "
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
  cmd->add_option("--step", o.job.step_deg, "table step [cam deg]; must divide 360 (default 0.25)");
  cmd->add_option("--basis", o.job.basis, "angle column of the table: cam (cam_deg) or crank (crank_deg = 2 x cam, "
                                      "derivatives per crank deg) (default cam)");
  cmd->add_option("--out", o.out, "output CSV: cam_deg (or crank_deg), lift_mm, vel_mm_per_deg, acc_mm_per_deg2, "
                                  "jerk_mm_per_deg3")
      ->required();
  add_report_options(*cmd, o.report, "<stem>.report.html beside the CSV",
                     "<stem>.<plot id>.svg or .png beside the CSV");
  cmd->callback([opts] { run_lift(*opts); });
}

}  // namespace camopt::cli
