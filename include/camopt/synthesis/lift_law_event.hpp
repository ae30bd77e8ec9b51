#pragma once
// a full valve-lift event over one cam revolution, assembled from lift laws
// (lift_law.hpp): base circle, opening ramp, rise, optional dwell at max lift, fall
// (its own law and duration), closing ramp, base circle. spec -> validate -> compile:
// a plain LiftEventSpec is checked by validate() (InputError naming the field, the value
// and the rule) and compile() returns an immutable LiftEvent; evaluation never allocates.
//
// each flank, in its own angle phi from the start of its ramp (the closing flank runs
// backwards from the end of the event):
//   ramp   [0, Lr): constant velocity vr = Hr / (Lr (1 - b/2)) reached by a cycloidal
//          velocity blend over the first b Lr (acceleration vr/(b Lr) (1 - cos 2 pi u)),
//          so lift, velocity, acceleration and jerk are continuous at the base circle
//          and the ramp reaches Hr at Lr exactly.
//   main   [Lr, beta]: s = Hr + (H - Hr) y(x) + vr beta_m R(x), x = (phi - Lr) / beta_m,
//          beta_m = beta - Lr, with y the law's unit rise and
//          R(x) = x (1 - x)^6 (1 + 6 x): R(0) = 0, R'(0) = 1, R''(0) = 0, and R and its
//          first five derivatives vanish at x = 1. the main flank so starts at the ramp
//          velocity with zero acceleration (c2 join to the ramp; the jerk steps) and ends
//          with the law's own end conditions (zero velocity and acceleration at max lift).
//   max lift: the flanks meet at H with zero velocity and acceleration (c2), directly or
//          through a dwell.
// formulas, continuity table and sources: docs/lift-laws.md.
#include <memory>
#include <string>
#include <vector>

#include "camopt/synthesis/lift_law.hpp"

namespace camopt::synthesis {

// one side of the event
struct FlankSpec {
  LawKind law = LawKind::polynomial_345;
  double duration_deg = 65.0;     // ramp + main flank, from lift start to max lift [cam deg]
  double ramp_height_mm = 0.0;    // lift at the end of the ramp [mm]; 0 with length 0: no ramp
  double ramp_length_deg = 0.0;   // [cam deg]
  std::vector<double> acc_controls;  // law bspline: acceleration control values [any unit, a shape]
  int bspline_degree = 3;            // law bspline: degree of the acceleration b-spline
};

struct LiftEventSpec {
  double max_lift_mm = 10.0;  // [mm]
  double peak_deg = 180.0;    // cam angle of max lift: the middle of the dwell [cam deg], in [0, 360)
  double dwell_deg = 0.0;     // dwell at max lift [cam deg]
  double ramp_blend = 0.5;    // fraction of each ramp spent reaching the ramp velocity, in (0, 1] [1]
  FlankSpec opening;
  FlankSpec closing;
  // law polydyne: design engine speed [rpm, crankshaft] and valvetrain natural frequency [Hz]
  double polydyne_engine_rpm = 0.0;
  double polydyne_natural_hz = 0.0;
  double crank_per_cam = 2.0;  // crank deg per cam deg (4-stroke)
};

// InputError "field = value unit: rule" for the first broken rule (fields named as in the
// spec, e.g. opening.ramp_length_deg); compile() also checks that each flank rises
// monotonically, which needs the laws built
void validate(const LiftEventSpec& spec);

// the angles where the event's pieces join [cam deg, unwrapped: start_deg() + offset]
struct EventJoins {
  double opening_start = 0.0;     // base circle -> opening ramp (or flank)
  double opening_blend_end = 0.0; // velocity blend -> constant-velocity ramp
  double opening_ramp_end = 0.0;  // ramp -> main opening flank
  double max_lift_start = 0.0;    // opening flank -> dwell (or closing flank)
  double max_lift_end = 0.0;      // dwell -> closing flank
  double closing_ramp_start = 0.0;  // main closing flank -> closing ramp
  double closing_blend_start = 0.0; // constant-velocity ramp -> velocity blend
  double closing_end = 0.0;       // closing ramp -> base circle
};

// a constant-velocity opening ramp of height Hr [mm] over Lr [cam deg], reaching its
// velocity vr = Hr / (Lr (1 - b/2)) through a cycloidal velocity blend over the first
// b Lr, so lift, velocity, acceleration and jerk are continuous at the base circle.
// length 0: no ramp (zero motion).
class Ramp {
 public:
  Ramp() = default;
  Ramp(double height_mm, double length_deg, double blend);
  // lift [mm] and derivatives per cam deg at phi [cam deg] from the start of the ramp;
  // past the ramp's end the constant-velocity line continues
  Motion evaluate(double phi_deg) const noexcept;

