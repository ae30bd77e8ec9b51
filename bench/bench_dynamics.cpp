// dynamics benchmark: one engine cycle (720 crank deg = 360 cam deg) of
// designs/cvvl_swing_cam.toml at 6000 rpm, control 0 (max lift), single-threaded.
//  - mode (a), rigid inverse dynamics, at 1 and 0.5 deg: run time, and the error of the
//    peak contact forces, peak cam torque and separation speeds against a 0.05 deg run
//    (the only approximation of mode (a) is the angle grid; each point is exact);
//  - mode (b), stiff contacts with CVODE, at the default tolerances (rtol 1e-6, path table
//    0.25 deg) and tighter ones: run time, max contact-force error over the cycle and error
//    of the peak forces against a tight run (rtol 1e-10, table 0.05 deg), relative to the
//    peak force;
//  - the flexible model: time per cycle against tolerance (rtol 1e-3 .. 1e-8) with
//    the error of the valve lift, of the contact forces and of the peak contact force against
//    rtol 1e-10 / atol 1e-12, steps, RHS and Jacobian evaluations; one setting also without
//    a CVODE restart at each contact event.
//    The time per cycle is the whole run (tabulation plus `revolutions` revolutions) divided
//    by the revolutions integrated.
// usage: bench_dynamics [--repeat N] [--csv FILE] [--flexible-only] [--single RTOL ATOL]
//  --flexible-only: only the flexible table (its reference run included);
//  --single RTOL ATOL: one flexible run at these tolerances and its counters, no reference,
//    no timing repeat (for a profiler: valgrind --tool=callgrind ... --single 1e-6 1e-7).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "camopt/dynamics/compliant.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/io/design_file.hpp"

using namespace camopt;
using camopt::bench::num;
using camopt::bench::seconds_of;

namespace {

constexpr double kRpm = 6000.0;

void check(const Status& st) {
  if (!st.ok()) {
    std::fprintf(stderr, "failed: %s\n", st.str().c_str());
    std::exit(1);
  }
}

// peaks of a mode (a) sweep at the benchmark speed
struct Peaks {
  std::vector<double> force, separation;
  double torque = 0;
};
Peaks peaks_of(const dynamics::RigidSweep& s, const dynamics::Model& model) {
  const double w = dynamics::cam_speed_rad_per_s(kRpm, model.crank_per_cam);
  Peaks p;
  p.force.assign(static_cast<std::size_t>(s.connections), 0.0);
  for (std::size_t i = 0; i < s.points(); ++i) {
    for (int c = 0; c < s.connections; ++c) p.force[c] = std::max(p.force[c], s.force_at(i, c, w));
    p.torque = std::max(p.torque, std::abs(s.torque_at(i, w)));
  }
  for (int c = 0; c < s.connections; ++c)
    p.separation.push_back(model.contacts[c].is_contact ? dynamics::separation_speed(s, model, c).engine_rpm : 0.0);
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  camopt::keep_freed_memory();  // as the camopt program does
  int repeat = 5;
  std::string csv_path;
  bool flexible_only = false, single = false;
  double single_rtol = 0, single_atol = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--flexible-only")) flexible_only = true;
    else if (!std::strcmp(argv[i], "--single") && i + 2 < argc) {
      single = true;
      single_rtol = std::atof(argv[++i]);
      single_atol = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: bench_dynamics [--repeat N] [--csv FILE] [--flexible-only] [--single RTOL ATOL]\n");
      return 2;
    }
  }
  const DesignSpec spec = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml");
  const kin::Mechanism mech = kin::compile(spec);
  const dynamics::Model model = dynamics::compile_dynamics(mech);
  const std::vector<double> controls{0.0};
  std::vector<std::string> rows{"mode,setting,ms_per_cycle,error_metric,error,steps,rhs_evaluations"};

