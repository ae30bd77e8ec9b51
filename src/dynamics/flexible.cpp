// flexible lumped-parameter dynamics: the CVODE run, the modes and the linearisation (see
// flexible.hpp, flexible_system.hpp and docs/dynamics.md)
#include "camopt/dynamics/flexible.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <charconv>
#include <memory>
#include <numbers>

#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics {

namespace {

using detail::System;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// a root this close to a kink (in revolutions) is at the kink: the contact that the lash
// closes touches exactly there, and CVODE returns the root before the stop time
constexpr double kKinkTime = 1e-9;

void read_state(const System& s, N_Vector y, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  const double* yv = N_VGetArrayPointer(y);
  q = Eigen::Map<const Eigen::VectorXd>(yv, s.N);
  qd = Eigen::Map<const Eigen::VectorXd>(yv + s.N, s.N);
}

int rhs_callback(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    ++s->rhs_calls;
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    double* yd = N_VGetArrayPointer(ydot);
    s->accelerations(yv, yv + s->N);
    std::copy(yv + s->N, yv + 2 * s->N, yd);
    std::copy(s->acc.data(), s->acc.data() + s->N, yd + s->N);
    // recoverable: CVODE retries with a smaller step
    return s->acc.allFinite() ? 0 : 1;
  } catch (...) {
    return -1;
  }
}

// drive, gas, viscous and friction power as CVODE quadratures (outside the Newton system)
int quadrature_callback(sunrealtype t, N_Vector y, N_Vector q_dot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    s->forces(yv, yv + s->N, true);
    double* qd = N_VGetArrayPointer(q_dot);
    qd[0] = s->fr.drive_power;
    qd[1] = s->fr.gas_power;
    qd[2] = s->fr.viscous_power;
    qd[3] = s->fr.friction_total;
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(qd[i])) return 1;
    return 0;
  } catch (...) {
    return -1;
  }
}

// J = [[0, I], [-M^-1 K, -M^-1 D]] kept as K, D and M (flexible_linear.cpp)
int jacobian_callback(sunrealtype t, N_Vector y, N_Vector, SUNMatrix jac, void* data, N_Vector, N_Vector, N_Vector) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    detail::NewtonMatrix& a = detail::newton_content(jac);
    s->newton_matrices(yv, yv + s->N, a.k, a.d);
    s->mass_matrix(a.m);
    a.alpha = 1.0;
    a.beta = 0.0;
    ++s->jacobian_calls;
    return a.k.core.allFinite() && a.d.core.allFinite() ? 0 : 1;
  } catch (...) {
    return -1;
  }
}

