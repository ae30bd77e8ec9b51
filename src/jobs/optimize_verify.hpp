#pragma once
// optimize --verify: the made design through the kinematic solver, the rigid and the flexible
// model at the set's speed, every figure held to the set's limits ([limits], [verify]); the
// verdict goes to report.json ("verified", "verification") and, when a check fails, to
// the caller as a failure table (the CLI exits with exit_verification_failed after writing its
// outputs).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/spline.hpp"
#include "camopt/jobs/common.hpp"
#include "camopt/opt/problem.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::jobs {

class Verdict {
 public:
  // the checks' notes ("optimize --verify: ...") go to `observer`
  Verdict(double relative_tolerance, Observer& observer) : tolerance_(relative_tolerance), observer_(observer) {}
  void note(const std::string& message) { observer_.note(message); }
  // value <= limit (upper) or value >= limit, within the relative tolerance of the limit
  void bound(const std::string& model, const std::string& check, const std::string& unit, double value, double limit,
             bool upper, const std::string& at = "");
  // a count of events that must be zero (separations, bounces, coil clashes)
  void none(const std::string& model, const std::string& check, int count, const std::string& at = "");
  // a run that could not be made
  void failed(const std::string& model, const std::string& check, const std::string& why);
  bool passed() const;
  nlohmann::json json() const;       // every check with its value, limit and outcome
  std::string failure_table() const;  // the failed checks, one line each

 private:
  struct Check {
    std::string model, check, unit, at, note;
    double value = 0, limit = 0;
    bool upper = true, passed = true, counted = false;
  };
  double tolerance_;
  Observer& observer_;
  std::vector<Check> checks_;
};

// a rotational cam: the kinematic solver's lift and limits on the made design, then rigid
// and flexible dynamics at the set's rpm; writes report["verify"]
void verify_rotational(const DesignSpec& made, const synthesis::SynthesisResult& made_cam, const PeriodicSpline& lift,
                       const std::vector<double>& controls, const opt::CamProblem& problem, nlohmann::json& report,
                       Verdict& verdict);

// a swing cam: rigid dynamics at every control position and flexible dynamics at the
// full-lift position (the kinematic check is the caller's); writes report["verify"]
void verify_swing_dynamics(const DesignSpec& made, const opt::CamProblem& problem, nlohmann::json& report,
                           Verdict& verdict);

// report["verified"] and report["verification"]
void record_verdict(const Verdict& verdict, nlohmann::json& report);

}  // namespace camopt::jobs
