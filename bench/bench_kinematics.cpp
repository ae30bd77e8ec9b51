// kinematics benchmark: run time per point against error.
//  - accuracy: an eccentric disc + offset roller follower against its closed form
//    (tests/oracles), max error of lift, velocity, acceleration, jerk relative to peak;
//  - every bundled design: ns per point for lift only, lift + derivatives, and all outputs
//    (derivatives + contact quantities), single-threaded, best of --repeat runs; and a
//    derivative self-check (jets against 6th-order central differences of the positions);
//  - the CVVL 17-position sweep at 0.5 deg, single-threaded and with --threads.
// usage: bench_kinematics [--repeat N] [--threads N] [--csv FILE] [--only DESIGN]
//        bench_kinematics --sweep lift|deriv|all [--only DESIGN] [--positions N] [--stop DEG] [--repeat N]
//   (--sweep: only one sweep of DESIGN, default cvvl_swing_cam, at 0.5 deg over N control
//    positions, default 17, from 0 to DEG, default 360, single-threaded: for callgrind)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "camopt/core/units.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "oracles/oracles.hpp"

using namespace camopt;
using camopt::bench::num;
using camopt::bench::seconds_of;

namespace {

constexpr double deg = camopt::rad_per_deg;

kin::SweepResult run(const kin::Mechanism& m, int order, bool contacts, double step, const std::vector<double>& controls,
                     int threads) {
  kin::SweepSpec s;
  s.start = m.driver.start;
  s.stop = m.driver.stop;
  s.step = step;
  s.request = {order, contacts};
  s.threads = threads;
  for (double c : controls) {
    std::vector<double> pos;
    for (const auto& ctl : m.controls) pos.push_back(ctl.default_value);
    if (!pos.empty()) pos[0] = c;
    s.control_positions.push_back(pos);
  }
  auto r = kin::sweep(m, s);
  for (const auto& p : r.positions)
    if (!p.status.ok()) {
      std::fprintf(stderr, "bench: %s: %s\n", m.name.c_str(), p.status.str().c_str());
      std::exit(1);
    }
  return r;
}

// max |jet derivative - 6th-order central difference of positions| / peak, orders 1 and 2
std::pair<double, double> derivative_self_check(const kin::Mechanism& m, const std::vector<double>& controls) {
  kin::Workspace ws(m);
  std::vector<double> pos;
  for (const auto& ctl : m.controls) pos.push_back(ctl.default_value);
  if (!pos.empty()) pos[0] = controls.front();
  ws.set_controls(pos);
  const int out = m.nodes[m.output_node].first_variable;
  const double h = 1e-3;  // [rad]
  double e1 = 0, e2 = 0, p1 = 0, p2 = 0;
  kin::Workspace fd(m);
  fd.set_controls(pos);
  for (int i = 0; i < 360; i += 3) {
    const double th = i * deg;
    if (!kin::solve(m, ws, th, {3, false}).ok()) continue;
    // skip stencils that straddle a lash opening or closing (the lift is only C0 there)
    auto any_open = [](const kin::Workspace& w) {
      for (bool o : w.lash_open())
        if (o) return true;
      return false;
    };
    double x[7];
    bool ok = !any_open(ws);
    for (int k = -3; k <= 3; ++k) {
      ok &= kin::solve(m, fd, th + k * h, {0, false}).ok();
      ok &= !any_open(fd);
      x[k + 3] = fd.values()[out];
    }
    if (!ok) continue;
    const double d1 = (-x[0] + 9 * x[1] - 45 * x[2] + 45 * x[4] - 9 * x[5] + x[6]) / (60 * h);
    const double d2 = (2 * x[0] - 27 * x[1] + 270 * x[2] - 490 * x[3] + 270 * x[4] - 27 * x[5] + 2 * x[6]) / (180 * h * h);
    const auto& j = ws.vars[out];
    e1 = std::max(e1, std::abs(j.derivative(1) - d1));
    e2 = std::max(e2, std::abs(j.derivative(2) - d2));
    p1 = std::max(p1, std::abs(j.derivative(1)));
    p2 = std::max(p2, std::abs(j.derivative(2)));
  }
  return {e1 / std::max(p1, 1e-300), e2 / std::max(p2, 1e-300)};
}

}  // namespace

struct Options {
  int repeat = 5, threads = 2;
  std::string csv_path, only;  // only: run just this bundled design (no accuracy case)
  std::string sweep_mode;      // --sweep: one sweep only
  int positions = 17;
  double stop = 360.0;
};

// false on an unknown option (usage printed)
bool parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) o.repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) o.threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) o.csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) o.only = argv[++i];
    else if (!std::strcmp(argv[i], "--sweep") && i + 1 < argc) o.sweep_mode = argv[++i];
    else if (!std::strcmp(argv[i], "--positions") && i + 1 < argc) o.positions = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--stop") && i + 1 < argc) o.stop = std::atof(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: bench_kinematics [--repeat N] [--threads N] [--csv FILE] [--only DESIGN]\n"
                   "       bench_kinematics --sweep lift|deriv|all [--only DESIGN] [--positions N] [--stop DEG]\n");
      return false;
    }
  }
  return true;
}

