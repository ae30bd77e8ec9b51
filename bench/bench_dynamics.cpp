// dynamics benchmark: one engine cycle (720 crank deg = 360 cam deg) of
// designs/cvvl_swing_cam.toml at 6000 rpm, control 0 (max lift), single-threaded.
//  - mode (a), rigid inverse dynamics, at 1 and 0.5 deg: run time, and the error of the
//    peak contact forces, peak cam torque and separation speeds against a 0.05 deg run
//    (the only approximation of mode (a) is the angle grid; each point is exact);
//  - mode (b), stiff contacts with CVODE, at the default tolerances (rtol 1e-6, path table
//    0.25 deg) and tighter ones: run time, max contact-force error over the cycle and error
//    of the peak forces against a tight run (rtol 1e-10, table 0.05 deg), relative to the
//    peak force;
//  - the flexible model: time per cycle (process CPU time, best of the repeats) against
//    tolerance (rtol 1e-3 .. 1e-8) with the error of the valve lift, of the contact forces, of
//    the peak contact force, of the event angles and of the seating velocity against rtol 1e-10 /
//    atol 1e-12, steps, RHS and Jacobian evaluations, events; one setting also without a CVODE
//    restart at each contact event. The time per cycle is the whole run (tabulation plus
//    `revolutions` revolutions) divided by the revolutions integrated.
//  - the flexible model against the spring's mass count: the direct-acting valve of the tests
//    (eccentric disc on a flat tappet, 40 N/mm / 250 N spring of 45 g) at 6000 rpm with
//    surge_masses 0 .. 500, default tolerances: CPU time per cycle, steps, ratio to 10 masses.
// usage: bench_dynamics [--repeat N] [--csv FILE] [--flexible-only | --rigid-only] [--single RTOL ATOL [--masses N]]
//                       [--design FILE]
//  --design FILE: another design instead of the CVVL (e.g. designs/cvvl_swing_cam_hla.toml:
//    the CVVL with its hydraulic lash adjuster, 4 more states and a dense Jacobian);
//  --rigid-only: only mode (a): 721 angles x 3 speeds on the direct-acting valves and the CVVL,
//    and the CVVL's steps against a 0.05 deg run (for a profiler: callgrind ... --rigid-only --repeat 1);
//  --flexible-only: only the flexible tables (the tolerance table's reference run included);
//    with --csv the file's other sections (modes a and b) are kept and the flexible rows replaced;
//  --single RTOL ATOL: one flexible run at these tolerances and its counters, no reference,
//    no timing repeat (for a profiler: valgrind --tool=callgrind ... --single 1e-6 1e-7);
//    with --masses N the direct-acting valve with N surge masses instead of the CVVL.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <time.h>  // clock_gettime (process CPU time)

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
Peaks peaks_of(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model) {
  const double w = dynamics::cam_speed_rad_per_s(kRpm, model.crank_per_cam);
  Peaks p;
  p.force.assign(static_cast<std::size_t>(s.connections), 0.0);
  for (std::size_t i = 0; i < s.points(); ++i) {
    for (int c = 0; c < s.connections; ++c) p.force[c] = std::max(p.force[c], s.force_at(i, c, w));
    p.torque = std::max(p.torque, std::abs(s.torque_at(i, w)));
  }
  for (int c = 0; c < s.connections; ++c) {
    dynamics::Separation sep;
    if (model.contacts[c].is_contact) check(dynamics::refined_separation_speed(mech, model, s, c, sep));
    p.separation.push_back(model.contacts[c].is_contact ? sep.engine_rpm : 0.0);
  }
  return p;
}

