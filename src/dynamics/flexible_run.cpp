// the flexible model's CVODE run: the callbacks (no exception crosses into SUNDIALS: each
// keeps its message in the System and returns -1) and the revolution-by-revolution
// integration with roots, lash kinks, quadratures and the periodic check (flexible_system.hpp)
#include <algorithm>
#include <memory>

#include "camopt/core/units.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

namespace {

// a root this close to a kink (in revolutions) is at the kink: the contact that the lash
// closes touches exactly there, and CVODE returns the root before the stop time
constexpr double kKinkTime = 1e-9;
// the energy quadratures: drive, gas, viscous, friction, the HLAs' work, the work of the
// springs left in the path (then two per HLA)
constexpr int kQuadratures = 6;

// the coordinates and rates, and the hydraulic state into the system
void read_state(System& s, N_Vector y, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  const double* yv = N_VGetArrayPointer(y);
  q = Eigen::Map<const Eigen::VectorXd>(yv, s.N);
  qd = Eigen::Map<const Eigen::VectorXd>(yv + s.N, s.N);
  if (s.H > 0) s.hyd = Eigen::Map<const Eigen::VectorXd>(yv + 2 * s.N, s.H);
}

int rhs_callback(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    ++s->rhs_calls;
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    double* yd = N_VGetArrayPointer(ydot);
    const double* h = yv + 2 * s->N;
    if (s->H > 0) s->hyd = Eigen::Map<const Eigen::VectorXd>(h, s->H);
    s->accelerations(yv, yv + s->N);
    std::copy(yv + s->N, yv + 2 * s->N, yd);
    std::copy(s->acc.data(), s->acc.data() + s->N, yd + s->N);
    const bool hydraulics = s->H == 0 || hydraulic_rates(*s, t, yv, yv + s->N, h, yd + 2 * s->N);
    // recoverable: CVODE retries with a smaller step
    return s->acc.allFinite() && hydraulics ? 0 : 1;
  } catch (...) {
    return keep_callback_error(s->callback_error, "right-hand side");
  }
}

// drive, gas, viscous and friction power as CVODE quadratures (outside the Newton system)
int quadrature_callback(sunrealtype t, N_Vector y, N_Vector q_dot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    if (s->H > 0) s->hyd = Eigen::Map<const Eigen::VectorXd>(yv + 2 * s->N, s->H);
    s->forces(yv, yv + s->N, true);
    double* qd = N_VGetArrayPointer(q_dot);
    qd[0] = s->fr.drive_power;
    qd[1] = s->fr.gas_power;
    qd[2] = s->fr.viscous_power;
    qd[3] = s->fr.friction_total;
    qd[4] = s->fr.hla_power;
    qd[5] = s->fr.path_spring_power;
    // the HLAs' leak and refill volumes as oil at 0 gauge: the chamber's content then changes
    // by exactly refill - leak (docs/hla.md, "Mass conservation")
    for (std::size_t k = 0; k < s->plungers.size(); ++k) {
      const HlaPoint pt = hla_point(*s, s->plungers[k], t, yv, yv + s->N, yv + 2 * s->N);
      qd[kQuadratures + 2 * k] = pt.leak_mm3_per_s / pt.volume_ratio;
      qd[kQuadratures + 2 * k + 1] = pt.refill_mm3_per_s / pt.volume_ratio;
    }
    for (int i = 0; i < kQuadratures + 2 * s->P; ++i)
      if (!std::isfinite(qd[i])) return 1;
    return 0;
  } catch (...) {
    return keep_callback_error(s->callback_error, "quadrature");
  }
}

// J = [[0, I], [-M^-1 K, -M^-1 D]] kept as K, D and M (flexible_linear.cpp)
int jacobian_callback(sunrealtype t, N_Vector y, N_Vector, SUNMatrix jac, void* data, N_Vector, N_Vector, N_Vector) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    NewtonMatrix& a = newton_content(jac);
    s->newton_matrices(yv, yv + s->N, a.k, a.d);
    s->mass_matrix(a.m);
    a.alpha = 1.0;
    a.beta = 0.0;
    ++s->jacobian_calls;
    return a.k.core.allFinite() && a.d.core.allFinite() ? 0 : 1;
  } catch (...) {
    return keep_callback_error(s->callback_error, "Jacobian");
  }
}

