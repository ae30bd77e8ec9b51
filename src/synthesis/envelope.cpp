// synthesize(): the steps of envelope synthesis in order (envelope.hpp), and the steps that
// are its own: the cut, the target's samples, the envelope of a rotational cam and its
// winding check. The other steps live in the files listed in detail/envelope_steps.hpp.
#include "camopt/synthesis/envelope.hpp"

#include <algorithm>
#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"
#include "camopt/synthesis/detail/fold_status.hpp"
#include "camopt/synthesis/swing_remedy.hpp"

namespace camopt::synthesis {

using detail::fmt;
using detail::Jet2;
using detail::Jet3;
using detail::P2;

namespace {

// the result's names of the cut, and a note for every lash the synthesis ignores
void start_result(const DesignSpec& spec, const detail::Halves& halves, SynthesisResult& result) {
  result = {};
  result.connection = spec.connections[halves.cut.connection].name;
  result.cam_node = halves.cut.cam_node;
  result.follower_node = halves.cut.follower_node;
  result.follower_shape = to_string(halves.follower_surface->shape);
  for (const auto& c : spec.connections)
    if (c.lash_mm > 0)
      result.notes.push_back("lash of '" + c.name + "' (" + fmt(c.lash_mm) +
                             " mm) is ignored: the target lift's ramps are expected to take it up");
}

// a swing cam: its resting follower over the control family, then its profile; a valve
// lift that folds the swing cam is told how far down its scale would have to go
Status synthesize_swing(const DesignSpec& spec, const PeriodicSpline& lift, const SynthesisOptions& options,
                        detail::Halves& halves, const detail::TargetSamples& target,
                        const detail::FollowerPath& follower, SynthesisResult& result) {
  const std::vector<detail::IdleCentre> idle_centres = detail::idle_family(halves, lift, target, follower.cam_rate);
  bool folds = false;
  Status st = detail::swing_profile(halves, follower, target.theta, idle_centres, options, result, folds);
  if (folds && options.remedies && options.target_node.empty())
    st.message += ". " + swing_remedy_text(largest_synthesizable_scale(spec, lift, options));
  return st;
}

// orientation of the traced path: +1 counter-clockwise (shoelace area)
double orientation(const std::vector<P2<Jet3>>& path) {
  const int n = static_cast<int>(path.size());
  double area = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto& a = path[i];
    const auto& b = path[(i + 1) % n];
    area += a.x.value() * b.y.value() - b.x.value() * a.y.value();
  }
  return area >= 0 ? 1.0 : -1.0;
}

}  // namespace

void SynthesisOptions::validate() const {
  CAMOPT_THROW_UNLESS(cam == "rotational" || cam == "swing",
                      "synthesis option cam = '" + cam + "' must be 'rotational' or 'swing'");
  CAMOPT_THROW_UNLESS(points >= 6, "synthesis option points = " + std::to_string(points) + " must be >= 6");
  CAMOPT_THROW_UNLESS(samples >= points, "synthesis option samples = " + std::to_string(samples) +
                                             " must be >= points (" + std::to_string(points) + ")");
  for (std::size_t k = 0; k < controls.size(); ++k)
    CAMOPT_THROW_UNLESS(std::isfinite(controls[k]), "synthesis option controls[" + std::to_string(k) +
                                                        "] = " + format_value(controls[k]) + " must be finite");
  CAMOPT_THROW_UNLESS(std::isfinite(wheel_radius_mm) && wheel_radius_mm >= 0,
                      "synthesis option wheel_radius_mm = " + format_value(wheel_radius_mm) +
                          " mm must be finite and >= 0 (0: no check)");
  CAMOPT_THROW_UNLESS(std::isfinite(min_radius_mm) && min_radius_mm >= 0,
                      "synthesis option min_radius_mm = " + format_value(min_radius_mm) +
                          " mm must be finite and >= 0 (0: no check)");
}

DesignSpec with_profile(const DesignSpec& spec, const ProfileSpec& profile) {
  DesignSpec out = spec;
  bool replaced = false;
  for (auto& p : out.profiles)
    if (p.name == profile.name) {
      const SourceRef where = p.where;
      p = profile;
      p.where = where;
      replaced = true;
    }
  CAMOPT_ASSERT(replaced);
  for (auto& c : out.connections) c.lash_mm = 0.0;
  return out;
}