// best wall and best process CPU time of `repeat` runs of f [s] (taken separately: on a shared
// machine the CPU time is what the run itself costs)
struct Timing {
  double wall = 1e300, cpu = 1e300;
};
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
Timing best_of(const std::function<void()>& f, int repeat) {
  Timing t;
  for (int r = 0; r < std::max(repeat, 1); ++r) {
    const double c0 = cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    f();
    t.wall = std::min(t.wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
    t.cpu = std::min(t.cpu, cpu_seconds() - c0);
  }
  return t;
}

// the direct-acting valve of the dynamics tests (tests/dynamics/dynamics_test_support.hpp,
// valve_with_spring_mass): eccentric disc (R 18, e 4, centre at -90 deg) on a flat tappet of
// 70 g (steel line contact 8 mm wide, seat by default as the output node), valve spring
// 40 N/mm, 250 N preload, 45 g in `surge_masses` internal masses
DesignSpec direct_valve_with_spring_mass(int surge_masses) {
  constexpr double kDiscRadius = 18, kEccentricity = 4;
  const double h = kEccentricity * std::sin(-std::numbers::pi / 2) + kDiscRadius;  // face height at 0 deg
  DesignSpec d;
  d.name = "direct_valve";
  d.driver.node = "cam";
  d.output_node = "tappet";
  NodeSpec cam;
  cam.name = "cam";
  cam.kind = NodeKind::rotational;
  cam.pivot_mm = {0, 0};
  NodeSpec tappet;
  tappet.name = "tappet";
  tappet.kind = NodeKind::translational;
  tappet.origin_mm = {0, h};
  tappet.direction = {0, 1};
  tappet.mass_kg = 0.07;
  d.nodes = {cam, tappet};
  ProfileSpec disc;
  disc.name = "disc";
  disc.form = ProfileForm::eccentric;
  disc.disc_radius_mm = kDiscRadius;
  disc.eccentricity_mm = kEccentricity;
  d.profiles = {disc};
  ConnectionSpec k;
  k.name = "cam_tappet";
  k.kind = ConnectionKind::contact;
  k.surface_a.node = "cam";
  k.surface_a.shape = SurfaceShape::profile;
  k.surface_a.profile = "disc";
  k.surface_a.origin_mm = {0, 0};
  k.surface_a.orientation_deg = -90;
  k.surface_b.node = "tappet";
  k.surface_b.shape = SurfaceShape::line;
  k.surface_b.origin_mm = {0, h};
  k.surface_b.normal = {0, -1};
  k.material_a = k.material_b = "steel";
  k.width_mm = 8;
  d.connections = {k};
  MaterialSpec steel;
  steel.name = "steel";
  steel.youngs_modulus_GPa = 210;
  steel.poisson_ratio = 0.3;
  d.materials = {steel};
  SpringSpec s;
  s.name = "valve_spring";
  s.node = "tappet";
  s.rate_N_per_mm = 40;
  s.preload_N = 250;
  s.mass_kg = 0.045;
  s.surge_masses = surge_masses;
  d.springs = {s};
  return d;
}

// a run's events against the reference's: each event matched with the reference event of the
// same contact / seat and direction nearest in angle (no such event: unmatched); the seating
// velocity is that of the first seat closing of the reported revolution
struct EventErrors {
  double max_angle_deg = 0;  // largest |angle - matched reference angle|
  int unmatched = 0;         // events with no reference event of the same kind
  long count_difference = 0; // events - reference events
  double seating_speed_error = std::numeric_limits<double>::quiet_NaN();  // [m/s]
  double seating_speed = std::numeric_limits<double>::quiet_NaN();
};
const dynamics::FlexibleEvent* first_seat_closing(const dynamics::FlexibleResult& r) {
  const dynamics::FlexibleEvent* first = nullptr;
  for (const auto& e : r.events) {
    const bool seat = e.what.size() > 5 && e.what.compare(e.what.size() - 5, 5, " seat") == 0;
    if (seat && !e.opens && (!first || e.time_s < first->time_s)) first = &e;
  }
  return first;
}
EventErrors compare_events(const dynamics::FlexibleResult& r, const dynamics::FlexibleResult& ref) {
  EventErrors out;
  for (const auto& e : r.events) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& f : ref.events)
      if (f.what == e.what && f.opens == e.opens) nearest = std::min(nearest, std::abs(e.cam_deg - f.cam_deg));
    if (std::isfinite(nearest)) out.max_angle_deg = std::max(out.max_angle_deg, nearest);
    else ++out.unmatched;
  }
  out.count_difference = static_cast<long>(r.events.size()) - static_cast<long>(ref.events.size());
  const dynamics::FlexibleEvent *a = first_seat_closing(r), *b = first_seat_closing(ref);
  if (a) out.seating_speed = a->speed_m_per_s;
  if (a && b) out.seating_speed_error = std::abs(a->speed_m_per_s - b->speed_m_per_s);
  return out;
}

// the sections of dynamics.csv the flexible part writes (--flexible-only keeps the others)
bool flexible_row(const std::string& row) {
  const std::string mode = row.substr(0, row.find(','));
  return mode == "flexible" || mode == "flexible wall" || mode == "flexible cpu" || mode == "flexible masses" ||
         mode == "rigid vs flexible";
}

