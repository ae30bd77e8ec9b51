// the HLA's standalone rig (docs/hla.md, "The rig"): the plunger (mass, return spring,
// chamber force, external force, travel stops) and the hydraulic state integrated by CVODE
// (BDF) with the element's roots; flows are cumulated as CVODES quadratures. This is the
// leak-down tester with a constant load, a cam event with a periodic force table, or a
// prescribed plunger motion.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "camopt/dynamics/hla.hpp"
#include "cvode_support.hpp"

namespace camopt::dynamics {

namespace {

using detail::keep_callback_error;

enum class PlungerStop { free, at_min, at_max };

// states: z, zdot, then the hydraulic state; roots: the element's, the two travel stops, the end
constexpr int kStates = 2 + kHlaStates;
constexpr int kTravelRoot = kHlaRoots, kEndRoot = kHlaRoots + 2, kRoots = kHlaRoots + 3;
constexpr int kQuadratures = 6;  // leak, orifice, refill; the same over s(p)

struct Rig {
  const Hla& h;
  const HlaRigLoad& load;
  const HlaRigOptions& opt;
  HlaMode mode;
  PlungerStop stop = PlungerStop::free;
  std::string callback_error;

  double crank(double t) const { return load.crank0_deg + 6.0 * load.rpm * t; }

  // the force pushing the plunger into the body [N]: constant plus the periodic table
  double external(double t) const {
    double f = load.force_N;
    const std::vector<double>& x = load.table_time_s;
    if (x.empty()) return f;
    double a = load.period_s > 0.0 ? std::fmod(t - x.front(), load.period_s) : t - x.front();
    if (a < 0.0) a += load.period_s;
    a += x.front();
    if (a <= x.front()) return f + load.table_force_N.front();
    if (a >= x.back()) return f + load.table_force_N.back();
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), a) - x.begin()) - 1;
    const double u = (a - x[i]) / (x[i + 1] - x[i]);
    return f + load.table_force_N[i] + u * (load.table_force_N[i + 1] - load.table_force_N[i]);
  }

  // plunger position, rate and (prescribed) acceleration at t
  void motion(double t, const double* y, double& z, double& zdot, double& zddot) const {
    if (!load.prescribed_motion) {
      z = y[0];
      zdot = y[1];
      zddot = 0.0;
      return;
    }
    const double w = 2.0 * std::numbers::pi * load.frequency_hz;
    z = opt.z0_mm + load.velocity_mm_per_s * t + load.amplitude_mm * std::sin(w * t);
    zdot = load.velocity_mm_per_s + load.amplitude_mm * w * std::cos(w * t);
    zddot = -load.amplitude_mm * w * w * std::sin(w * t);
  }

  // the net force extending the plunger [N]
  double net_force(double t, double z, double p) const { return hla_force(h, crank(t), p, z) - external(t); }

  void rates(double t, const double* y, double* yd, HlaFlows* flows) const {
    double z = 0.0, zdot = 0.0, zddot = 0.0;
    motion(t, y, z, zdot, zddot);
    hla_rates(h, crank(t), z, zdot, y + 2, mode, yd + 2, flows);
    if (load.prescribed_motion) {
      yd[0] = zdot;
      yd[1] = zddot;
    } else if (stop != PlungerStop::free) {
      yd[0] = yd[1] = 0.0;
    } else {
      yd[0] = y[1];
      yd[1] = net_force(t, z, y[2 + kHlaPressure]) / h.plunger_mass;
    }
  }

  void roots(double t, const double* y, double* g) const {
    double z = 0.0, zdot = 0.0, zddot = 0.0;
    motion(t, y, z, zdot, zddot);
    hla_roots(h, crank(t), z, zdot, y + 2, mode, g);
    g[kTravelRoot] = g[kTravelRoot + 1] = 1.0;
    if (!load.prescribed_motion) {
      if (stop == PlungerStop::free) hla_travel_roots(h, z, g + kTravelRoot);
      if (stop == PlungerStop::at_min) g[kTravelRoot] = net_force(t, z, y[2 + kHlaPressure]);  // > 0: leaves
      if (stop == PlungerStop::at_max) g[kTravelRoot + 1] = net_force(t, z, y[2 + kHlaPressure]);  // < 0: leaves
    }
    g[kEndRoot] = z - opt.stop_z_mm;
  }
};

