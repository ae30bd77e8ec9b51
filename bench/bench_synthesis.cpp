// synthesis benchmark: run time of envelope synthesis against its error.
//  - eccentric disc + offset roller: the synthesized profile against the exact disc;
//  - the bundled roller finger follower, bucket tappet and rocker arm, the CVVL swing cam
//    and the Valvetronic lever's working curve (a profile on a floating body) at maximum
//    lift: target = the design's own forward lift at 0.25 deg; error = round trip (forward
//    lift of the new cam against the target).
// resolution: 360 / points deg (polar angle, cam angle and tangent turn); samples = points.
// usage: bench_synthesis [--repeat N] [--rounds K] [--csv FILE] [--only TEXT] [--points N]
// synthesis ms: the best of N runs in each of K rounds over all cases (the rounds are
// seconds apart, so a case gets more than one chance at a quiet machine; a shared VM's
// load comes in bursts of seconds)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "camopt/core/units.hpp"
#include "camopt/core/process_memory.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "camopt/synthesis/envelope.hpp"

using namespace camopt;

namespace {
constexpr double deg = camopt::rad_per_deg;

PeriodicSpline forward_lift(const DesignSpec& d) {
  const auto m = kin::compile(d);
  PeriodicSpline lift;
  if (!kin::periodic_motion(m, m.output_node, {}, 0.25, lift).ok()) std::exit(1);
  return lift;
}
}  // namespace

int main(int argc, char** argv) {
  camopt::keep_freed_memory();  // as the camopt program does
  int repeat = 5, rounds = 1;
  std::string csv_path, only;  // only: the cases whose "design:cam" contains this text
  std::vector<int> resolutions{360, 720, 1440};  // points per revolution (--points: one of them)
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc) rounds = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--points") && i + 1 < argc) resolutions = {std::atoi(argv[++i])};
    else {
      std::fprintf(stderr, "usage: bench_synthesis [--repeat N] [--rounds K] [--csv FILE] [--only TEXT] [--points N]\n");
      return 2;
    }
  }
  std::vector<std::string> rows{
      "design,resolution_deg,table_points,synthesis_ms,round_trip_ms,profile_error_mm,round_trip_error_mm"};
  std::printf("%-26s %10s %8s %14s %14s %16s %18s\n", "design", "resol deg", "table", "synthesis ms",
              "round trip ms", "profile err mm", "round trip err mm");
  struct Case {
    const char* name;
    const char* cam;
  };
  std::map<std::string, double> best_ms;  // per case and resolution, over the rounds
  for (int round = 0; round < rounds; ++round)
  for (const Case& c : {Case{"eccentric_offset_roller", "rotational"}, Case{"roller_finger_follower", "rotational"},
                        Case{"bucket_tappet", "rotational"}, Case{"rocker_arm", "rotational"},
                        Case{"cvvl_swing_cam", "swing"}, Case{"valvetronic", "swing"},
                        Case{"valvetronic", "rotational"}}) {
    const char* name = c.name;
    const bool swing = std::string(c.cam) == "swing";
    if (!only.empty() && (std::string(name) + ":" + c.cam).find(only) == std::string::npos) continue;
    // the swing cam's untouched stretch and the Valvetronic lobe's idle-travel stretch are
    // the synthesizer's own (not fixed by the lift): no profile error against the original
    const bool own_stretch = swing || std::string(name) == "valvetronic";
    DesignSpec d = io::load_design(std::string(CAMOPT_SOURCE_DIR) + "/designs/" + name + ".toml");
    for (auto& conn : d.connections) conn.lash_mm = 0.0;
    const PeriodicSpline target = forward_lift(d);
    const auto m = kin::compile(d);
    for (int points : resolutions) {
      synthesis::SynthesisOptions o;
      o.points = points;
      o.samples = points;
      o.cam = c.cam;
      synthesis::SynthesisResult res;
      double best = 1e300;
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const Status st = synthesis::synthesize(d, target, o, res);
        if (!st.ok()) {
          std::fprintf(stderr, "%s: synthesize failed: %s\n", c.name, st.str().c_str());
          return 1;
        }
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      const std::string key = std::string(name) + ":" + c.cam + ":" + std::to_string(points);
      best = best_ms[key] = best_ms.count(key) ? std::min(best_ms[key], best) : best;
      if (round + 1 < rounds) continue;  // the errors and the table once, after the last round
      // profile error against the design's own cam (exact for the eccentric disc; the swing
      // cam's untouched stretch is the synthesizer's own bridge, so it is not compared)
      double perr = 0.0;
      int profile = -1;
      for (std::size_t i = 0; i < m.profiles.size(); ++i)
        if (m.profiles[i].name() == res.profile.name) profile = static_cast<int>(i);
      for (std::size_t k = 0; k < res.angle_deg.size() && !own_stretch; ++k)
        perr = std::max(perr, std::abs(res.radius_mm[k] - m.profiles[profile].radius_at(res.angle_deg[k] * deg)));
      synthesis::RoundTrip rt;
      const auto t0 = std::chrono::steady_clock::now();
      const Status rst = synthesis::round_trip(synthesis::with_profile(d, res.profile), target, {}, res.connection, rt);
      if (!rst.ok()) {
        std::fprintf(stderr, "%s: round trip failed: %s\n", c.name, rst.str().c_str());
        return 1;
      }
      const double trt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double resolution = 360.0 / points;
      const int table = static_cast<int>(res.angle_deg.size());
      const std::string label = std::string(name) + (swing ? " (swing)" : "");
      std::printf("%-26s %10.4g %8d %14.3f %14.2f %16.2e %18.2e\n", label.c_str(), resolution, table, best * 1e3,
                  trt * 1e3, own_stretch ? NAN : perr, rt.max_error_mm);
      char perr_text[32] = "";  // empty where not compared (never a NaN in a CSV)
      if (!own_stretch) std::snprintf(perr_text, sizeof perr_text, "%.4g", perr);
      char line[256];
      std::snprintf(line, sizeof line, "%s,%.4g,%d,%.4g,%.4g,%s,%.4g", label.c_str(), resolution, table, best * 1e3,
                    trt * 1e3, perr_text, rt.max_error_mm);
      rows.push_back(line);
    }
  }
  if (!csv_path.empty()) {
    std::ofstream f(csv_path);
    for (const auto& r : rows) f << r << "\n";
  }
  return 0;
}