Status synthesize(const DesignSpec& spec, const PeriodicSpline& lift, const SynthesisOptions& options,
                  SynthesisResult& result) {
  options.validate();
  // 1. cut: the designed contact out of the mechanism, both halves compiled at the controls
  detail::Halves halves = detail::cut_and_compile(spec, options);
  start_result(spec, halves, result);
  // the target motion L(theta) as jets, at the envelope's samples of the driver angle
  const detail::TargetSamples target = detail::sample_target(lift, options.samples);
  // 2. inversion: the follower as a function of the target motion
  detail::FollowerInverse inverse;
  if (Status st = detail::invert_downstream(spec, halves, target, inverse, result); !st.ok()) return st;
  // the cam's motion: solved upstream, interpolated in the driver angle
  detail::CamMotion cam;
  if (Status st = detail::solve_cam_motion(halves, target.n, cam); !st.ok()) return st;
  result.upstream_solves = static_cast<int>(cam.node_at.size());
  // a swing cam is traced only where it moves: its angle at every sample first
  detail::FollowerPath follower(target.n, halves.roller);
  std::vector<char> needed(static_cast<std::size_t>(target.n), 1);
  if (options.cam == "swing" && !cam.lone_driver)
    detail::swing_angle_at_samples(halves, target.n, cam, follower.cam_rate, needed);
  // the follower in the cam's profile frame: inverse and cam motion composed
  detail::trace_follower(halves, target, inverse, cam, needed, follower);
  // a swing cam is traced over a stretch only: a profile of its own (swing_profile.cpp)
  if (options.cam == "swing") return synthesize_swing(spec, lift, options, halves, target, follower, result);
  // 3. envelope of the follower surfaces in the profile frame
  std::vector<P2<Jet2>> env;
  if (Status st = detail::envelope_of_follower(halves, target, follower, env, result); !st.ok()) return st;
  // the envelope must wind once round the cam pivot without folding back (no undercut)
  std::vector<double> phi;
  double sign = 1.0;
  if (Status st = detail::check_winding(halves, env, follower, phi, sign); !st.ok()) return st;
  // 4. resampling into the polar table at the profile's resolution
  detail::resample_polar(env, phi, sign, options, halves.cut.profile, result);
  return Status::success();
}