  double height_mm() const noexcept { return height_; }
  double length_deg() const noexcept { return length_; }
  double blend_length_deg() const noexcept { return blend_length_; }
  double velocity() const noexcept { return velocity_; }  // [mm/deg]

 private:
  double height_ = 0.0, length_ = 0.0, blend_length_ = 0.0, velocity_ = 0.0;
};

// one flank compiled: ramp + main law + velocity-matching term
class Flank {
 public:
  Flank() = default;
  Flank(std::shared_ptr<const RiseLaw> law, double ramp_height_mm, double ramp_length_deg, double ramp_blend);
  // lift [mm] and derivatives per deg of phi, phi in [0, duration] from the start of the ramp
  Motion evaluate(double phi_deg) const noexcept;

  const RiseLaw& law() const noexcept { return *law_; }
  double duration_deg() const noexcept { return ramp_.length_deg() + law_->duration_deg(); }
  double ramp_height_mm() const noexcept { return ramp_.height_mm(); }
  double ramp_length_deg() const noexcept { return ramp_.length_deg(); }
  double blend_length_deg() const noexcept { return ramp_.blend_length_deg(); }
  double ramp_velocity() const noexcept { return ramp_.velocity(); }  // [mm/deg]

 private:
  std::shared_ptr<const RiseLaw> law_;  // the main flank: height H - Hr over beta - Lr
  Ramp ramp_;
};

class LiftEvent {
 public:
  // validate, build both flanks, check each rises monotonically
  static LiftEvent compile(const LiftEventSpec& spec);

  // lift [mm], d/dtheta [mm/deg], d2 [mm/deg^2], d3 [mm/deg^3] at any cam angle [deg]
  // (periodic over 360); a join evaluates the piece to its right
  Motion evaluate(double cam_deg) const noexcept;

  const LiftEventSpec& spec() const noexcept { return spec_; }
  const Flank& opening() const noexcept { return opening_; }
  const Flank& closing() const noexcept { return closing_; }
  double start_deg() const noexcept { return start_; }    // opening start, in [0, 360)
  double length_deg() const noexcept { return length_; }  // opening + dwell + closing
  EventJoins joins() const noexcept;

  // cam-angle span with lift >= lift_mm [cam deg]: exact (bisection on the monotonic
  // flanks); the whole event for lift_mm <= 0 and 0 above the max lift
  double duration_above(double lift_mm) const noexcept;

 private:
  LiftEventSpec spec_;
  Flank opening_, closing_;
  double start_ = 0.0, length_ = 0.0;
};

// extremes over the cycle, sampled every resolution_deg and at every join
struct LiftEventSummary {
  double max_lift_mm = 0.0, max_lift_at_deg = 0.0;
  double event_deg = 0.0;                 // duration at 0 lift (ramps included)
  double duration_1mm_deg = 0.0;          // duration at 1 mm lift
  double duration_0p1mm_deg = 0.0;        // duration at 0.1 mm lift
  double max_vel = 0.0, min_vel = 0.0;    // [mm/deg]
  double max_acc = 0.0, max_acc_at_deg = 0.0, min_acc = 0.0, min_acc_at_deg = 0.0;  // [mm/deg^2], [cam deg]
  double max_abs_jerk = 0.0;              // [mm/deg^3]
};

LiftEventSummary summarize(const LiftEvent& event, double resolution_deg = 0.01);

}  // namespace camopt::synthesis