int root_callback(sunrealtype t, N_Vector y, sunrealtype* gout, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    for (std::size_t i = 0; i < s->root_list.size(); ++i) gout[i] = s->root_value(s->root_list[i], yv, yv + s->N);
    return 0;
  } catch (...) {
    return -1;
  }
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// every law, stiffness and damping of a built system
std::vector<FlexibleParameter> describe(const System& s) {
  std::vector<FlexibleParameter> p;
  const DesignSpec& spec = s.mech.spec;
  auto add = [&](std::string key, double v, std::string unit, bool given) { p.push_back({key, shortest(v), unit, given}); };
  auto name = [&](std::string key, std::string v, bool given) { p.push_back({key, v, "", given}); };
  auto law = [&](const std::string& key, const detail::ForceLaw& l, const ContactLawSpec& ls) {
    name(key + ".law", to_string(l.law), l.law != ContactLaw::hertz);
    if (l.law == ContactLaw::linear) {
      add(key + ".stiffness", l.k, "N/mm", true);
      add(key + ".damping", l.c * 1e3, "N s/m", ls.damping_N_s_per_m.has_value());
      return;
    }
    add(key + ".length", l.length, "mm", true);
    add(key + ".e_star", l.e_star, "N/mm^2", true);
    name(key + ".damping_law", to_string(l.damping_law), ls.damping_law != ContactDampingLaw::hunt_crossley);
    if (l.damping_law == ContactDampingLaw::hunt_crossley) add(key + ".alpha", l.alpha * 1e3, "s/m", ls.restitution || ls.damping_N_s_per_m);
    else add(key + ".damping", l.c * 1e3, "N s/m", ls.damping_N_s_per_m.has_value());
  };
  for (int c = 0; c < s.C; ++c) {
    const ConnectionSpec* cs = nullptr;
    for (const ConnectionSpec& x : spec.connections)
      if (x.name == s.mech.connections[c].name) cs = &x;
    const std::string key = "connection." + s.mech.connections[c].name;
    if (s.flex.contacts[c].is_contact) {
      law(key, s.laws[c], cs->contact_law);
    } else {
      const bool angular = cs->kind == ConnectionKind::gear || cs->kind == ConnectionKind::variable_gear;
      add(key + ".stiffness", s.link_k[c], angular ? "N mm/rad" : "N/mm", cs->stiffness_N_per_mm || cs->stiffness_Nm_per_rad);
      add(key + ".damping", s.link_c[c], angular ? "N mm s/rad" : "N s/mm", cs->damping_ratio.has_value());
    }
  }
  for (const detail::Seat& st : s.seats) {
    const NodeSpec* ns = nullptr;
    for (const NodeSpec& x : spec.nodes)
      if (x.name == s.mech.nodes[st.node].name) ns = &x;
    const std::string key = "node." + ns->name + ".seat";
    add(key + ".diameter", ns->seat.diameter_mm, "mm", ns->seat.given);
    add(key + ".angle", ns->seat.angle_deg, "deg", ns->seat.given);
    add(key + ".width", ns->seat.width_mm, "mm", ns->seat.given);
    if (st.law.law == ContactLaw::hertz) add(key + ".crown_radius", st.radius, "mm", ns->seat.given);
    law(key, st.law, ns->seat.law);
  }
  for (const detail::Element& e : s.elements) {
    const std::string key = "node." + s.mech.nodes[e.node].name;
    const bool angular = s.mech.nodes[e.node].kind == NodeKind::rotational;
    add(key + ".stiffness", e.k, angular ? "N mm/rad" : "N/mm", true);
    add(key + ".damping", e.c, angular ? "N mm s/rad" : "N s/mm", e.damping_given);
    if (!e.damping_given) add(key + ".damping_ratio", e.zeta, "-", e.zeta != s.opt.component_damping_ratio);
  }
  for (const detail::Chain& ch : s.chains) {
    const std::string key = "spring." + ch.name;
    add(key + ".masses", ch.masses, "-", ch.masses > 0);
    add(key + ".damping", ch.spring_damping * 1e3, "N s/m", ch.spring_damping > 0);
    if (ch.masses > 0) add(key + ".coil_damping", ch.coil_damping * 1e3 * (ch.masses + 1), "N s/m per segment", false);
  }
  add("train_frequency", s.train_frequency_hz, "Hz", true);  // derived: the component damping's reference
  return p;
}

// one CVODE run of the flexible model
class Run {
 public:
  Run(System& s, const FlexibleOptions& o, FlexibleResult& out) : s_(s), opt_(o), out_(out) {}
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
  double cam_deg(double t) const { return first_deg_ + t * s_.omega / kDeg; }

