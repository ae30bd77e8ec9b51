#pragma once
// what would make a valve-lift target that folds a swing cam feasible: the same lift shape
// scaled down, bisected on its scale until it synthesizes.
#include <string>

#include "camopt/core/spline.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::synthesis {

struct LiftScaleBound {
  bool found = false;              // some scale >= smallest_scale synthesizes
  double scale = 0.0;              // the largest scale found to synthesize (bisection's lower end)
  double failing_scale = 1.0;      // the smallest scale found to fail (bisection's upper end)
  double peak_mm = 0.0;            // the target's peak lift [mm]
  int syntheses = 0;               // work: syntheses run
};

// bisection on s in [smallest_scale, 1] of "s x lift synthesizes" (synthesize() returns ok,
// options as given), `steps` halvings after the first probe at smallest_scale; lift: the
// valve lift [mm] against cam angle [rad]
LiftScaleBound largest_synthesizable_scale(const DesignSpec& spec, const PeriodicSpline& lift,
                                           const SynthesisOptions& options, double smallest_scale = 1.0 / 64,
                                           int steps = 8);

// the sentence appended to a swing fold's message: the bound above in mm of peak lift, and
// the pointer to `camopt optimize --cam swing`
std::string swing_remedy_text(const LiftScaleBound& bound, double smallest_scale = 1.0 / 64);

}  // namespace camopt::synthesis