struct Options {
  int repeat = 5;
  std::string csv_path;
  bool flexible_only = false, single = false, rigid_only = false;
  double single_rtol = 0, single_atol = 0;
  int single_masses = -1;  // --masses N: the direct-acting valve instead of the CVVL
  std::string design = std::string(CAMOPT_SOURCE_DIR) + "/designs/cvvl_swing_cam.toml";
};

// the CVVL at control 0, compiled once, and the repeat count
struct Context {
  kin::Mechanism mech;
  dynamics::Model model;
  std::vector<double> controls;
  int repeat = 5;
};

constexpr int kRevolutions = 3;

dynamics::FlexibleOptions flex_options(double rtol, double atol, bool restart) {
  dynamics::FlexibleOptions opt;
  opt.revolutions = kRevolutions;
  opt.relative_tolerance = rtol;
  opt.absolute_tolerance = atol;
  opt.restart_at_events = restart;
  opt.periodic_tolerance = 0;  // always the same 3 revolutions (the reference too)
  return opt;
}

void run_flex(const Context& ctx, double rtol, double atol, bool restart, dynamics::FlexibleResult& r) {
  check(dynamics::run_flexible(ctx.mech, ctx.model, ctx.controls, kRpm, 0, 360, 1, flex_options(rtol, atol, restart), r));
}

// the direct-acting valve with n surge masses, compiled once per n
struct Valve {
  DesignSpec spec;
  kin::Mechanism mech;
  dynamics::Model model;
  explicit Valve(int n)
      : spec(direct_valve_with_spring_mass(n)), mech(kin::compile(spec)), model(dynamics::compile_dynamics(spec, mech)) {}
  void run(const dynamics::FlexibleOptions& opt, dynamics::FlexibleResult& r) const {
    check(dynamics::run_flexible(mech, model, {}, kRpm, 0, 360, 1, opt, r));
  }
};

// false on an unknown option (usage printed)
bool parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) o.repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) o.csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--flexible-only")) o.flexible_only = true;
    else if (!std::strcmp(argv[i], "--rigid-only")) o.rigid_only = true;
    else if (!std::strcmp(argv[i], "--single") && i + 2 < argc) {
      o.single = true;
      o.single_rtol = std::atof(argv[++i]);
      o.single_atol = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--masses") && i + 1 < argc) {
      o.single_masses = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--design") && i + 1 < argc) {
      o.design = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: bench_dynamics [--repeat N] [--csv FILE] [--flexible-only | --rigid-only] "
                   "[--single RTOL ATOL [--masses N]] [--design FILE]\n");
      return false;
    }
  }
  return true;
}