  System& s_;
  const FlexibleOptions& opt_;
  FlexibleResult& out_;
  // the Newton matrix and solver outlive CVODE (declared before it: destroyed after it)
  std::unique_ptr<_generic_SUNLinearSolver, int (*)(SUNLinearSolver)> ls_{nullptr, SUNLinSolFree};
  std::unique_ptr<_generic_SUNMatrix, void (*)(SUNMatrix)> jac_{nullptr, SUNMatDestroy};
  detail::Sundials su_;
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
  const int N = s_.N;
  if (SUNContext_Create(nullptr, &su_.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  su_.y = N_VNew_Serial(2 * N, su_.ctx);
  su_.atol = N_VNew_Serial(2 * N, su_.ctx);
  for (int i = 0; i < N; ++i) {
    NV_Ith_S(su_.y, i) = x0(i);
    NV_Ith_S(su_.y, N + i) = v0(i);
    NV_Ith_S(su_.atol, i) = opt_.absolute_tolerance;
    NV_Ith_S(su_.atol, N + i) = opt_.absolute_tolerance * 1e4;
  }
  su_.quad = N_VNew_Serial(4, su_.ctx);
  detail::use_fast_ops(su_.quad);
  N_VConst(0.0, su_.quad);
  out_.initial_state.assign(N_VGetArrayPointer(su_.y), N_VGetArrayPointer(su_.y) + 2 * N);
  const int nroots = static_cast<int>(s_.root_list.size());
  found_.assign(std::max(nroots, 1), 0);
  if (!su_.create_bdf(rhs_callback, root_callback, nroots, &s_, opt_.relative_tolerance, opt_.max_steps,
                      detail::path_max_step_s(2.0 * kPi / std::ceil(360.0 / opt_.table_step_deg - 1e-9), s_.omega),
                      !opt_.analytic_jacobian))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};
  if (CVodeQuadInit(su_.cvode, quadrature_callback, su_.quad) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (quadratures)", ""};
  // BDF orders 3-5 are unstable for lightly damped modes near the imaginary axis (spring
  // surge at 1 %): stability-limit detection (CVODE guide, "BDF stability limit detection")
  if (CVodeSetStabLimDet(su_.cvode, SUNTRUE) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (stability limit detection)", ""};
  if (opt_.analytic_jacobian) {
    jac_.reset(detail::make_newton_matrix(su_.ctx, s_));
    ls_.reset(detail::make_newton_solver(su_.ctx, s_));
    if (!jac_ || !ls_ || CVodeSetLinearSolver(su_.cvode, ls_.get(), jac_.get()) != CV_SUCCESS ||
        CVodeSetJacFn(su_.cvode, jacobian_callback) != CV_SUCCESS)
      return {StatusCode::integrator_failure, "CVODE setup failed (Jacobian)", ""};
  }
  set_stop_time();
  return Status::success();
}

Status Run::failure(const std::string& what, double t) {
  out_.steps = steps_total_ + detail::steps_since_restart(su_.cvode);
  std::string state;
  for (int i = 0; i < 2 * s_.N; ++i) state += (i ? ", " : "") + detail::format_number(NV_Ith_S(su_.y, i));
  return Status{StatusCode::integrator_failure, what,
                "t = " + detail::format_number(t) + " s, cam " + detail::format_number(cam_deg(t)) + " deg, " +
                    detail::format_number(rpm_) + " rpm, state [x; dx/dt] = [" + state + "]"};
}

// the next kink after the last one passed: CVODE must not step across it (the path's rates
// jump there)
void Run::set_stop_time() {
  if (s_.kinks.empty()) return;
  const double period = 2.0 * kPi / s_.omega;
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
    window_events_.push_back({t, report_deg0_ + (t - window_t0_) * s_.omega / kDeg, s_.root_name(rt), found_[r] < 0, speed});
  }
  ++events_total_;
  const std::string chatter = detail::step_budget_exceeded(steps_total_ + detail::steps_since_restart(su_.cvode),
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
    if (flag < 0) return failure("CVODE failed: " + detail::cvode_flag_name(flag), t_);
    const bool root = flag == CV_ROOT_RETURN;
    const bool kink = next_kink_t_ - t_ <= kKinkTime * 2.0 * kPi / s_.omega;
    if (!root && !kink) continue;
    if (root) {
      const Status st = on_roots(t_);
      if (!st.ok()) return st;
    }
    if (kink) {
      on_kink(t_);
      last_kink_t_ = next_kink_t_;
    }
    if (kink || opt_.restart_at_events) {
      steps_total_ += detail::steps_since_restart(su_.cvode);
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
  const std::string over = detail::step_budget_exceeded(steps_total_ + detail::steps_since_restart(su_.cvode),
                                                        events_total_, opt_.max_steps, "");
  return over.empty() ? Status::success() : failure(over, t_);
}

// the state at a window's start against the previous window's, in CVODE's error weights
bool Run::periodic_check() {
  bool periodic = false;
  if (!window_start_state_.empty() && opt_.periodic_tolerance > 0.0) {
    double diff = 0.0;
    for (int j = 0; j < 2 * s_.N; ++j) {
      const double y = NV_Ith_S(su_.y, j);
      const double weight = opt_.relative_tolerance * std::abs(y) + NV_Ith_S(su_.atol, j);
      diff = std::max(diff, std::abs(y - window_start_state_[j]) / weight);
    }
    out_.periodic_difference = diff;
    periodic = diff <= opt_.periodic_tolerance;
  }
  window_start_state_.assign(N_VGetArrayPointer(su_.y), N_VGetArrayPointer(su_.y) + 2 * s_.N);
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
  const double scale = s_.output_angle ? 1.0 / kDeg : 1.0;
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
  if (t_ > 0.0) {  // before the first step the integrals are their initial zeros
    double tq = tout;
    CVodeGetQuad(su_.cvode, &tq, su_.quad);
  }
  out_.drive_work[i] = NV_Ith_S(su_.quad, 0);
  out_.gas_work[i] = NV_Ith_S(su_.quad, 1);
  out_.viscous_loss[i] = NV_Ith_S(su_.quad, 2);
  out_.friction_loss[i] = NV_Ith_S(su_.quad, 3);
  out_.energy[i] = s_.energy(q_.data(), qd_.data());
  return Status::success();
}

// revolution by revolution; each records its window over the last one's (every window when
// starting from rest); at a window's start the state is compared with the previous one's
// (periodic steady state: stop, the previous window stands)
Status Run::integrate(double start_deg, double stop_deg, double step_deg) {
  const auto per_window = static_cast<std::size_t>(std::floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1;
  const double period = 2.0 * kPi / s_.omega;
  const double report_t0 = (start_deg - first_deg_) * kDeg / s_.omega;
  const int windows = opt_.revolutions;
  const bool all = opt_.start_at_rest;
  const std::size_t points = all ? per_window * windows : per_window;
  const int N = s_.N, C = s_.C;
  const std::size_t nch = s_.chains.size(), nseat = s_.seats.size();
  for (auto* vec : {&out_.cam_deg, &out_.lift_kinematic, &out_.lift, &out_.velocity, &out_.acceleration,
                    &out_.seat_force, &out_.cam_torque, &out_.drive_work, &out_.gas_work, &out_.viscous_loss,
                    &out_.friction_loss, &out_.energy})
    vec->resize(points);
  out_.force.resize(points * C);
  out_.friction_power.resize(points * C);
  out_.seat_forces.resize(points * nseat);
  out_.deformation.resize(points * s_.elements.size());
  for (auto* vec : {&out_.coil_force_top, &out_.coil_force_base, &out_.spring_static_load}) vec->resize(points * nch);
  if (opt_.coil_displacements) out_.coil_displacement.resize(points * (N - s_.core()));
  out_.state.resize(points * N);
  for (int rev = 0; rev < windows; ++rev) {
    window_t0_ = all ? report_t0 + rev * period : report_t0 - (windows - 1 - rev) * period;
    report_deg0_ = all ? start_deg + 360.0 * rev : start_deg;
    if (!all) window_events_.clear();
    for (std::size_t i = 0; i < per_window; ++i) {
      const double deg = start_deg + step_deg * static_cast<double>(i);
      const double tout = window_t0_ + (deg - start_deg) * kDeg / s_.omega;
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
  out_.steps = steps_total_ + detail::steps_since_restart(su_.cvode);
  out_.rhs_evaluations = s_.rhs_calls;
  long jacobians = 0;
  CVodeGetNumJacEvals(su_.cvode, &jacobians);
  out_.jacobian_evaluations += jacobians;
  return Status::success();
}

}  // namespace

Status run_flexible(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                    double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                    const FlexibleOptions& options, FlexibleResult& out) {
  CAMOPT_ASSERT(step_deg > 0 && stop_deg > start_deg && engine_rpm_value > 0 && options.revolutions >= 1);
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  const double first_deg = options.start_at_rest ? start_deg : start_deg - 360.0 * (options.revolutions - 1);
  // the static start, or rest: every body still (the deviation's rate cancels the path's)
  Eigen::VectorXd x0, v0;
  {
    const Status st = detail::static_start(s, model, controls, first_deg * kDeg, x0, v0);
    if (!st.ok()) return st;
  }
  if (options.start_at_rest) {
    s.evaluate(0.0);
    for (int e = 0; e < s.N; ++e) v0(e) = -s.kinematic_rate(e);
  }
  out = FlexibleResult{};
  out.layout = {s.R, s.E, s.N - s.core()};
  out.connections = s.C;
  out.parameters = describe(s);
  for (int c = 0; c < s.C; ++c)
    out.contact_damping.push_back(s.flex.contacts[c].is_contact ? s.laws[c].damping_at(options.reference_force)
                                                                : s.link_c[c]);
  out.train_frequency_hz = s.train_frequency_hz;
  for (const detail::Element& e : s.elements) out.element_names.push_back(mech.nodes[e.node].name);
  for (const detail::Chain& ch : s.chains) out.chain_names.push_back(ch.name), out.chain_segments.push_back(ch.masses + 1);
  for (const detail::Seat& st : s.seats) out.seat_names.push_back(mech.nodes[st.node].name), out.seat_area.push_back(st.area);
  for (double k : s.kinks) {
    const double x = k / kDeg - start_deg;
    out.kink_deg.push_back(start_deg + x - 360.0 * std::floor(x / 360.0));
  }
  // integrate window by window
  Run run(s, options, out);
  Status st = run.setup(first_deg, engine_rpm_value, x0, v0);
  if (!st.ok()) return st;
  return run.integrate(start_deg, stop_deg, step_deg);
}

std::vector<FlexibleParameter> flexible_parameters(const kin::Mechanism& mech, const Model& model,
                                                   const std::vector<double>& controls, const FlexibleOptions& options) {
  System s(mech, options);
  s.omega = 0.0;
  const Status st = detail::build_system(s, model, controls, mech.spec.driver.start_deg * kDeg);
  if (!st.ok()) return {};
  return describe(s);
}

Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      FlexibleModes& out) {
  System s(mech, options);
  s.omega = 0.0;
  Eigen::VectorXd x, v;
  {
    const Status st = detail::static_start(s, model, controls, cam_deg * kDeg, x, v);
    if (!st.ok()) return st;
  }
  v.setZero();
  detail::polish_static(s, x, v, 10);
  if (release_driver_contacts) {
    s.forces(x.data(), v.data());
    for (int c = 0; c < s.C; ++c) {
      const auto& conn = mech.connections[c];
      if (conn.node_a == mech.driver_node || conn.node_b == mech.driver_node) {
        s.frozen[c] = 1;
        s.frozen_force[c] = s.fr.connection[c];
      }
    }
  }
  s.newton_matrices(x.data(), v.data(), s.jk, s.jd, true);
  s.mass_matrix(s.m);
  const Eigen::MatrixXd k = s.jk.dense(s.chains, s.N), m = s.m.dense(s.chains, s.N);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (k + k.transpose()), m);
  if (eig.info() != Eigen::Success)
    return {StatusCode::no_convergence, "the generalized eigenproblem K x = w^2 M x did not converge",
            "cam " + detail::format_number(cam_deg) + " deg"};
  out = FlexibleModes{};
  for (int r = 0; r < s.R; ++r) {
    const int var = s.flex.free_variables[r];
    int node = 0;
    for (int n = 0; n < static_cast<int>(mech.nodes.size()); ++n)
      if (mech.nodes[n].first_variable >= 0 && var >= mech.nodes[n].first_variable &&
          var < mech.nodes[n].first_variable + (mech.nodes[n].kind == NodeKind::floating ? 3 : 1))
        node = n;
    const bool floating = mech.nodes[node].kind == NodeKind::floating;
    const int sub = var - mech.nodes[node].first_variable;
    out.coordinates.push_back(mech.nodes[node].name + (floating ? std::string(sub == 0 ? ".x" : sub == 1 ? ".y" : ".phi") : ""));
    out.units.push_back(mech.nodes[node].kind == NodeKind::translational || (floating && sub < 2) ? "mm" : "rad");
  }
  for (const detail::Element& e : s.elements) {
    out.coordinates.push_back(mech.nodes[e.node].name + ".far");
    out.units.push_back(out.units[e.near]);
  }
  for (const detail::Chain& ch : s.chains)
    for (int j = 1; j <= ch.masses; ++j) out.coordinates.push_back(ch.name + ".coil" + std::to_string(j)), out.units.push_back("mm");
  const int n = s.N;
  for (int i = 0; i < n; ++i) {
    out.frequencies_hz.push_back(std::sqrt(std::max(eig.eigenvalues()(i), 0.0)) / (2 * kPi));
    Eigen::VectorXd shape = eig.eigenvectors().col(i);
    Eigen::Index big = 0;
    shape.cwiseAbs().maxCoeff(&big);
    if (shape(big) < 0) shape = -shape;
    out.shapes.insert(out.shapes.end(), shape.data(), shape.data() + n);
  }
  out.static_state.assign(x.data(), x.data() + n);
  return Status::success();
}

Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      std::vector<double>& frequencies_hz) {
  FlexibleModes modes;
  const Status st = flexible_modes(mech, model, controls, cam_deg, options, release_driver_contacts, modes);
  frequencies_hz = modes.frequencies_hz;
  return st;
}

Status flexible_linearise(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                          double engine_rpm_value, double cam_deg, const FlexibleOptions& options,
                          const std::vector<double>& q, const std::vector<double>& qd, FlexibleLinearisation& out) {
  CAMOPT_ASSERT(engine_rpm_value > 0);
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  Eigen::VectorXd x, v;
  {
    const Status st = detail::static_start(s, model, controls, cam_deg * kDeg, x, v);
    if (!st.ok()) return st;
  }
  const int n = s.N;
  if (!q.empty()) {
    CAMOPT_ASSERT(static_cast<int>(q.size()) == n);
    x = Eigen::Map<const Eigen::VectorXd>(q.data(), n);
  }
  if (!qd.empty()) {
    CAMOPT_ASSERT(static_cast<int>(qd.size()) == n);
    v = Eigen::Map<const Eigen::VectorXd>(qd.data(), n);
  }
  s.evaluate(0.0);
  s.forces(x.data(), v.data());
  s.newton_matrices(x.data(), v.data(), s.jk, s.jd);
  const Eigen::MatrixXd k = s.jk.dense(s.chains, n), d = s.jd.dense(s.chains, n);
  out.layout = {s.R, s.E, n - s.core()};
  out.q.assign(x.data(), x.data() + n);
  out.qd.assign(v.data(), v.data() + n);
  out.force.assign(s.fr.f.data(), s.fr.f.data() + n);
  out.stiffness.resize(static_cast<std::size_t>(n) * n);
  out.damping.resize(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out.stiffness[i * n + j] = k(i, j), out.damping[i * n + j] = d(i, j);
  return Status::success();
}

}  // namespace camopt::dynamics