int rhs_callback(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* rig = static_cast<Rig*>(data);
  try {
    rig->rates(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), nullptr);
    const double* yd = N_VGetArrayPointer(ydot);
    for (int i = 0; i < kStates; ++i)
      if (!std::isfinite(yd[i])) return 1;  // recoverable: CVODE retries with a smaller step
    return 0;
  } catch (...) {
    return keep_callback_error(rig->callback_error, "right-hand side");
  }
}

int quadrature_callback(sunrealtype t, N_Vector y, N_Vector q_dot, void* data) {
  auto* rig = static_cast<Rig*>(data);
  try {
    const double* yv = N_VGetArrayPointer(y);
    double yd[kStates];
    HlaFlows f;
    rig->rates(t, yv, yd, &f);
    const double s = hla_volume_ratio(rig->h, yv[2 + kHlaPressure]);
    double* q = N_VGetArrayPointer(q_dot);
    q[0] = f.leak, q[1] = f.orifice, q[2] = f.refill;
    q[3] = f.leak / s, q[4] = f.orifice / s, q[5] = f.refill / s;
    return std::isfinite(s) ? 0 : 1;
  } catch (...) {
    return keep_callback_error(rig->callback_error, "quadrature");
  }
}

int root_callback(sunrealtype t, N_Vector y, sunrealtype* g, void* data) {
  auto* rig = static_cast<Rig*>(data);
  try {
    rig->roots(t, N_VGetArrayPointer(y), g);
    return 0;
  } catch (...) {
    return keep_callback_error(rig->callback_error, "root function");
  }
}

// the plunger speed at which the chamber's net outflow keeps the load balanced (a start without
// the hydraulic spring's transient): -zdot (A_p + couette + V k / (beta A_p)) = Q_out(zdot = 0)
double quasi_static_speed(const Rig& rig, const double* y) {
  const Hla& h = rig.h;
  double rates[kHlaStates];
  HlaFlows f;
  hla_rates(h, rig.crank(0.0), y[0], 0.0, y + 2, rig.mode, rates, &f);
  const double p = y[2 + kHlaPressure];
  const double compression = hla_chamber_volume(h, y[0]) * h.spring_rate / (hla_bulk_modulus(h, p) * h.plunger_area);
  return (f.refill - f.leak - f.orifice) / (h.plunger_area + h.couette_area + compression);
}

class RigRun {
 public:
  RigRun(Rig& rig, HlaRigResult& out) : rig_(rig), out_(out) {}
  Status setup();
  Status integrate();

 private:
  Status advance(double tout, bool& ended);
  bool on_roots(bool& ended);
  void record();
  Status failure(const std::string& what) const {
    return {StatusCode::integrator_failure, what + detail::callback_note(rig_.callback_error),
            "HLA rig " + rig_.h.name + ", t = " + detail::format_number(t_) + " s"};
  }

  Rig& rig_;
  HlaRigResult& out_;
  detail::Sundials su_;
  double t_ = 0.0;
  long steps_ = 0;
};