int root_callback(sunrealtype t, N_Vector y, sunrealtype* gout, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    const double* h = yv + 2 * s->N;
    if (s->H > 0) s->hyd = Eigen::Map<const Eigen::VectorXd>(h, s->H);
    for (std::size_t i = 0; i < s->root_list.size(); ++i) {
      const System::Root& rt = s->root_list[i];
      gout[i] = rt.kind == 3 ? hla_root_value(*s, rt, t, yv, yv + s->N, h) : s->root_value(rt, yv, yv + s->N);
    }
    return 0;
  } catch (...) {
    return keep_callback_error(s->callback_error, "root function");
  }
}


// one CVODE run of the flexible model
class Run {
 public:
  // the structured Newton solver covers the mechanical states; with hydraulic states CVODE
  // takes its dense finite-difference Jacobian
  Run(System& s, const FlexibleOptions& o, FlexibleResult& out)
      : s_(s), opt_(o), out_(out), analytic_(o.analytic_jacobian && s.H == 0) {}
  Status setup(double first_deg, double rpm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0);
  Status integrate(double start_deg, double stop_deg, double step_deg);

 private:
  Status advance(double tout);
  Status on_roots(double t);
  void on_kink(double t);
  void set_stop_time();
  Status record(std::size_t i, double deg, double tout);
  bool periodic_check();
  Status failure(const std::string& what, double t);
  bool stop_requested() const { return opt_.stop_requested && opt_.stop_requested(); }
  double cam_deg(double t) const { return first_deg_ + t * s_.omega / rad_per_deg; }

  System& s_;
  const FlexibleOptions& opt_;
  FlexibleResult& out_;
  bool analytic_ = true;
  bool state_changed_ = false;  // a root changed the state: CVODE restarts from it
  // the Newton matrix and solver outlive CVODE (declared before it: destroyed after it)
  std::unique_ptr<_generic_SUNLinearSolver, int (*)(SUNLinearSolver)> ls_{nullptr, SUNLinSolFree};
  std::unique_ptr<_generic_SUNMatrix, void (*)(SUNMatrix)> jac_{nullptr, SUNMatDestroy};
  Sundials su_;
  double first_deg_ = 0.0, rpm_ = 0.0, t_ = 0.0, window_t0_ = 0.0, report_deg0_ = 0.0;
  double last_kink_t_ = -1e-12, next_kink_t_ = 1e300;  // [s] (the start is past no kink)
  long steps_total_ = 0, events_total_ = 0;
  std::vector<int> found_;
  std::vector<double> window_start_state_;
  std::vector<FlexibleEvent> window_events_;
  Eigen::VectorXd q_, qd_;
};

