// a full lift event from lift laws: validation, ramps, velocity-matched flanks, dwell,
// asymmetric fall (formulas in lift_law_event.hpp and docs/lift-laws.md).
#include "camopt/synthesis/lift_law_event.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/core/units.hpp"

namespace camopt::synthesis {

namespace {

constexpr double kCycleDeg = 360.0;
// velocity below -kMonotonicTol * (mean flank velocity) counts as a falling flank
constexpr double kMonotonicTol = 1e-9;
constexpr int kMonotonicSamples = 4000;

std::string num(double v) { return format_value(v, 10); }

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// R(x) = x (1 - x)^6 (1 + 6 x) = x - 21 x^3 + 70 x^4 - 105 x^5 + 84 x^6 - 35 x^7 + 6 x^8:
// R(0) = 0, R'(0) = 1, R''(0) = 0; R .. R^(5) vanish at x = 1
constexpr std::array<double, 9> kVelocityMatch = {0.0, 1.0, 0.0, -21.0, 70.0, -105.0, 84.0, -35.0, 6.0};

void velocity_match(double x, double* r) noexcept {
  for (int k = 0; k <= 3; ++k) {
    double s = 0.0;
    for (int m = static_cast<int>(kVelocityMatch.size()) - 1; m >= k; --m) {
      double f = 1.0;
      for (int i = 0; i < k; ++i) f *= m - i;
      s = s * x + kVelocityMatch[static_cast<std::size_t>(m)] * f;
    }
    r[k] = s;
  }
}

void validate_flank(const LiftEventSpec& spec, const FlankSpec& f, const std::string& side) {
  const std::string p = side + ".";
  if (!finite_positive(f.duration_deg))
    throw InputError(p + "duration_deg = " + num(f.duration_deg) + " cam deg: must be finite and positive");
  if (!finite_non_negative(f.ramp_height_mm))
    throw InputError(p + "ramp_height_mm = " + num(f.ramp_height_mm) + " mm: must be finite and >= 0");
  if (!finite_non_negative(f.ramp_length_deg))
    throw InputError(p + "ramp_length_deg = " + num(f.ramp_length_deg) + " cam deg: must be finite and >= 0");
  if (f.ramp_height_mm > 0.0 && f.ramp_length_deg == 0.0)
    throw InputError(p + "ramp_height_mm = " + num(f.ramp_height_mm) + " mm: a ramp needs a length (" + p +
                     "ramp_length_deg is 0); give both or neither");
  if (f.ramp_length_deg > 0.0 && f.ramp_height_mm == 0.0)
    throw InputError(p + "ramp_length_deg = " + num(f.ramp_length_deg) + " cam deg: a ramp needs a height (" + p +
                     "ramp_height_mm is 0); give both or neither");
  if (f.ramp_length_deg >= f.duration_deg)
    throw InputError(p + "ramp_length_deg = " + num(f.ramp_length_deg) + " cam deg: must be shorter than " + p +
                     "duration_deg = " + num(f.duration_deg) + " cam deg (the ramp is part of the flank)");
  if (f.ramp_height_mm >= spec.max_lift_mm)
    throw InputError(p + "ramp_height_mm = " + num(f.ramp_height_mm) + " mm: must be below max_lift_mm = " +
                     num(spec.max_lift_mm) + " mm");
  if (f.law == LawKind::bspline) {
    if (f.bspline_degree < BSplineAcceleration::kMinDegree || f.bspline_degree > BSplineAcceleration::kMaxDegree)
      throw InputError(p + "bspline_degree = " + std::to_string(f.bspline_degree) + ": must be in [" +
                       std::to_string(BSplineAcceleration::kMinDegree) + ", " +
                       std::to_string(BSplineAcceleration::kMaxDegree) + "]");
    const std::size_t need = static_cast<std::size_t>(std::max(f.bspline_degree + 1, 4));
    if (f.acc_controls.size() < need)
      throw InputError(p + "acc_controls: " + std::to_string(f.acc_controls.size()) + " values: law bspline of degree " +
                       std::to_string(f.bspline_degree) + " needs at least " + std::to_string(need) +
                       " acceleration control values");
    for (std::size_t i = 0; i < f.acc_controls.size(); ++i)
      if (!std::isfinite(f.acc_controls[i]))
        throw InputError(p + "acc_controls: value " + std::to_string(i + 1) + " = " + num(f.acc_controls[i]) +
                         ": must be finite");
  } else if (!f.acc_controls.empty()) {
    throw InputError(p + "acc_controls: given, but " + p + "law is " + to_string(f.law) +
                     " (acceleration control values are for law bspline only)");
  }
}

// the main-flank law of one side: height H - Hr over beta - Lr
std::shared_ptr<const RiseLaw> make_law(const LiftEventSpec& spec, const FlankSpec& f, const std::string& side) {
  const double h = spec.max_lift_mm - f.ramp_height_mm;
  const double beta = f.duration_deg - f.ramp_length_deg;
  switch (f.law) {
    case LawKind::polynomial_345:
      return std::make_shared<Polynomial345>(h, beta);
    case LawKind::polynomial_4567:
      return std::make_shared<Polynomial4567>(h, beta);
    case LawKind::cycloidal:
      return std::make_shared<Cycloidal>(h, beta);
    case LawKind::modified_trapezoid:
      return std::make_shared<ModifiedTrapezoid>(h, beta);
    case LawKind::modified_sine:
      return std::make_shared<ModifiedSine>(h, beta);
    case LawKind::polydyne:
      return std::make_shared<Polydyne>(
          h, beta, Polydyne::dynamic_factor(spec.polydyne_engine_rpm, spec.polydyne_natural_hz, beta, spec.crank_per_cam));
    case LawKind::bspline:
      try {
        return std::make_shared<BSplineAcceleration>(h, beta, f.acc_controls, f.bspline_degree);
      } catch (const InputError& e) {
        throw InputError(side + "." + e.what());
      }
  }
  CAMOPT_ASSERT_MSG(false, "unknown lift law");
  return nullptr;
}

// a lift flank must rise monotonically: a falling flank means the ramp is too fast for
// the law, or a polydyne factor / b-spline shape that overshoots
void check_monotonic(const Flank& flank, const LiftEventSpec& spec, const FlankSpec& f, const std::string& side) {
  const double beta = flank.duration_deg();
  const double tol = kMonotonicTol * spec.max_lift_mm / beta;
  for (int i = 0; i <= kMonotonicSamples; ++i) {
    const double phi = beta * i / kMonotonicSamples;
    const Motion m = flank.evaluate(phi);
    if (m.vel < -tol) {
      const std::string p = side + ".";
      std::vector<std::string> fixes;
      if (flank.ramp_length_deg() > 0.0)
        fixes.push_back("lower " + p + "ramp_height_mm or lengthen " + p + "ramp_length_deg");
      if (f.law == LawKind::polydyne) {
        const auto& law = static_cast<const Polydyne&>(flank.law());
        fixes.push_back("lower the polydyne factor K = " + num(law.dynamic_factor()) +
                        " (raise polydyne_natural_hz or lower polydyne_engine_rpm)");
      }
      if (f.law == LawKind::bspline) fixes.push_back("change " + p + "acc_controls");
      if (fixes.empty()) fixes.push_back("lengthen " + p + "duration_deg");
      std::string hint;
      for (const auto& fix : fixes) hint += (hint.empty() ? "" : ", or ") + fix;
      throw InputError(p + "duration_deg = " + num(f.duration_deg) + " cam deg: the " + side + " flank (law " +
                       to_string(f.law) + ") would not rise monotonically: velocity " + num(m.vel) + " mm/deg at " +
                       num(phi) + " cam deg from its lift start; " + hint);
    }
  }
}

// the largest phi in [0, beta] with flank lift <= level (flank non-decreasing)
double crossing(const Flank& flank, double level) noexcept {
  double lo = 0.0, hi = flank.duration_deg();
  for (int i = 0; i < 200 && hi - lo > 1e-13 * flank.duration_deg(); ++i) {
    const double mid = 0.5 * (lo + hi);
    if (flank.evaluate(mid).lift < level)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double wrap(double deg) noexcept {
  double u = std::fmod(deg, kCycleDeg);
  if (u < 0.0) u += kCycleDeg;
  if (u >= kCycleDeg) u -= kCycleDeg;
  return u;
}

}  // namespace

// ---- validation ------------------------------------------------------------------------

void validate(const LiftEventSpec& spec) {
  if (!finite_positive(spec.max_lift_mm))
    throw InputError("max_lift_mm = " + num(spec.max_lift_mm) + " mm: must be finite and positive");
  if (!std::isfinite(spec.peak_deg) || spec.peak_deg < 0.0 || spec.peak_deg >= kCycleDeg)
    throw InputError("peak_deg = " + num(spec.peak_deg) + " cam deg: must be in [0, 360)");
  if (!finite_non_negative(spec.dwell_deg))
    throw InputError("dwell_deg = " + num(spec.dwell_deg) + " cam deg: must be finite and >= 0");
  if (!std::isfinite(spec.ramp_blend) || spec.ramp_blend <= 0.0 || spec.ramp_blend > 1.0)
    throw InputError("ramp_blend = " + num(spec.ramp_blend) +
                     ": must be in (0, 1] (0 would jump to the ramp velocity: infinite acceleration)");
  if (!finite_positive(spec.crank_per_cam))
    throw InputError("crank_per_cam = " + num(spec.crank_per_cam) + ": must be finite and positive");
  validate_flank(spec, spec.opening, "opening");
  validate_flank(spec, spec.closing, "closing");
  const double total = spec.opening.duration_deg + spec.dwell_deg + spec.closing.duration_deg;
  if (!(total < kCycleDeg))
    throw InputError("opening.duration_deg + dwell_deg + closing.duration_deg = " + num(spec.opening.duration_deg) +
                     " + " + num(spec.dwell_deg) + " + " + num(spec.closing.duration_deg) + " = " + num(total) +
                     " cam deg: the event must be shorter than 360 cam deg (the cam needs a base circle)");
  if (spec.opening.law == LawKind::polydyne || spec.closing.law == LawKind::polydyne) {
    if (!finite_positive(spec.polydyne_engine_rpm))
      throw InputError("polydyne_engine_rpm = " + num(spec.polydyne_engine_rpm) +
                       " rpm: law polydyne needs its design engine speed, finite and positive");
    if (!finite_positive(spec.polydyne_natural_hz))
      throw InputError("polydyne_natural_hz = " + num(spec.polydyne_natural_hz) +
                       " Hz: law polydyne needs the valvetrain natural frequency, finite and positive");
  }
}

// ---- Flank -----------------------------------------------------------------------------

Ramp::Ramp(double height_mm, double length_deg, double blend) : height_(height_mm), length_(length_deg) {
  if (length_ > 0.0) {
    blend_length_ = blend * length_;
    // Hr = vr (b Lr / 2 + (1 - b) Lr)
    velocity_ = height_ / (length_ * (1.0 - 0.5 * blend));
  }
}

Motion Ramp::evaluate(double phi) const noexcept {
  const double v = velocity_;
  if (length_ <= 0.0) return {};
  if (phi < blend_length_) {
    // cycloidal velocity blend 0 -> vr over [0, Lb]: v = vr (u - sin(2 pi u) / (2 pi))
    const double lb = blend_length_, w = 2.0 * pi;
    const double u = std::max(phi, 0.0) / lb;
    const double s = std::sin(w * u), c = std::cos(w * u);
    return {v * lb * (0.5 * u * u + (c - 1.0) / (w * w)), v * (u - s / w), v / lb * (1.0 - c),
            v / (lb * lb) * w * s};
  }
  return {v * (0.5 * blend_length_ + (phi - blend_length_)), v, 0.0, 0.0};
}

Flank::Flank(std::shared_ptr<const RiseLaw> law, double ramp_height_mm, double ramp_length_deg, double ramp_blend)
    : law_(std::move(law)), ramp_(ramp_height_mm, ramp_length_deg, ramp_blend) {
  CAMOPT_ASSERT(law_ != nullptr);
}

Motion Flank::evaluate(double phi) const noexcept {
  const double v = ramp_.velocity();
  if (phi < ramp_.length_deg()) return ramp_.evaluate(phi);
  // main flank: Hr + law + vr beta_m R(x)
  const double xi = phi - ramp_.length_deg();
  Motion m = law_->evaluate(xi);
  m.lift += ramp_.height_mm();
  if (v > 0.0) {
    const double bm = law_->duration_deg();
    const double x = std::clamp(xi / bm, 0.0, 1.0);
    double r[4];
    velocity_match(x, r);
    m.lift += v * bm * r[0];
    m.vel += v * r[1];
    m.acc += v / bm * r[2];
    m.jerk += v / (bm * bm) * r[3];
  }
  return m;
}

// ---- LiftEvent -------------------------------------------------------------------------

LiftEvent LiftEvent::compile(const LiftEventSpec& spec) {
  validate(spec);
  LiftEvent ev;
  ev.spec_ = spec;
  ev.opening_ = Flank(make_law(spec, spec.opening, "opening"), spec.opening.ramp_height_mm,
                      spec.opening.ramp_length_deg, spec.ramp_blend);
  ev.closing_ = Flank(make_law(spec, spec.closing, "closing"), spec.closing.ramp_height_mm,
                      spec.closing.ramp_length_deg, spec.ramp_blend);
  check_monotonic(ev.opening_, spec, spec.opening, "opening");
  check_monotonic(ev.closing_, spec, spec.closing, "closing");
  ev.length_ = spec.opening.duration_deg + spec.dwell_deg + spec.closing.duration_deg;
  ev.start_ = wrap(spec.peak_deg - 0.5 * spec.dwell_deg - spec.opening.duration_deg);
  return ev;
}

Motion LiftEvent::evaluate(double cam_deg) const noexcept {
  const double u = wrap(cam_deg - start_);
  const double bo = opening_.duration_deg();
  if (u < bo) return opening_.evaluate(u);
  if (u < bo + spec_.dwell_deg) return {spec_.max_lift_mm, 0.0, 0.0, 0.0};
  if (u < length_) {
    // the closing flank runs backwards: d/dtheta = -d/dphi
    Motion m = closing_.evaluate(length_ - u);
    m.vel = -m.vel;
    m.jerk = -m.jerk;
    return m;
  }
  return {};
}

EventJoins LiftEvent::joins() const noexcept {
  EventJoins j;
  j.opening_start = start_;
  j.opening_blend_end = start_ + opening_.blend_length_deg();
  j.opening_ramp_end = start_ + opening_.ramp_length_deg();
  j.max_lift_start = start_ + opening_.duration_deg();
  j.max_lift_end = j.max_lift_start + spec_.dwell_deg;
  j.closing_end = start_ + length_;
  j.closing_ramp_start = j.closing_end - closing_.ramp_length_deg();
  j.closing_blend_start = j.closing_end - closing_.blend_length_deg();
  return j;
}

double LiftEvent::duration_above(double lift_mm) const noexcept {
  if (!(lift_mm > 0.0)) return length_;
  if (lift_mm > spec_.max_lift_mm) return 0.0;
  const double phi_open = crossing(opening_, lift_mm);
  const double phi_close = crossing(closing_, lift_mm);
  return (opening_.duration_deg() - phi_open) + spec_.dwell_deg + (closing_.duration_deg() - phi_close);
}

LiftEventSummary summarize(const LiftEvent& event, double resolution_deg) {
  CAMOPT_ASSERT(resolution_deg > 0.0);
  LiftEventSummary s;
  s.max_lift_mm = event.spec().max_lift_mm;
  s.max_lift_at_deg = event.spec().peak_deg;
  s.event_deg = event.length_deg();
  s.duration_1mm_deg = event.duration_above(1.0);
  s.duration_0p1mm_deg = event.duration_above(0.1);

  const EventJoins j = event.joins();
  std::vector<double> angles;
  const int n = static_cast<int>(std::ceil(event.length_deg() / resolution_deg));
  for (int i = 0; i <= n; ++i) angles.push_back(event.start_deg() + event.length_deg() * i / n);
  for (double a : {j.opening_blend_end, j.opening_ramp_end, j.max_lift_start, j.max_lift_end, j.closing_ramp_start,
                   j.closing_blend_start})
    angles.push_back(a);
  bool first = true;
  for (double a : angles) {
    const Motion m = event.evaluate(a);
    if (first || m.acc > s.max_acc) {
      s.max_acc = m.acc;
      s.max_acc_at_deg = wrap(a);
    }
    if (first || m.acc < s.min_acc) {
      s.min_acc = m.acc;
      s.min_acc_at_deg = wrap(a);
    }
    s.max_vel = first ? m.vel : std::max(s.max_vel, m.vel);
    s.min_vel = first ? m.vel : std::min(s.min_vel, m.vel);
    s.max_abs_jerk = std::max(s.max_abs_jerk, std::abs(m.jerk));
    first = false;
  }
  return s;
}

}  // namespace camopt::synthesis