// the initial state: z0, zdot0, the pressure (given, or balancing the load at z0), no void,
// the ball at its initial lift; the modes settled on it
Status RigRun::setup() {
  const HlaRigOptions& o = rig_.opt;
  if (SUNContext_Create(nullptr, &su_.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  su_.y = N_VNew_Serial(kStates, su_.ctx);
  su_.atol = N_VNew_Serial(kStates, su_.ctx);
  su_.quad = N_VNew_Serial(kQuadratures, su_.ctx);
  if (!su_.y || !su_.atol || !su_.quad) return {StatusCode::integrator_failure, "N_VNew_Serial failed", ""};
  double* y = N_VGetArrayPointer(su_.y);
  double zddot = 0.0;
  y[0] = o.z0_mm;
  y[1] = o.zdot0_mm_per_s;
  rig_.motion(0.0, y, y[0], y[1], zddot);
  const double supply = rig_.h.supply_at(rig_.crank(0.0));
  y[2 + kHlaPressure] = o.p0_equilibrium
                            ? supply + (rig_.external(0.0) - rig_.h.spring_preload + rig_.h.spring_rate * y[0]) /
                                           rig_.h.plunger_area
                            : o.p0_MPa;
  y[2 + kHlaVoid] = 0.0;
  y[2 + kHlaBallLift] = o.ball_lift0_mm;
  y[2 + kHlaBallVelocity] = 0.0;
  rig_.mode = hla_settle_mode(rig_.h, rig_.crank(0.0), y[0], y[1], y + 2, o.ball_held);
  if (o.p0_equilibrium && !rig_.load.prescribed_motion) y[1] = quasi_static_speed(rig_, y);
  // absolute tolerances: lengths, rates, pressure, volumes
  const double atol[kStates] = {1e-10, 1e-9, 1e-10, 1e-10, 1e-10, 1e-9};
  std::copy(atol, atol + kStates, N_VGetArrayPointer(su_.atol));
  detail::use_fast_ops(su_.quad);
  N_VConst(0.0, su_.quad);
  if (!su_.create_bdf(rhs_callback, root_callback, kRoots, &rig_, o.relative_tolerance, o.max_steps, o.output_step_s))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};
  if (CVodeQuadInit(su_.cvode, quadrature_callback, su_.quad) != CV_SUCCESS ||
      CVodeQuadSStolerances(su_.cvode, o.relative_tolerance, 1e-10) != CV_SUCCESS ||
      CVodeSetQuadErrCon(su_.cvode, SUNTRUE) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (quadratures)", ""};
  return Status::success();
}

// the plunger at a travel root: on the stop while the net force presses it there
void settle_plunger(Rig& rig, double t, double* y, const int* found, std::vector<HlaRigEvent>& events) {
  if (rig.load.prescribed_motion) return;
  const auto name = [&](const char* what) {
    events.push_back({t, what, y[2 + kHlaPressure], y[2 + kHlaBallLift], y[0]});
  };
  for (int side = 0; side < 2; ++side) {
    if (found[kTravelRoot + side] == 0) continue;
    const double limit = side == 0 ? rig.h.travel_min : rig.h.travel_max;
    const double pushing = (side == 0 ? 1.0 : -1.0) * rig.net_force(t, limit, y[2 + kHlaPressure]);  // > 0: away
    if (rig.stop == PlungerStop::free) {
      y[0] = limit;
      y[1] = 0.0;
      if (pushing <= 0.0) {
        rig.stop = side == 0 ? PlungerStop::at_min : PlungerStop::at_max;
        name(side == 0 ? "plunger-min" : "plunger-max");
      }
    } else if (pushing > 0.0) {
      rig.stop = PlungerStop::free;
      name("plunger-free");
    }
  }
}

// the element's and the plunger's events; false when CVODE's root information fails
bool RigRun::on_roots(bool& ended) {
  int found[kRoots] = {};
  if (CVodeGetRootInfo(su_.cvode, found) != CV_SUCCESS) return false;
  double* y = N_VGetArrayPointer(su_.y);
  double z = 0.0, zdot = 0.0, zddot = 0.0;
  rig_.motion(t_, y, z, zdot, zddot);
  const std::uint32_t events = hla_on_root(rig_.h, rig_.crank(t_), z, zdot, y + 2, rig_.mode, found);
  if (events != 0) out_.events.push_back({t_, hla_event_names(events), y[2 + kHlaPressure], y[2 + kHlaBallLift], z});
  settle_plunger(rig_, t_, y, found, out_.events);
  if (found[kEndRoot] != 0) {
    ended = true;
    out_.stop_time_s = t_;
    out_.events.push_back({t_, "stop", y[2 + kHlaPressure], y[2 + kHlaBallLift], z});
  }
  return true;
}

// to tout through the roots; CVODE restarts at each (the state or the rates jump there)
Status RigRun::advance(double tout, bool& ended) {
  while (t_ < tout && !ended) {
    const int flag = CVode(su_.cvode, tout, su_.y, &t_, CV_NORMAL);
    if (flag < 0) return failure("CVODE failed: " + detail::cvode_flag_name(flag));
    if (flag != CV_ROOT_RETURN) continue;
    if (!on_roots(ended)) return failure("CVodeGetRootInfo failed");
    steps_ += detail::steps_since_restart(su_.cvode);
    double tq = t_;
    if (CVodeGetQuad(su_.cvode, &tq, su_.quad) != CV_SUCCESS || CVodeReInit(su_.cvode, t_, su_.y) != CV_SUCCESS ||
        CVodeQuadReInit(su_.cvode, su_.quad) != CV_SUCCESS)
      return failure("CVodeReInit failed");
    const std::string over = detail::step_budget_exceeded(steps_, static_cast<long>(out_.events.size()),
                                                          rig_.opt.max_steps, "");
    if (!over.empty()) return failure(over);
  }
  return Status::success();
}

// one output row at t_
void RigRun::record() {
  const double* y = N_VGetArrayPointer(su_.y);
  double yd[kStates];
  HlaFlows f;
  rig_.rates(t_, y, yd, &f);
  double z = 0.0, zdot = 0.0, zddot = 0.0;
  rig_.motion(t_, y, z, zdot, zddot);
  if (t_ > 0.0) {
    double tq = t_;
    CVodeGetQuad(su_.cvode, &tq, su_.quad);
  }
  const double* q = N_VGetArrayPointer(su_.quad);
  const double p = y[2 + kHlaPressure];
  out_.time_s.push_back(t_);
  out_.z_mm.push_back(z);
  out_.zdot_mm_per_s.push_back(zdot);
  out_.pressure_MPa.push_back(p);
  out_.void_mm3.push_back(y[2 + kHlaVoid]);
  out_.ball_lift_mm.push_back(rig_.mode.ball == HlaBall::seated ? 0.0 : y[2 + kHlaBallLift]);
  out_.force_N.push_back(hla_force(rig_.h, rig_.crank(t_), p, z));
  out_.supply_MPa.push_back(rig_.h.supply_at(rig_.crank(t_)));
  out_.leak_mm3_per_s.push_back(f.leak);
  out_.orifice_mm3_per_s.push_back(f.orifice);
  out_.refill_mm3_per_s.push_back(f.refill);
  out_.leak_mm3.push_back(q[0]);
  out_.orifice_mm3.push_back(q[1]);
  out_.refill_mm3.push_back(q[2]);
  out_.leak_ref_mm3.push_back(q[3]);
  out_.orifice_ref_mm3.push_back(q[4]);
  out_.refill_ref_mm3.push_back(q[5]);
}

Status RigRun::integrate() {
  const HlaRigOptions& o = rig_.opt;
  record();
  bool ended = false;
  for (long k = 1; !ended && t_ < o.duration_s; ++k) {
    const double tout = std::min(o.duration_s, static_cast<double>(k) * o.output_step_s);
    Status st = advance(tout, ended);
    if (!st.ok()) return st;
    for (double v : {N_VGetArrayPointer(su_.y)[0], N_VGetArrayPointer(su_.y)[2]})
      if (!std::isfinite(v)) return failure("non-finite state");
    record();
  }
  out_.steps = steps_ + detail::steps_since_restart(su_.cvode);
  return Status::success();
}

}  // namespace

Status run_hla_rig(const Hla& hla, const HlaRigLoad& load, const HlaRigOptions& options, HlaRigResult& out) {
  CAMOPT_THROW_UNLESS(options.duration_s > 0.0 && options.output_step_s > 0.0,
                      "HLA rig duration_s = " + format_value(options.duration_s) + " and output_step_s = " +
                          format_value(options.output_step_s) + " must be > 0");
  CAMOPT_THROW_UNLESS(load.table_time_s.size() == load.table_force_N.size(),
                      "HLA rig force table: time and force columns differ in length");
  out = HlaRigResult{};
  Rig rig{hla, load, options, {}, PlungerStop::free, {}};
  RigRun run(rig, out);
  const Status st = run.setup();
  if (!st.ok()) return st;
  return run.integrate();
}

}  // namespace camopt::dynamics