Status Run::setup(double first_deg, double rpm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0) {
  first_deg_ = first_deg;
  rpm_ = rpm;
  const int N = s_.N, size = 2 * N + s_.H;
  if (SUNContext_Create(nullptr, &su_.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  su_.y = N_VNew_Serial(size, su_.ctx);
  su_.atol = N_VNew_Serial(size, su_.ctx);
  for (int i = 0; i < N; ++i) {
    NV_Ith_S(su_.y, i) = x0(i);
    NV_Ith_S(su_.y, N + i) = v0(i);
    NV_Ith_S(su_.atol, i) = opt_.absolute_tolerance;
    NV_Ith_S(su_.atol, N + i) = opt_.absolute_tolerance * 1e4;
  }
  // the hydraulic states from the static start, with their own absolute tolerances
  for (int i = 0; i < s_.H; ++i) {
    NV_Ith_S(su_.y, 2 * N + i) = s_.hyd(i);
    NV_Ith_S(su_.atol, 2 * N + i) = hydraulic_tolerance(s_, i);
  }
  su_.quad = N_VNew_Serial(kQuadratures + 2 * s_.P, su_.ctx);
  use_fast_ops(su_.quad);
  N_VConst(0.0, su_.quad);
  out_.initial_state.assign(N_VGetArrayPointer(su_.y), N_VGetArrayPointer(su_.y) + 2 * N);
  const int nroots = static_cast<int>(s_.root_list.size());
  found_.assign(std::max(nroots, 1), 0);
  if (!su_.create_bdf(rhs_callback, root_callback, nroots, &s_, opt_.relative_tolerance, opt_.max_steps,
                      path_max_step_s(2.0 * pi / std::ceil(360.0 / opt_.table_step_deg - 1e-9), s_.omega),
                      !analytic_))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};
  if (CVodeQuadInit(su_.cvode, quadrature_callback, su_.quad) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (quadratures)", ""};
  // BDF orders 3-5 are unstable for lightly damped modes near the imaginary axis (spring
  // surge at 1 %): stability-limit detection (CVODE guide, "BDF stability limit detection")
  if (CVodeSetStabLimDet(su_.cvode, SUNTRUE) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (stability limit detection)", ""};
  if (analytic_) {
    jac_.reset(make_newton_matrix(su_.ctx, s_));
    ls_.reset(make_newton_solver(su_.ctx, s_));
    if (!jac_ || !ls_ || CVodeSetLinearSolver(su_.cvode, ls_.get(), jac_.get()) != CV_SUCCESS ||
        CVodeSetJacFn(su_.cvode, jacobian_callback) != CV_SUCCESS)
      return {StatusCode::integrator_failure, "CVODE setup failed (Jacobian)", ""};
  }
  set_stop_time();
  return Status::success();
}

Status Run::failure(const std::string& what, double t) {
  out_.steps = steps_total_ + steps_since_restart(su_.cvode);
  std::string state;
  for (int i = 0; i < 2 * s_.N + s_.H; ++i) state += (i ? ", " : "") + format_number(NV_Ith_S(su_.y, i));
  return Status{StatusCode::integrator_failure, what,
                "t = " + format_number(t) + " s, cam " + format_number(cam_deg(t)) + " deg, " +
                    format_number(rpm_) + " rpm, state [x; dx/dt" + (s_.H > 0 ? "; hydraulics" : "") + "] = [" +
                    state + "]"};
}

// the next kink after the last one passed: CVODE must not step across it (the path's rates
// jump there)
void Run::set_stop_time() {
  if (s_.kinks.empty()) return;
  const double period = 2.0 * pi / s_.omega;
  next_kink_t_ = 1e300;
  for (double k : s_.kinks) {
    double tk = (k - s_.theta0) / s_.omega;
    tk -= period * std::floor((tk - last_kink_t_) / period);
    if (tk <= last_kink_t_ + kKinkTime * period) tk += period;
    next_kink_t_ = std::min(next_kink_t_, tk);
  }
  CVodeSetStopTime(su_.cvode, next_kink_t_);
}

// a kink: the piece after it becomes the active one and the deviation's rate jumps by minus
// the path's, so the bodies keep their velocities
void Run::on_kink(double t) {
  const int before = s_.piece_of(s_.theta0 + s_.omega * t);
  const int after = (before + 1) % static_cast<int>(s_.pieces.size());
  double* y = N_VGetArrayPointer(su_.y);
  for (int e = 0; e < s_.core(); ++e) y[s_.N + e] -= s_.piece_end_rate(after, 0, e) - s_.piece_end_rate(before, 1, e);
  s_.active_piece = after;
  s_.evaluated_theta = std::nan("");
}

Status Run::on_roots(double t) {
  CVodeGetRootInfo(su_.cvode, found_.data());
  s_.evaluate(t);
  read_state(s_, su_.y, q_, qd_);
  const int nroots = static_cast<int>(s_.root_list.size());
  // the HLAs' discrete states (ball, cavitation) change here; the stops need no change
  for (int r = 0, k = -1; r < nroots; ++r) {
    const System::Root& rt = s_.root_list[r];
    if (rt.kind != 3 || rt.segment != 0 || rt.index == k) continue;
    k = rt.index;
    if (found_[r] == 0 && found_[r + 1] == 0 && found_[r + 2] == 0) continue;
    double* y = N_VGetArrayPointer(su_.y);
    on_hla_roots(s_, k, &found_[r], t, y, y + s_.N, y + 2 * s_.N);
    state_changed_ = true;
  }
  int last = 0;
  for (int r = 0; r < nroots; ++r) {
    if (found_[r] == 0) continue;
    last = r;
    if (t < window_t0_ - 1e-12) continue;  // before this window's first point
    const auto& rt = s_.root_list[r];
    double speed = 0.0;
    if (rt.kind == 0) speed = std::abs(s_.penetration_rate(rt.index, qd_.data())) * 1e-3;
    if (rt.kind == 1) speed = std::abs(s_.seat_rate(s_.seats[rt.index], qd_.data())) * 1e-3;
    // penetration (coil: overlap) falling through zero: the pair opens
    window_events_.push_back({t, report_deg0_ + (t - window_t0_) * s_.omega / rad_per_deg, s_.root_name(rt), found_[r] < 0, speed});
  }
  ++events_total_;
  const std::string chatter = step_budget_exceeded(steps_total_ + steps_since_restart(su_.cvode),
                                                           events_total_, opt_.max_steps,
                                                           s_.root_name(s_.root_list[last]));
  if (!chatter.empty()) return failure(chatter, t);
  return Status::success();
}

// integrate to tout through roots and kinks; a restart at each drops the history across the
// force law's kink (contact damping switches on at touch-down)
Status Run::advance(double tout) {
  while (t_ < tout) {
    const int flag = CVode(su_.cvode, tout, su_.y, &t_, CV_NORMAL);
    if (flag < 0) return failure("CVODE failed: " + cvode_flag_name(flag) + callback_note(s_.callback_error), t_);
    const bool root = flag == CV_ROOT_RETURN;
    const bool kink = next_kink_t_ - t_ <= kKinkTime * 2.0 * pi / s_.omega;
    if (!root && !kink) continue;
    if (root) {
      const Status st = on_roots(t_);
      if (!st.ok()) return st;
    }
    if (kink) {
      on_kink(t_);
      last_kink_t_ = next_kink_t_;
    }
    if (kink || opt_.restart_at_events || state_changed_) {
      state_changed_ = false;
      steps_total_ += steps_since_restart(su_.cvode);
      long jacobians = 0;
      CVodeGetNumJacEvals(su_.cvode, &jacobians);
      out_.jacobian_evaluations += jacobians;
      double tq = t_;
      if (CVodeGetQuad(su_.cvode, &tq, su_.quad) != CV_SUCCESS || CVodeReInit(su_.cvode, t_, su_.y) != CV_SUCCESS ||
          CVodeQuadReInit(su_.cvode, su_.quad) != CV_SUCCESS)
        return failure("CVodeReInit failed", t_);
      set_stop_time();
    }
  }
  // the budget holds between events too (CVODE's own limit is per output interval)
  const std::string over = step_budget_exceeded(steps_total_ + steps_since_restart(su_.cvode),
                                                        events_total_, opt_.max_steps, "");
  return over.empty() ? Status::success() : failure(over, t_);
}

// the state at a window's start against the previous window's, in CVODE's error weights
bool Run::periodic_check() {
  bool periodic = false;
  if (!window_start_state_.empty() && opt_.periodic_tolerance > 0.0) {
    double diff = 0.0;
    for (int j = 0; j < 2 * s_.N + s_.H; ++j) {
      const double y = NV_Ith_S(su_.y, j);
      const double weight = opt_.relative_tolerance * std::abs(y) + NV_Ith_S(su_.atol, j);
      diff = std::max(diff, std::abs(y - window_start_state_[j]) / weight);
    }
    out_.periodic_difference = diff;
    periodic = diff <= opt_.periodic_tolerance;
  }
  window_start_state_.assign(N_VGetArrayPointer(su_.y), N_VGetArrayPointer(su_.y) + 2 * s_.N + s_.H);
  return periodic;
}

Status Run::record(std::size_t i, double deg, double tout) {
  s_.accelerations(q_.data(), qd_.data());
  // the linearised contact geometry's error: past the limit the result is no result
  int contact = -1;
  const double error = s_.gap_error(q_.data(), contact);
  if (error > out_.gap_error_mm) {
    out_.gap_error_mm = error;
    out_.gap_error_at_cam_deg = deg;
    out_.gap_error_contact = s_.mech.connections[contact].name;
  }
  if (error > opt_.max_gap_error_mm) return failure(s_.gap_error_message(error, contact), t_);
  const int C = s_.C, N = s_.N;
  const std::size_t nch = s_.chains.size(), ne = s_.elements.size(), nseat = s_.seats.size();
  const double scale = s_.output_angle ? 1.0 / rad_per_deg : 1.0;
  const double w = s_.omega;
  out_.cam_deg[i] = deg;
  out_.lift_kinematic[i] = s_.path[s_.L.out] * scale;
  const bool row = s_.output_row >= 0;
  out_.lift[i] = (s_.path[s_.L.out] + (row ? q_(s_.output_row) : 0.0)) * scale;
  out_.velocity[i] = (s_.path[s_.L.out1] * w + (row ? qd_(s_.output_row) : 0.0)) * scale;
  out_.acceleration[i] = (s_.path[s_.L.out2] * w * w + (row ? s_.acc(s_.output_row) : 0.0)) * scale;
  for (int c = 0; c < C; ++c) {
    out_.force[i * C + c] = s_.fr.connection[c];
    out_.friction_power[i * C + c] = s_.fr.friction_power[c] * 1e-3;  // N mm/s -> W
  }
  out_.seat_force[i] = 0.0;
  for (std::size_t k = 0; k < nseat; ++k) out_.seat_forces[i * nseat + k] = s_.fr.seat[k], out_.seat_force[i] += s_.fr.seat[k];
  out_.cam_torque[i] = s_.fr.torque;
  for (std::size_t e = 0; e < ne; ++e) out_.deformation[i * ne + e] = q_(s_.elements[e].far) - q_(s_.elements[e].near);
  for (std::size_t c = 0; c < nch; ++c) {
    out_.coil_force_top[i * nch + c] = s_.fr.coil_top[c];
    out_.coil_force_base[i * nch + c] = s_.fr.coil_base[c];
    out_.spring_static_load[i * nch + c] = s_.fr.static_load[c];
  }
  const int masses = N - s_.core();
  if (opt_.coil_displacements)
    for (int k = 0; k < masses; ++k) out_.coil_displacement[i * masses + k] = q_(s_.core() + k);
  for (int j = 0; j < N; ++j) out_.state[i * N + j] = q_(j);
  const double* h = N_VGetArrayPointer(su_.y) + 2 * N;
  for (int j = 0; j < s_.H; ++j) out_.hydraulic_state[i * s_.H + j] = h[j];
  const std::size_t np = s_.plungers.size();
  for (std::size_t k = 0; k < np; ++k) {
    const HlaPoint pt = hla_point(s_, s_.plungers[k], tout, q_.data(), qd_.data(), h);
    out_.hla_plunger[i * np + k] = pt.plunger_mm;
    out_.hla_force[i * np + k] = pt.force_N;
    out_.hla_pressure[i * np + k] = pt.pressure_MPa;
    out_.hla_ball_lift[i * np + k] = pt.ball_lift_mm;
    out_.hla_leak_flow[i * np + k] = pt.leak_mm3_per_s;
    out_.hla_refill_flow[i * np + k] = pt.refill_mm3_per_s;
  }
  if (t_ > 0.0) {  // before the first step the integrals are their initial zeros
    double tq = tout;
    CVodeGetQuad(su_.cvode, &tq, su_.quad);
  }
  out_.drive_work[i] = NV_Ith_S(su_.quad, 0);
  out_.gas_work[i] = NV_Ith_S(su_.quad, 1);
  out_.viscous_loss[i] = NV_Ith_S(su_.quad, 2);
  out_.friction_loss[i] = NV_Ith_S(su_.quad, 3);
  out_.hla_work[i] = NV_Ith_S(su_.quad, 4);
  out_.spring_work[i] = NV_Ith_S(su_.quad, 5);
  for (std::size_t k = 0; k < np; ++k) {
    out_.hla_leak_volume[i * np + k] = NV_Ith_S(su_.quad, kQuadratures + 2 * k);
    out_.hla_refill_volume[i * np + k] = NV_Ith_S(su_.quad, kQuadratures + 2 * k + 1);
  }
  out_.energy[i] = s_.energy(q_.data(), qd_.data());
  return Status::success();
}

// revolution by revolution; each records its window over the last one's (every window when
// starting from rest); at a window's start the state is compared with the previous one's
// (periodic steady state: stop, the previous window stands)
Status Run::integrate(double start_deg, double stop_deg, double step_deg) {
  const auto per_window = static_cast<std::size_t>(std::floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1;
  const double period = 2.0 * pi / s_.omega;
  const double report_t0 = (start_deg - first_deg_) * rad_per_deg / s_.omega;
  const int windows = opt_.revolutions;
  const bool all = opt_.start_at_rest;
  const std::size_t points = all ? per_window * windows : per_window;
  const int N = s_.N, C = s_.C;
  const std::size_t nch = s_.chains.size(), nseat = s_.seats.size();
  for (auto* vec : {&out_.cam_deg, &out_.lift_kinematic, &out_.lift, &out_.velocity, &out_.acceleration,
                    &out_.seat_force, &out_.cam_torque, &out_.drive_work, &out_.gas_work, &out_.viscous_loss,
                    &out_.friction_loss, &out_.hla_work, &out_.spring_work, &out_.energy})
    vec->resize(points);
  out_.force.resize(points * C);
  out_.friction_power.resize(points * C);
  out_.seat_forces.resize(points * nseat);
  out_.deformation.resize(points * s_.elements.size());
  for (auto* vec : {&out_.coil_force_top, &out_.coil_force_base, &out_.spring_static_load}) vec->resize(points * nch);
  if (opt_.coil_displacements) out_.coil_displacement.resize(points * (N - s_.core()));
  out_.state.resize(points * N);
  out_.hydraulic_state.resize(points * s_.H);
  for (auto* vec : {&out_.hla_plunger, &out_.hla_force, &out_.hla_pressure, &out_.hla_ball_lift, &out_.hla_leak_flow,
                    &out_.hla_refill_flow, &out_.hla_leak_volume, &out_.hla_refill_volume})
    vec->resize(points * s_.plungers.size());
  for (int rev = 0; rev < windows; ++rev) {
    window_t0_ = all ? report_t0 + rev * period : report_t0 - (windows - 1 - rev) * period;
    report_deg0_ = all ? start_deg + 360.0 * rev : start_deg;
    if (!all) window_events_.clear();
    for (std::size_t i = 0; i < per_window; ++i) {
      const double deg = start_deg + step_deg * static_cast<double>(i);
      const double tout = window_t0_ + (deg - start_deg) * rad_per_deg / s_.omega;
      // a caller's stop request, between output points
      if (stop_requested())
        return {StatusCode::interrupted, "stopped on request",
                "cam " + format_number(cam_deg(t_)) + " deg, " + format_number(rpm_) + " rpm"};
      Status st = advance(tout);
      if (!st.ok()) return st;
      s_.evaluate(tout);
      read_state(s_, su_.y, q_, qd_);
      if (!q_.allFinite() || !qd_.allFinite()) return failure("non-finite state", t_);
      if (i == 0) {
        if (!all && periodic_check()) {
          out_.periodic = true;
          break;
        }
        out_.start_time_s = all && rev > 0 ? out_.start_time_s : window_t0_;
        ++out_.revolutions_integrated;
      }
      st = record(all ? rev * per_window + i : i, deg + (all ? 360.0 * rev : 0.0), tout);
      if (!st.ok()) return st;
    }
    if (out_.periodic) break;
    // the events of this window up to its last point belong to it
    if (!all) out_.events = window_events_;
  }
  if (all) out_.events = window_events_;
  out_.steps = steps_total_ + steps_since_restart(su_.cvode);
  out_.rhs_evaluations = s_.rhs_calls;
  long jacobians = 0;
  CVodeGetNumJacEvals(su_.cvode, &jacobians);
  out_.jacobian_evaluations += jacobians;
  return Status::success();
}

}  // namespace

Status integrate_flexible(System& s, double first_deg, double rpm, const Eigen::VectorXd& x0,
                          const Eigen::VectorXd& v0, double start_deg, double stop_deg, double step_deg,
                          FlexibleResult& out) {
  Run run(s, s.opt, out);
  const Status st = run.setup(first_deg, rpm, x0, v0);
  if (!st.ok()) return st;
  return run.integrate(start_deg, stop_deg, step_deg);
}

}  // namespace camopt::dynamics::detail