  if (!flexible_only && !single) {  // modes (a) and (b)
    // ---- mode (a) ----
    dynamics::RigidSweep fine;
    check(dynamics::rigid_sweep(mech, model, controls, 0, 360, 0.05, fine));
    const Peaks ref = peaks_of(fine, model);
    std::printf("mode (a) rigid inverse dynamics, CVVL control 0, %g rpm, one cycle (360 cam deg)\n", kRpm);
    std::printf("%-10s %-12s %-22s %-16s %-22s\n", "step_deg", "ms/cycle", "peak force rel err", "torque rel err",
                "separation rpm err");
    for (const double step : {1.0, 0.5, 0.25}) {
      dynamics::RigidSweep s;
      const double t = seconds_of([&] { check(dynamics::rigid_sweep(mech, model, controls, 0, 360, step, s)); }, repeat);
      const Peaks p = peaks_of(s, model);
      double force_err = 0, sep_err = 0;
      for (std::size_t c = 0; c < p.force.size(); ++c) {
        force_err = std::max(force_err, std::abs(p.force[c] - ref.force[c]) / ref.force[c]);
        if (std::isfinite(ref.separation[c])) sep_err = std::max(sep_err, std::abs(p.separation[c] - ref.separation[c]));
      }
      const double torque_err = std::abs(p.torque - ref.torque) / ref.torque;
      std::printf("%-10g %-12.3f %-22.3g %-16.3g %-22.3g\n", step, t * 1e3, force_err, torque_err, sep_err);
      rows.push_back("a,step " + num(step) + " deg," + num(t * 1e3) + ",peak contact force rel," + num(force_err) + ",,");
      rows.push_back("a,step " + num(step) + " deg," + num(t * 1e3) + ",peak cam torque rel," + num(torque_err) + ",,");
      rows.push_back("a,step " + num(step) + " deg," + num(t * 1e3) + ",separation rpm abs," + num(sep_err) + ",,");
    }

    // ---- mode (b) ----
    auto run_b = [&](double rtol, double atol, dynamics::CompliantResult& r, double table_step = 0.25) {
      dynamics::CompliantOptions opt;
      opt.relative_tolerance = rtol;
      opt.absolute_tolerance = atol;
      opt.table_step_deg = table_step;
      check(dynamics::run_compliant(mech, model, controls, kRpm, 0, 360, 1, opt, r));
    };
    dynamics::CompliantResult tight;
    run_b(1e-10, 1e-12, tight, 0.05);
    double peak = 0;
    for (double f : tight.force) peak = std::max(peak, std::abs(f));
    std::printf("\nmode (b) stiff contacts (CVODE BDF), same cycle, output every 1 cam deg; %zu events in the tight run\n",
                tight.events.size());
    std::printf("%-28s %-12s %-24s %-22s %-8s %-8s %-8s\n", "rtol / atol_mm / table_deg", "ms/cycle", "max force err / peak",
                "peak force err / peak", "steps", "rhs", "events");
    struct Setting {
      double rtol, atol, table;
    };
    for (const auto& [rtol, atol, table] :
         std::vector<Setting>{{1e-6, 1e-8, 0.25}, {1e-7, 1e-9, 0.25}, {1e-8, 1e-10, 0.25}, {1e-8, 1e-10, 0.1}, {1e-8, 1e-10, 0.05}}) {
      dynamics::CompliantResult r;
      const double t = seconds_of([&] { run_b(rtol, atol, r, table); }, repeat);
      double err = 0, peak_err = 0;
      for (std::size_t i = 0; i < r.force.size(); ++i) err = std::max(err, std::abs(r.force[i] - tight.force[i]));
      for (int c = 0; c < r.connections; ++c) {
        double pr = 0, pt = 0;
        for (std::size_t i = 0; i < r.cam_deg.size(); ++i) {
          pr = std::max(pr, r.force[i * r.connections + c]);
          pt = std::max(pt, tight.force[i * r.connections + c]);
        }
        peak_err = std::max(peak_err, std::abs(pr - pt) / peak);
      }
      std::printf("%-28s %-12.3f %-24.3g %-22.3g %-8ld %-8ld %-8zu\n",
                  (num(rtol) + " / " + num(atol) + " / " + num(table)).c_str(), t * 1e3,
                  err / peak, peak_err, r.steps, r.rhs_evaluations, r.events.size());
      rows.push_back("b,rtol " + num(rtol) + " atol " + num(atol) + " table " + num(table) + " deg," + num(t * 1e3) + ",max contact force err / peak," +
                     num(err / peak) + "," + std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations));
      rows.push_back("b,rtol " + num(rtol) + " atol " + num(atol) + " table " + num(table) + " deg," + num(t * 1e3) + ",peak contact force err / peak," +
                     num(peak_err) + "," + std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations));
    }
  }
  // ---- flexible ----
  constexpr int kRevolutions = 3;
  auto run_flex = [&](double rtol, double atol, bool restart, dynamics::FlexibleResult& r) {
    dynamics::FlexibleOptions opt;
    opt.revolutions = kRevolutions;
    opt.relative_tolerance = rtol;
    opt.absolute_tolerance = atol;
    opt.restart_at_events = restart;
    opt.periodic_tolerance = 0;  // always the same 3 revolutions (the reference too)
    check(dynamics::run_flexible(mech, model, controls, kRpm, 0, 360, 1, opt, r));
  };
  if (single) {
    dynamics::FlexibleResult r;
    const std::clock_t c0 = std::clock();
    run_flex(single_rtol, single_atol, true, r);
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / kRevolutions;
    std::printf("flexible rtol %g atol %g: %.2f CPU ms/cycle, steps %ld, rhs %ld, jac %ld, events %zu\n", single_rtol,
                single_atol, cpu * 1e3, r.steps, r.rhs_evaluations, r.jacobian_evaluations, r.events.size());
    return 0;
  }
  dynamics::FlexibleResult ref_flex;
  run_flex(1e-10, 1e-12, true, ref_flex);
  const auto peak_force = [](const dynamics::FlexibleResult& r) {
    return *std::max_element(r.force.begin(), r.force.end());
  };
  const double ref_peak = peak_force(ref_flex);
  std::printf("\nflexible model, same cycle after %d revolutions (the last reported), output every 1 cam deg;"
              " reference rtol 1e-10 / atol 1e-12 (peak contact force %.1f N, %zu events, train mode %.0f Hz)\n",
              kRevolutions, ref_peak, ref_flex.events.size(), ref_flex.train_frequency_hz);
  std::printf("%-30s %-10s %-10s %-16s %-20s %-20s %-8s %-8s %-6s %-7s\n", "rtol / atol_mm / restart", "ms/cycle",
              "cpu ms", "max lift err mm", "max force err/peak", "peak force err/peak", "steps", "rhs", "jac", "events");
  struct FlexSetting {
    double rtol, atol;
    bool restart;
  };
  for (const auto& [rtol, atol, restart] :
       std::vector<FlexSetting>{{1e-3, 1e-5, true}, {1e-4, 1e-6, true}, {1e-5, 1e-7, true}, {1e-6, 1e-7, true},
                                {1e-6, 1e-8, true}, {1e-7, 1e-9, true}, {1e-8, 1e-10, true}, {1e-6, 1e-7, false}}) {
    dynamics::FlexibleResult r;
    // wall and process CPU time (the machine is shared: CPU time is what the run itself costs)
    double cpu = 1e300;
    const double t = seconds_of([&] {
                       const std::clock_t c0 = std::clock();
                       run_flex(rtol, atol, restart, r);
                       cpu = std::min(cpu, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
                     },
                                repeat) /
                     kRevolutions;
    cpu /= kRevolutions;
    double lift_err = 0, force_err = 0;
    for (std::size_t i = 0; i < r.lift.size(); ++i) lift_err = std::max(lift_err, std::abs(r.lift[i] - ref_flex.lift[i]));
    for (std::size_t i = 0; i < r.force.size(); ++i)
      force_err = std::max(force_err, std::abs(r.force[i] - ref_flex.force[i]) / ref_peak);
    const double peak_err = std::abs(peak_force(r) - ref_peak) / ref_peak;
    const std::string setting = "rtol " + num(rtol) + " atol " + num(atol) + (restart ? " restart" : " no restart");
    std::printf("%-30s %-10.2f %-10.2f %-16.3g %-20.3g %-20.3g %-8ld %-8ld %-6ld %-7zu\n", setting.c_str(), t * 1e3,
                cpu * 1e3, lift_err,
                force_err, peak_err, r.steps, r.rhs_evaluations, r.jacobian_evaluations, r.events.size());
    rows.push_back("flexible cpu," + setting + "," + num(cpu * 1e3) + ",,,,");
    rows.push_back("flexible," + setting + "," + num(t * 1e3) + ",max valve lift err mm," + num(lift_err) + "," +
                   std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations));
    rows.push_back("flexible," + setting + "," + num(t * 1e3) + ",max contact force err / peak," + num(force_err) +
                   "," + std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations));
    rows.push_back("flexible," + setting + "," + num(t * 1e3) + ",peak contact force err / peak," + num(peak_err) +
                   "," + std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations));
  }
  {  // rigid vs flexible cost of one cycle
    dynamics::RigidSweep s;
    const double t_rigid = seconds_of([&] { check(dynamics::rigid_sweep(mech, model, controls, 0, 360, 1, s)); }, repeat);
    dynamics::FlexibleResult r;
    const double t_flex = seconds_of([&] { run_flex(1e-6, 1e-7, true, r); }, repeat) / kRevolutions;
    std::printf("\nrigid (a) 1 deg: %.3f ms/cycle; flexible rtol 1e-6: %.3f ms/cycle (x %.0f)\n", t_rigid * 1e3,
                t_flex * 1e3, t_flex / t_rigid);
    rows.push_back("rigid vs flexible,rigid step 1 deg," + num(t_rigid * 1e3) + ",,,,");
    rows.push_back("rigid vs flexible,flexible rtol 1e-6," + num(t_flex * 1e3) + ",,," + std::to_string(r.steps) + "," +
                   std::to_string(r.rhs_evaluations));
  }
  if (!csv_path.empty()) {
    std::ofstream f(csv_path);
    for (const auto& row : rows) f << row << "\n";
  }
  return 0;
}