// mode (a): rigid inverse dynamics at three steps against a 0.05 deg reference
void rigid_rows(const Context& ctx, std::vector<std::string>& rows) {
  dynamics::RigidSweep fine;
  check(dynamics::rigid_sweep(ctx.mech, ctx.model, ctx.controls, 0, 360, 0.05, fine));
  const Peaks ref = peaks_of(ctx.mech, fine, ctx.model);
  std::printf("mode (a) rigid inverse dynamics, CVVL control 0, %g rpm, one cycle (360 cam deg)\n", kRpm);
  std::printf("%-10s %-12s %-22s %-16s %-22s\n", "step_deg", "ms/cycle", "peak force rel err", "torque rel err",
              "separation rpm err");
  for (const double step : {1.0, 0.5, 0.25}) {
    dynamics::RigidSweep s;
    const double t = seconds_of([&] { check(dynamics::rigid_sweep(ctx.mech, ctx.model, ctx.controls, 0, 360, step, s)); }, ctx.repeat);
    const Peaks p = peaks_of(ctx.mech, s, ctx.model);
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
}

// mode (a) as a user's script runs it: 721 cam angles (0.5 deg) at 3 engine speeds on the
// direct-acting valves and the CVVL (control 0): the sweep, the refined separation speed of
// every contact and each speed's contact forces and cam torque; the forces' error against
// a 0.05 deg run's at the common angles is round-off (each point is exact)
void rigid_speed_rows(int repeat, std::vector<std::string>& rows) {
  std::printf("\nmode (a), 721 cam angles (0.5 deg) x 3 speeds (3000, 5000, 7000 rpm): sweep, separation speeds, "
              "forces and torque at each speed; best of %d\n",
              repeat);
  std::printf("%-28s %-10s %-12s %-14s\n", "design", "ms", "ns/point", "separation rpm");
  for (const char* name : {"eccentric_flat_follower", "bucket_tappet", "cvvl_swing_cam"}) {
    const DesignSpec spec = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml");
    const kin::Mechanism mech = kin::compile(spec);
    const dynamics::Model model = dynamics::compile_dynamics(spec, mech);
    const std::vector<double> controls(mech.controls.size(), 0.0);
    dynamics::RigidSweep s;
    std::vector<double> force(721 * 3 * mech.connections.size()), torque(721 * 3);
    double separation = 0;
    const double t = seconds_of(
        [&] {
          check(dynamics::rigid_sweep(mech, model, controls, 0, 360, 0.5, s));
          for (int c = 0; c < s.connections; ++c)
            if (model.contacts[c].is_contact) {
              dynamics::Separation sep;
              check(dynamics::refined_separation_speed(mech, model, s, c, sep));
              separation = c == 0 ? sep.engine_rpm : std::min(separation, sep.engine_rpm);
            }
          std::size_t k = 0;
          for (const double rpm : {3000.0, 5000.0, 7000.0}) {
            const double w = dynamics::cam_speed_rad_per_s(rpm, model.crank_per_cam);
            for (std::size_t i = 0; i < s.points(); ++i) {
              torque[k * s.points() + i] = s.torque_at(i, w);
              for (int c = 0; c < s.connections; ++c)
                force[(k * s.points() + i) * s.connections + c] = s.force_at(i, c, w);
            }
            ++k;
          }
        },
        repeat);
    std::printf("%-28s %-10.3f %-12.0f %-14.6f\n", name, t * 1e3, t * 1e9 / (3.0 * 721), separation);
    rows.push_back(std::string("a 721x3,") + name + "," + num(t * 1e3) + ",separation rpm," + num(separation) + ",,");
  }
}

// mode (b): stiff contacts integrated by CVODE at several tolerances against a tight run
void compliant_rows(const Context& ctx, std::vector<std::string>& rows) {
  auto run_b = [&](double rtol, double atol, dynamics::CompliantResult& r, double table_step = 0.25) {
    dynamics::CompliantOptions opt;
    opt.relative_tolerance = rtol;
    opt.absolute_tolerance = atol;
    opt.table_step_deg = table_step;
    check(dynamics::run_compliant(ctx.mech, ctx.model, ctx.controls, kRpm, 0, 360, 1, opt, r));
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
    const double t = seconds_of([&] { run_b(rtol, atol, r, table); }, ctx.repeat);
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

// --single RTOL ATOL [--masses N]: one flexible run, its CPU time and counters
void single_run(const Context& ctx, const Options& o) {
  dynamics::FlexibleResult r;
  const double c0 = cpu_seconds();
  if (o.single_masses >= 0) Valve(o.single_masses).run(flex_options(o.single_rtol, o.single_atol, true), r);
  else run_flex(ctx, o.single_rtol, o.single_atol, true, r);
  const double cpu = (cpu_seconds() - c0) / kRevolutions;
  std::printf("flexible %s rtol %g atol %g: %.2f CPU ms/cycle, steps %ld, rhs %ld, jac %ld, events %zu\n",
              o.single_masses >= 0 ? ("direct-acting valve, " + std::to_string(o.single_masses) + " surge masses,").c_str()
                                 : "CVVL",
              o.single_rtol, o.single_atol, cpu * 1e3, r.steps, r.rhs_evaluations, r.jacobian_evaluations, r.events.size());
}

// the flexible model at several tolerances against a tight reference: errors and cost
void flexible_tolerance_rows(const Context& ctx, std::vector<std::string>& rows) {
  dynamics::FlexibleResult ref_flex;
  run_flex(ctx, 1e-10, 1e-12, true, ref_flex);
  const auto peak_force = [](const dynamics::FlexibleResult& r) {
    return *std::max_element(r.force.begin(), r.force.end());
  };
  const double ref_peak = peak_force(ref_flex);
  const dynamics::FlexibleEvent* ref_seat = first_seat_closing(ref_flex);
  std::printf("\nflexible model, %s control 0, %g rpm, the last of %d revolutions, output every 1 cam deg;"
              " reference rtol 1e-10 / atol 1e-12 (peak contact force %.1f N, %zu events, first seating %.4f m/s"
              " at %.2f deg, train mode %.0f Hz); times: process CPU, best of %d\n",
              ctx.mech.name.c_str(), kRpm, kRevolutions, ref_peak, ref_flex.events.size(), ref_seat ? ref_seat->speed_m_per_s : -1.0,
              ref_seat ? ref_seat->cam_deg : -1.0, ref_flex.train_frequency_hz, ctx.repeat);
  std::printf("%-30s %-9s %-9s %-12s %-12s %-12s %-12s %-9s %-12s %-7s %-7s %-5s %-6s\n", "rtol / atol_mm / restart",
              "cpu ms", "wall ms", "lift err mm", "force err/pk", "peak err/pk", "event deg", "events-ref",
              "seat v err", "steps", "rhs", "jac", "events");
  struct FlexSetting {
    double rtol, atol;
    bool restart;
  };
  for (const auto& [rtol, atol, restart] :
       std::vector<FlexSetting>{{1e-3, 1e-5, true}, {1e-4, 1e-6, true}, {1e-5, 1e-7, true}, {1e-6, 1e-7, true},
                                {1e-6, 1e-8, true}, {1e-7, 1e-9, true}, {1e-8, 1e-10, true}, {1e-6, 1e-7, false}}) {
    dynamics::FlexibleResult r;
    Timing t = best_of([&] { run_flex(ctx, rtol, atol, restart, r); }, ctx.repeat);
    t.cpu /= kRevolutions;
    t.wall /= kRevolutions;
    double lift_err = 0, force_err = 0;
    for (std::size_t i = 0; i < r.lift.size(); ++i) lift_err = std::max(lift_err, std::abs(r.lift[i] - ref_flex.lift[i]));
    for (std::size_t i = 0; i < r.force.size(); ++i)
      force_err = std::max(force_err, std::abs(r.force[i] - ref_flex.force[i]) / ref_peak);
    const double peak_err = std::abs(peak_force(r) - ref_peak) / ref_peak;
    const EventErrors ev = compare_events(r, ref_flex);
    const std::string setting = "rtol " + num(rtol) + " atol " + num(atol) + (restart ? " restart" : " no restart");
    const std::string event_deg = num(ev.max_angle_deg) + (ev.unmatched ? " (" + std::to_string(ev.unmatched) + " unm.)" : "");
    std::printf("%-30s %-9.2f %-9.2f %-12.3g %-12.3g %-12.3g %-12s %-9ld %-12.3g %-7ld %-7ld %-5ld %-6zu\n",
                setting.c_str(), t.cpu * 1e3, t.wall * 1e3, lift_err, force_err, peak_err, event_deg.c_str(),
                ev.count_difference, ev.seating_speed_error, r.steps, r.rhs_evaluations, r.jacobian_evaluations,
                r.events.size());
    const std::string counters = "," + std::to_string(r.steps) + "," + std::to_string(r.rhs_evaluations);
    const std::string head = "flexible," + setting + "," + num(t.cpu * 1e3) + ",";
    rows.push_back("flexible wall," + setting + "," + num(t.wall * 1e3) + ",,,,");
    rows.push_back(head + "max valve lift err mm," + num(lift_err) + counters);
    rows.push_back(head + "max contact force err / peak," + num(force_err) + counters);
    rows.push_back(head + "peak contact force err / peak," + num(peak_err) + counters);
    rows.push_back(head + "max event angle err deg," + num(ev.max_angle_deg) + counters);
    rows.push_back(head + "unmatched events," + std::to_string(ev.unmatched) + counters);
    rows.push_back(head + "event count - reference," + std::to_string(ev.count_difference) + counters);
    rows.push_back(head + "seating velocity err m/s," + num(ev.seating_speed_error) + counters);
    rows.push_back(head + "jacobian evaluations," + std::to_string(r.jacobian_evaluations) + counters);
    rows.push_back(head + "events," + std::to_string(r.events.size()) + counters);
  }
}

// rigid against flexible: the CPU cost of one cycle
void rigid_vs_flexible_rows(const Context& ctx, std::vector<std::string>& rows) {
  dynamics::RigidSweep s;
  const Timing t_rigid = best_of([&] { check(dynamics::rigid_sweep(ctx.mech, ctx.model, ctx.controls, 0, 360, 1, s)); }, ctx.repeat);
  dynamics::FlexibleResult r;
  const double t_flex = best_of([&] { run_flex(ctx, 1e-6, 1e-7, true, r); }, ctx.repeat).cpu / kRevolutions;
  std::printf("\nrigid (a) 1 deg: %.3f CPU ms/cycle; flexible rtol 1e-6: %.3f CPU ms/cycle (x %.0f)\n",
              t_rigid.cpu * 1e3, t_flex * 1e3, t_flex / t_rigid.cpu);
  rows.push_back("rigid vs flexible,rigid step 1 deg," + num(t_rigid.cpu * 1e3) + ",,,,");
  rows.push_back("rigid vs flexible,flexible rtol 1e-6," + num(t_flex * 1e3) + ",,," + std::to_string(r.steps) + "," +
                 std::to_string(r.rhs_evaluations));
}

// the flexible model's time per cycle against the valve spring's surge mass count
void mass_rows(const Context& ctx, std::vector<std::string>& rows) {
  std::printf("\nflexible model, direct-acting valve (tests' valve_with_spring_mass), %g rpm, %d revolutions, "
              "rtol 1e-6 / atol 1e-7; process CPU, best of %d\n",
              kRpm, kRevolutions, ctx.repeat);
  std::printf("%-14s %-8s %-12s %-10s %-8s %-8s %-6s %-7s %-14s\n", "surge_masses", "states", "cpu ms/cyc",
              "wall ms", "steps", "rhs", "jac", "events", "ratio to N=10");
  const dynamics::FlexibleOptions opt = flex_options(1e-6, 1e-7, true);
  struct MassRow {
    int n;
    Timing t;
    dynamics::FlexibleResult r;
  };
  std::vector<MassRow> measured;
  for (const int n : {0, 10, 50, 100, 200, 500}) {
    const Valve valve(n);
    MassRow row{n, {}, {}};
    row.t = best_of([&] { valve.run(opt, row.r); }, ctx.repeat);
    row.t.cpu /= kRevolutions;
    row.t.wall /= kRevolutions;
    measured.push_back(std::move(row));
  }
  double cpu10 = 0;
  for (const auto& m : measured)
    if (m.n == 10) cpu10 = m.t.cpu;
  for (const auto& m : measured) {
    const double ratio = m.t.cpu / cpu10;
    std::printf("%-14d %-8d %-12.3f %-10.3f %-8ld %-8ld %-6ld %-7zu %-14.2f\n", m.n, 2 * m.r.layout.size(),
                m.t.cpu * 1e3, m.t.wall * 1e3, m.r.steps, m.r.rhs_evaluations, m.r.jacobian_evaluations,
                m.r.events.size(), ratio);
    const std::string setting = "direct valve surge_masses " + std::to_string(m.n);
    rows.push_back("flexible masses," + setting + "," + num(m.t.cpu * 1e3) + ",cpu ratio to 10 masses," + num(ratio) +
                   "," + std::to_string(m.r.steps) + "," + std::to_string(m.r.rhs_evaluations));
    rows.push_back("flexible masses," + setting + "," + num(m.t.cpu * 1e3) + ",jacobian evaluations," +
                   std::to_string(m.r.jacobian_evaluations) + "," + std::to_string(m.r.steps) + "," +
                   std::to_string(m.r.rhs_evaluations));
  }
}

// the rows to --csv; --flexible-only keeps the file's other sections before the new flexible rows
void write_rows(const Options& o, std::vector<std::string> rows) {
  if (o.flexible_only) {  // keep the file's other sections, in their order, before the new flexible rows
    std::ifstream in(o.csv_path);
    std::vector<std::string> kept;
    std::string line;
    for (bool header = true; std::getline(in, line); header = false)
      if (!header && !line.empty() && !flexible_row(line)) kept.push_back(line);
    rows.insert(rows.begin() + 1, kept.begin(), kept.end());
  }
  std::ofstream f(o.csv_path);
  for (const auto& row : rows) f << row << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  camopt::keep_freed_memory();  // as the camopt program does
  Options o;
  if (!parse_options(argc, argv, o)) return 2;
  const DesignSpec spec = io::load_design(o.design);
  const kin::Mechanism mech = kin::compile(spec);
  const Context c{mech, dynamics::compile_dynamics(spec, mech), std::vector<double>(mech.controls.size(), 0.0), o.repeat};
  if (o.single) return single_run(c, o), 0;
  std::vector<std::string> rows{"mode,setting,ms_per_cycle,error_metric,error,steps,rhs_evaluations"};
  if (o.rigid_only) {
    rigid_speed_rows(o.repeat, rows);
    rigid_rows(c, rows);
    if (!o.csv_path.empty()) write_rows(o, std::move(rows));
    return 0;
  }
  if (!o.flexible_only) {
    rigid_speed_rows(o.repeat, rows);
    rigid_rows(c, rows);
    compliant_rows(c, rows);
  }
  flexible_tolerance_rows(c, rows);
  rigid_vs_flexible_rows(c, rows);
  mass_rows(c, rows);
  if (!o.csv_path.empty()) write_rows(o, std::move(rows));
  return 0;
}