// --sweep: one sweep of one design over its control range, timed
void one_sweep(const Options& o) {
  const std::string design = o.only.empty() ? "cvvl_swing_cam" : o.only;
  const auto m = kin::compile(io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + design + ".toml"));
  std::vector<double> controls;
  const bool one = o.positions <= 1 || m.controls.empty();
  for (int i = 0; i < (one ? 1 : o.positions); ++i)
    controls.push_back(m.controls.empty() || one ? (m.controls.empty() ? 0.0 : m.controls[0].default_value)
                                                 : m.controls[0].min + (m.controls[0].max - m.controls[0].min) * i /
                                                                           (o.positions - 1));
  kin::SweepSpec s;
  s.start = 0.0;
  s.stop = o.stop;
  s.step = 0.5;
  s.request = {o.sweep_mode == "lift" ? 0 : 3, o.sweep_mode == "all"};
  for (double c : controls) {
    std::vector<double> pos;
    for (const auto& ctl : m.controls) pos.push_back(ctl.default_value);
    if (!pos.empty()) pos[0] = c;
    s.control_positions.push_back(pos);
  }
  long solved = 0, rejected = 0;
  const double t = seconds_of(
      [&] {
        const auto r = kin::sweep(m, s);
        solved = rejected = 0;
        for (const auto& p : r.positions) {
          if (!p.status.ok()) {
            std::fprintf(stderr, "bench: %s: %s\n", design.c_str(), p.status.str().c_str());
            std::exit(1);
          }
          solved += p.stats.points;
          rejected += p.stats.rejected_steps;
        }
      },
      o.repeat);
  const double requested = static_cast<double>(controls.size()) * (std::lround(o.stop / 0.5) + 1);
  std::printf("%s %s, %zu positions x 0..%g deg at 0.5 deg: best of %d %.3f ms, %.0f ns per requested point "
              "(%ld solved, %ld steps halved)\n",
              design.c_str(), o.sweep_mode.c_str(), controls.size(), o.stop, o.repeat, t * 1e3, t / requested * 1e9, solved,
              rejected);
}

// accuracy against a closed form: an eccentric disc on an offset translating roller
void closed_form_rows(const Options& options, std::vector<std::string>& rows) {
  oracles::EccentricOffsetRoller o;
  o.disc_radius = 20;
  o.eccentricity = 4;
  o.phase = 0;
  o.roller_radius = 8;
  o.offset = 3;
  DesignSpec d;
  d.name = "eccentric_offset_roller(code)";
  d.output_node = "follower";
  d.driver.node = "cam";
  NodeSpec cam;
  cam.name = "cam";
  cam.kind = NodeKind::rotational;
  const double y0 = o.centre_height(0)[0];
  NodeSpec fol;
  fol.name = "follower";
  fol.kind = NodeKind::translational;
  fol.origin_mm = {3.0, y0};
  d.nodes = {cam, fol};
  ProfileSpec disc;
  disc.name = "disc";
  disc.form = ProfileForm::eccentric;
  disc.disc_radius_mm = 20;
  disc.eccentricity_mm = 4;
  d.profiles = {disc};
  ConnectionSpec c;
  c.name = "cam_roller";
  c.kind = ConnectionKind::contact;
  c.surface_a.node = "cam";
  c.surface_a.shape = SurfaceShape::profile;
  c.surface_a.profile = "disc";
  c.surface_b.node = "follower";
  c.surface_b.shape = SurfaceShape::circle;
  c.surface_b.origin_mm = {3.0, y0};
  c.surface_b.radius_mm = 8;
  c.surface_b.roller = true;
  d.connections = {c};
  const auto m = kin::compile(d);
  for (double step : {1.0, 0.5, 0.1}) {
    kin::SweepResult r;
    const double t = seconds_of([&] { r = run(m, 3, false, step, {0.0}, 1); }, options.repeat);
    double err[4] = {0, 0, 0, 0}, peak[4] = {0, 0, 0, 0};
    const auto& p = r.positions[0];
    for (std::size_t i = 0; i < r.driver.size(); ++i) {
      const auto ref = o.lift(r.driver[i] * deg);
      for (int k = 0; k < 4; ++k) {
        const double ours = p.value(i, 1, k) / std::pow(deg, k);
        err[k] = std::max(err[k], std::abs(ours - ref[k]));
        peak[k] = std::max(peak[k], std::abs(ref[k]));
      }
    }
    std::printf("%-34s step %.1f deg: %6.0f ns/point  error/peak: lift %.1e vel %.1e acc %.1e jerk %.1e\n",
                d.name.c_str(), step, t / r.driver.size() * 1e9, err[0] / peak[0], err[1] / peak[1],
                err[2] / peak[2], err[3] / peak[3]);
    const char* names[4] = {"lift", "vel", "acc", "jerk"};
    for (int k = 0; k < 4; ++k)
      rows.push_back(d.name + ",1," + std::to_string(r.driver.size()) + ",derivatives," +
                     num(t / r.driver.size() * 1e9) + "," + num(t * 1e3) + ",closed_form_" + names[k] + "," +
                     num(err[k] / peak[k]));
  }
}

