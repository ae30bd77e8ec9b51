// optimisation benchmark: iterations, evaluations and time of every solver on the bundled
// constraint sets, with the error of each result: the objective's distance from the best
// objective any solver reached (same problem, so the same optimum), and the largest
// normalised constraint violation (fraction of its limit). cases: two conventional cams and
// the CVVL swing cam over its 17 control positions and the VVLD working curve over its 11.
// usage: bench_optimize [--csv FILE] [--solvers a,b,c] [--only DESIGN_SUBSTRING]
#include <cstdio>
#include <ctime>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/core/process_memory.hpp"
#include "camopt/io/constraint_file.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/opt/solve.hpp"

using namespace camopt;

int main(int argc, char** argv) {
  camopt::keep_freed_memory();  // as the camopt program does
  std::string csv_path, only;
  std::vector<std::string> solvers = {"ipopt", "slsqp", "mma", "cobyla", "global"};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--solvers") && i + 1 < argc) {
      solvers.clear();
      std::stringstream s(argv[++i]);
      for (std::string item; std::getline(s, item, ',');) solvers.push_back(item);
    } else {
      std::fprintf(stderr, "usage: bench_optimize [--csv FILE] [--solvers ipopt,slsqp,mma,cobyla,global] "
                           "[--only DESIGN_SUBSTRING]\n");
      return 2;
    }
  }
  const std::string root = CAMOPT_SOURCE_DIR;
  struct Case {
    const char *design, *set, *cam;
  };
  // the swing case: the CVVL's swing cam over its 17 control positions (optimize --cam swing)
  const Case cases[] = {{"designs/roller_finger_follower.toml", "constraints/passenger_car_intake.toml", "rotational"},
                        {"designs/bucket_tappet.toml", "constraints/high_speed_bucket.toml", "rotational"},
                        {"designs/cvvl_swing_cam.toml", "constraints/cvvl_swing_cam.toml", "swing"},
                        {"designs/vvld.toml", "constraints/vvld_swing_cam.toml", "swing"}};
  std::ostringstream csv;
  csv << "constraint_set,solver,variables,constraints,solver_rows,rounds,status,iterations,evaluations,time_s,cpu_s,"
         "objective,objective_error,max_violation\n";
  std::printf("| constraint set | solver | vars | constraints | solver rows | rounds | status | iterations | evaluations | "
              "time s | cpu s | objective | objective error | max violation |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    if (!only.empty() && std::string(c.design).find(only) == std::string::npos) continue;
    const DesignSpec d = io::load_design(root + "/" + c.design);
    opt::OptimizationSpec set = io::load_constraints(root + "/" + c.set);
    set.cam = c.cam;
    struct Row {
      std::string solver, status;
      int rows, rounds, it, ev;
      double t, cpu, f, v;
    };
    std::vector<Row> rows;
    double best = 1e300;
    std::unique_ptr<opt::CamProblem> made;
    if (const Status st = opt::CamProblem::create(d, set, nullptr, made); !st.ok()) {
      std::fprintf(stderr, "%s: %s\n", c.design, st.str().c_str());
      return 4;
    }
    opt::CamProblem& problem = *made;
    for (const auto& s : solvers) {
      opt::SolverOptions so;
      // "ipopt-h" / "ipopt-lbfgs": ipopt with the objective's own hessian / limited-memory bfgs
      // ("ipopt": the default, the objective's for a conventional cam, bfgs for a swing cam);
      // "-full" after any of them: every row in ipopt's problem (no row screening)
      so.solver = opt::parse_solver(s.rfind("ipopt", 0) == 0 ? "ipopt" : s);
      if (s.rfind("ipopt-h", 0) == 0) so.ipopt_hessian = opt::IpoptHessian::objective;
      if (s.rfind("ipopt-lbfgs", 0) == 0) so.ipopt_hessian = opt::IpoptHessian::limited_memory;
      if (s.size() > 5 && s.compare(s.size() - 5, 5, "-full") == 0) so.ipopt_screening = false;
      const std::clock_t c0 = std::clock();
      const auto r = opt::optimize(problem, so);
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      const bool ipopt = so.solver == opt::SolverKind::ipopt;
      rows.push_back({s, r.status.ok() ? "converged" : to_string(r.status.code), ipopt ? r.solver_rows : 0,
                      ipopt ? r.rounds : 0, r.iterations, r.evaluations, r.seconds, cpu,
                      r.final.objective, r.max_violation});
      if (r.max_violation <= 1e-6) best = std::min(best, r.final.objective);
    }
    for (const auto& r : rows) {
      const double err = std::abs(r.f - best) / std::max(1.0, std::abs(best));
      std::printf("| %s | %s | %d | %zu | %d | %d | %s | %d | %d | %.3f | %.3f | %.9f | %.1e | %.1e |\n",
                  set.name.c_str(), r.solver.c_str(), problem.variables(), problem.rows().size(), r.rows, r.rounds,
                  r.status.c_str(), r.it, r.ev, r.t, r.cpu, r.f, err, r.v);
      csv << '"' << set.name << "\"," << r.solver << ',' << problem.variables() << ',' << problem.rows().size() << ','
          << r.rows << ',' << r.rounds << ',' << r.status << ',' << r.it << ',' << r.ev << ',' << r.t << ',' << r.cpu << ',' << r.f << ',' << err << ',' << r.v << '\n';
    }
  }
  if (!csv_path.empty()) std::ofstream(csv_path) << csv.str();
  return 0;
}