namespace detail {

Halves cut_and_compile(const DesignSpec& spec, const SynthesisOptions& options) {
  const std::string target_node = options.target_node.empty() ? spec.output_node : options.target_node;
  MechanismCut cut = cut_mechanism(spec, options.cam, target_node);
  const auto& conn = spec.connections[cut.connection];
  // a floating follower (intermediate lever) is not fixed by the target motion during its
  // idle travel: inverted through its cam roller's travel instead (floating_inversion.hpp),
  // on a mechanism of its own, so the downstream half is compiled only where it is solved
  // (a conventional follower, or the idle family of a swing cam)
  const auto follower_spec = std::find_if(spec.nodes.begin(), spec.nodes.end(),
                                          [&](const NodeSpec& nd) { return nd.name == cut.follower_node; });
  CAMOPT_ASSERT(follower_spec != spec.nodes.end());
  const bool floating_follower = follower_spec->kind == NodeKind::floating;
  const bool needs_downstream = !floating_follower || options.cam == "swing";
  kin::Mechanism up = kin::compile(cut.upstream);
  kin::Mechanism down = needs_downstream ? kin::compile(cut.downstream) : kin::Mechanism{};
  Halves h(std::move(up), std::move(down));
  h.target_node = target_node;
  h.cam_surface = cut.profile_on_a ? &conn.surface_a : &conn.surface_b;
  h.follower_surface = cut.profile_on_a ? &conn.surface_b : &conn.surface_a;
  h.floating_follower = floating_follower;
  h.needs_downstream = needs_downstream;
  h.controls = options.controls;
  if (h.controls.empty())
    for (const auto& c : spec.controls) h.controls.push_back(c.default_value);
  h.up_ws.set_controls(h.controls);
  if (needs_downstream) h.down_ws.set_controls(h.controls);
  h.cam = h.up.node_index(cut.cam_node);
  h.follower = needs_downstream ? h.down.node_index(cut.follower_node) : -1;
  const kin::Node& cam = h.up.nodes[h.cam];
  h.cam_angle_variable = cam.first_variable + (cam.kind == NodeKind::floating ? 2 : 0);
  if (!h.up.driver_is_angle()) throw InputError("synthesize: the driver '" + spec.driver.node + "' must be rotational");
  // profile placement on the cam node (drawing) [mm]
  const SurfaceSpec& cs = *h.cam_surface;
  h.frame = {cs.origin_mm[0], cs.origin_mm[1], std::cos(cs.orientation_deg * pi / 180),
             std::sin(cs.orientation_deg * pi / 180)};
  h.roller = h.follower_surface->shape == SurfaceShape::circle;
  h.radius = h.follower_surface->radius_mm;
  h.cut = std::move(cut);
  return h;
}

TargetSamples sample_target(const PeriodicSpline& lift, int requested_samples) {
  TargetSamples t;
  t.n = envelope_samples(lift, requested_samples);
  t.theta.resize(t.n);
  t.motion.resize(t.n);
  t.lo = 1e300, t.hi = -1e300;
  for (int i = 0; i < t.n; ++i) {
    t.theta[i] = 2 * pi * i / t.n;
    double d[4];  // L and its derivatives at theta
    lift.evaluate(t.theta[i], 3, d);
    t.motion[i] = jet_from_derivatives<3>(d);
    t.lo = std::min(t.lo, t.motion[i].value());
    t.hi = std::max(t.hi, t.motion[i].value());
  }
  return t;
}

Status envelope_of_follower(const Halves& halves, const TargetSamples& target, const FollowerPath& follower,
                            std::vector<P2<Jet2>>& env, SynthesisResult& result) {
  const int n = target.n;
  const auto& path = follower.path;
  const auto& normal = follower.normal;
  const double orient = orientation(path);
  // envelope points with their first two derivatives in theta
  env.assign(n, P2<Jet2>{});
  double face_min = 1e300, face_max = -1e300;
  for (int i = 0; i < n; ++i) {
    if (halves.roller) {
      // p = c - r nu: the centre path offset by the roller radius
      const P2<Jet2> d{derivative_of(path[i].x), derivative_of(path[i].y)};
      const Jet2 len = sqrt(d.x * d.x + d.y * d.y);
      if (!(len.value() > 1e-12))
        return {StatusCode::undercut, "the follower centre stands still relative to the cam (no envelope)",
                "cam " + fmt(target.theta[i] * 180 / pi) + " deg"};
      // outward normal of the centre path (right of a counter-clockwise tangent)
      const P2<Jet2> nu{orient * d.y / len, -orient * d.x / len};
      env[i] = {truncate<2>(path[i].x) - halves.radius * nu.x, truncate<2>(path[i].y) - halves.radius * nu.y};
    } else {
      // envelope of the face lines (x - q).n = 0 over theta: p = q + lambda t with
      // lambda = (q'.n) / (t.n') (Chakraborty & Dhande, ch. 3)
      const P2<Jet2> q{truncate<2>(path[i].x), truncate<2>(path[i].y)};
      const P2<Jet2> dq{derivative_of(path[i].x), derivative_of(path[i].y)};
      const P2<Jet2> nv{truncate<2>(normal[i].x), truncate<2>(normal[i].y)};
      const P2<Jet2> dn{derivative_of(normal[i].x), derivative_of(normal[i].y)};
      const P2<Jet2> t{-nv.y, nv.x};
      const Jet2 turn = t.x * dn.x + t.y * dn.y;  // rotation rate of the face in the cam frame
      if (!(std::abs(turn.value()) > 1e-12))
        return {StatusCode::undercut, "the flat face does not turn relative to the cam (no envelope)",
                "cam " + fmt(target.theta[i] * 180 / pi) + " deg"};
      const Jet2 lambda = (dq.x * nv.x + dq.y * nv.y) / turn;  // contact offset along the face [mm]
      // offset from the face's reference point (the drawing point_mm)
      face_min = std::min(face_min, lambda.value());
      face_max = std::max(face_max, lambda.value());
      env[i] = {q.x + lambda * t.x, q.y + lambda * t.y};
    }
  }
  if (!halves.roller) {
    result.face_offset_min_mm = face_min;
    result.face_offset_max_mm = face_max;
  }
  return Status::success();
}

Status check_winding(const Halves& halves, const std::vector<P2<Jet2>>& env, const FollowerPath& follower,
                     std::vector<double>& phi, double& sign) {
  const int n = static_cast<int>(env.size());
  const auto& path = follower.path;
  const double orient = orientation(path);  // for the fold status
  // the profile must be traced monotonically in polar angle (star-shaped, no undercut), in
  // the sense in which it winds
  phi.assign(n + 1, 0.0);
  std::vector<double> dphi(n);
  double winding = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = env[i].x.value(), y = env[i].y.value();
    const double x1 = env[i].x.derivative(1), y1 = env[i].y.derivative(1);
    dphi[i] = (x * y1 - y * x1) / (x * x + y * y);
    winding += dphi[i];
  }
  sign = winding >= 0 ? 1.0 : -1.0;
  bool folds = false;
  for (int i = 0; i < n && !folds; ++i) {
    // roller: the profile runs backwards against its centre path where the centre path's
    // radius of curvature is below the roller radius (undercut, a cusp)
    const double d_env = env[i].x.derivative(1) * path[i].x.derivative(1) + env[i].y.derivative(1) * path[i].y.derivative(1);
    folds = !(dphi[i] * sign > 0) || (halves.roller && d_env <= 0.0);
  }
  phi[0] = std::atan2(env[0].y.value(), env[0].x.value());
  for (int i = 1; i <= n; ++i) {
    const auto& e = env[i % n];
    double a = std::atan2(e.y.value(), e.x.value());
    a += 2 * pi * std::round((phi[i - 1] - a) / (2 * pi));
    phi[i] = a;
  }
  // every window where it folds, with the worst value in each
  if (folds) return detail::revolution_fold_status(env, path, phi, sign, orient, halves.roller ? halves.radius : -1.0);
  if (std::abs(std::abs(phi[n] - phi[0]) - 2 * pi) > 1e-6)
    return {StatusCode::undercut, "the synthesized profile does not wind once around the cam pivot", "whole revolution"};
  return Status::success();
}

}  // namespace detail

}  // namespace camopt::synthesis