// every bundled design at 0.5 deg: lift only, derivatives, all outputs, and threads
void bundled_rows(const Options& o, std::vector<std::string>& rows) {
  struct Case {
    const char* file;
    std::vector<double> controls;
  };
  const std::vector<Case> cases = {
      {"eccentric_flat_follower", {0}},  {"eccentric_offset_roller", {0}}, {"eccentric_oscillating_roller", {0}},
      {"four_bar", {0}},                 {"offset_slider_crank", {0}},     {"bucket_tappet", {0}},
      {"roller_finger_follower", {0}},   {"rocker_arm", {0}},              {"cvvl_swing_cam", {}},
      {"vvld", {}},                      {"valvetronic", {}},
  };
  std::printf("\n%-30s %5s %6s %12s %12s %12s %10s %12s %12s\n", "design", "pos", "points", "lift ns/pt",
              "deriv ns/pt", "all ns/pt", "all ms", "fd vel err", "fd acc err");
  for (const auto& cs : cases) {
    if (!o.only.empty() && o.only != cs.file) continue;
    const std::string path = std::string(CAMOPT_SOURCE_DIR) + "/designs/" + cs.file + ".toml";
    if (!std::ifstream(path)) continue;
    const auto m = kin::compile(io::load_design(path));
    std::vector<double> controls = cs.controls;
    if (controls.empty()) {
      // the full control range in the paper's resolution: 17 positions (CVVL), 11 (VVLD, Valvetronic)
      const int n = std::string(cs.file) == "cvvl_swing_cam" ? 17 : 11;
      const auto& c0 = m.controls.at(0);
      for (int i = 0; i < n; ++i) controls.push_back(c0.min + (c0.max - c0.min) * i / (n - 1));
    }
    const double step = 0.5;
    std::size_t points = 0;
    double t_mode[3];
    const int orders[3] = {0, 3, 3};
    const bool contacts[3] = {false, false, true};
    for (int mode = 0; mode < 3; ++mode)
      t_mode[mode] = seconds_of([&] { points = run(m, orders[mode], contacts[mode], step, controls, 1).driver.size(); }, o.repeat);
    const auto [fd1, fd2] = derivative_self_check(m, controls);
    const double n = static_cast<double>(points * controls.size());
    std::printf("%-30s %5zu %6zu %12.0f %12.0f %12.0f %10.2f %12.1e %12.1e\n", cs.file, controls.size(), points,
                t_mode[0] / n * 1e9, t_mode[1] / n * 1e9, t_mode[2] / n * 1e9, t_mode[2] * 1e3, fd1, fd2);
    const char* modes[3] = {"lift", "derivatives", "all"};
    for (int mode = 0; mode < 3; ++mode)
      rows.push_back(std::string(cs.file) + "," + std::to_string(controls.size()) + "," + std::to_string(points) + "," +
                     modes[mode] + "," + num(t_mode[mode] / n * 1e9) + "," + num(t_mode[mode] * 1e3) +
                     ",fd_vel_acc," + num(std::max(fd1, fd2)));
    if (controls.size() > 1 && o.threads > 1) {
      const double t = seconds_of([&] { run(m, 3, true, step, controls, o.threads); }, o.repeat);
      std::printf("%-30s all outputs with %d threads: %.2f ms\n", cs.file, o.threads, t * 1e3);
      rows.push_back(std::string(cs.file) + "," + std::to_string(controls.size()) + "," + std::to_string(points) +
                     ",all_" + std::to_string(o.threads) + "_threads," + num(t / n * 1e9) + "," + num(t * 1e3) +
                     ",,");
    }
  }
}

int main(int argc, char** argv) {
  camopt::keep_freed_memory();  // as the camopt program does
  Options o;
  if (!parse_options(argc, argv, o)) return 2;
  if (!o.sweep_mode.empty()) return one_sweep(o), 0;
  std::vector<std::string> rows;
  rows.push_back("design,positions,points,mode,ns_per_point,total_ms,error_kind,error_rel_peak");
  if (o.only.empty()) closed_form_rows(o, rows);
  bundled_rows(o, rows);
  if (!o.csv_path.empty()) {
    std::ofstream f(o.csv_path);
    for (const auto& r : rows) f << r << "\n";
  }
  return 0;
}
