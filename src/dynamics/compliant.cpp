// mode (b): stiff separable contacts integrated with CVODE (see compliant.hpp)
#include "camopt/dynamics/compliant.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"

namespace camopt::dynamics {

namespace {

constexpr double kDefaultReferenceForce = 500.0;  // [N]

// the kinematic path at one cam angle, as the integrator needs it (free rows r, connections c)
struct PathLayout {
  int rows = 0, nc = 0;
  int load = 0, g_normal = 0, g_force = 0, gap = 0, held = 0, mass = 0, spring_k = 0, size = 0;
  PathLayout(int r, int c) : rows(r), nc(c) {
    g_normal = load + rows;           // rows x nc, column-major: gap gradient (links: length)
    g_force = g_normal + rows * nc;   // rows x nc: direction of the force (friction included)
    gap = g_force + rows * nc;        // nc: kinematic gap (lash)
    held = gap + nc;                  // nc: held node displacement from rest
    mass = held + nc;                 // rows x rows
    spring_k = mass + rows * rows;    // rows x rows: spring stiffness d(load)/dq
    size = spring_k + rows * rows;
  }
};

// the integrated system; every callback returns a code, never throws (an exception's message
// is kept in callback_error)
struct Problem {
  const kin::Mechanism& mech;
  const Model& model;
  const CompliantOptions& opt;
  double omega = 0.0, theta0 = 0.0;
  int rows = 0, nc = 0;
  PathLayout lay{0, 0};
  std::vector<double> table;  // points x lay.size
  double grid_first = 0.0, grid_step = 0.0;
  int grid_points = 0;
  std::vector<double> path;   // interpolated at evaluated_theta
  std::vector<double> k, damping;           // per connection
  std::vector<int> held_row;                // per connection: seat row of its held node (-1: none)
  std::vector<double> seat_sign;            // per connection: seat pushes the held variable this way
  std::vector<double> seat_k, seat_damping;
  std::vector<int> unilateral;              // root index -> connection (contacts first, then seats)
  int roots = 0, contact_roots = 0;
  Eigen::VectorXd f, dq, dv, acc;
  Eigen::MatrixXd m;
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  double evaluated_theta = std::nan("");
  long rhs_calls = 0;
  std::string callback_error;  // "<callback>: <what>" of an exception caught in a CVODE callback

  Problem(const kin::Mechanism& me, const Model& md, const CompliantOptions& o) : mech(me), model(md), opt(o) {}

  // the path at time t: Catmull-Rom cubic through the four nearest grid points
  void evaluate(double t) {
    const double theta = theta0 + omega * t;
    if (theta == evaluated_theta) return;
    evaluated_theta = theta;
    const double x = (theta - grid_first) / grid_step;
    int i = static_cast<int>(std::floor(x));
    i = std::clamp(i, 1, grid_points - 3);
    double w[4];
    detail::catmull_rom_weights(x - i, w);
    const double* p0 = &table[static_cast<std::size_t>(i - 1) * lay.size];
    const double* p1 = p0 + lay.size;
    const double* p2 = p1 + lay.size;
    const double* p3 = p2 + lay.size;
    for (int j = 0; j < lay.size; ++j) path[j] = w[0] * p0[j] + w[1] * p1[j] + w[2] * p2[j] + w[3] * p3[j];
  }

  double gn(int r, int c) const { return path[lay.g_normal + r + rows * c]; }
  double gf(int r, int c) const { return path[lay.g_force + r + rows * c]; }
  double normal_dot(int c, const Eigen::VectorXd& x) const {
    double s = 0.0;
    for (int r = 0; r < rows; ++r) s += gn(r, c) * x(r);
    return s;
  }
  // penetrations (positive: overlap) of contact c and of its seat
  double penetration(int c, const Eigen::VectorXd& q) const { return -(path[lay.gap + c] + normal_dot(c, q)); }
  double seat_penetration(int c, const Eigen::VectorXd& q) const {
    return -seat_sign[c] * (path[lay.held + c] + q(held_row[c]));
  }

  // connection force (contacts: normal force) for deviations q, rates v
  double force(int c, const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
    if (model.contacts[c].is_contact) {
      const double pen = penetration(c, q);
      if (model.contacts[c].two_sided) return k[c] * pen - damping[c] * normal_dot(c, v);  // in a slot
      if (pen <= 0.0) return 0.0;
      return std::max(0.0, k[c] * pen - damping[c] * normal_dot(c, v));
    }
    return -k[c] * normal_dot(c, q);
  }
  double seat_force(int c, const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
    const double pen = seat_penetration(c, q);
    if (pen <= 0.0) return 0.0;
    return std::max(0.0, seat_k[c] * pen - seat_damping[c] * seat_sign[c] * v(held_row[c]));
  }

  // generalized force on the free rows and the accelerations
  void accelerations(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    for (int r = 0; r < rows; ++r) {
      f(r) = -path[lay.load + r];
      for (int j = 0; j < rows; ++j) f(r) -= path[lay.spring_k + r + rows * j] * q(j);
    }
    for (int c = 0; c < nc; ++c) {
      const double fc = force(c, q, v);
      if (fc != 0.0)
        for (int r = 0; r < rows; ++r) f(r) += fc * gf(r, c);
      if (held_row[c] >= 0) f(held_row[c]) += seat_sign[c] * seat_force(c, q, v);
    }
    for (int r = 0; r < rows; ++r)
      for (int j = 0; j < rows; ++j) m(r, j) = path[lay.mass + r + rows * j];
    ldlt.compute(m);
    acc = ldlt.solve(f);
  }
};

int rhs_callback(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* p = static_cast<Problem*>(data);
  try {
    ++p->rhs_calls;
    p->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    double* yd = N_VGetArrayPointer(ydot);
    for (int r = 0; r < p->rows; ++r) {
      p->dq(r) = yv[r];
      p->dv(r) = yv[p->rows + r];
    }
    p->accelerations(p->dq, p->dv);
    for (int r = 0; r < p->rows; ++r) {
      yd[r] = p->dv(r);
      yd[p->rows + r] = p->acc(r);
    }
    return 0;
  } catch (...) {
    // fatal: reported by CVode's return flag with the time, the state and this message
    return detail::keep_callback_error(p->callback_error, "right-hand side");
  }
}

int root_callback(sunrealtype t, N_Vector y, sunrealtype* gout, void* data) {
  auto* p = static_cast<Problem*>(data);
  try {
    p->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    for (int r = 0; r < p->rows; ++r) p->dq(r) = yv[r];
    for (int i = 0; i < p->roots; ++i) {
      const int c = p->unilateral[i];
      gout[i] = i < p->contact_roots ? p->penetration(c, p->dq) : p->seat_penetration(c, p->dq);
    }
    return 0;
  } catch (...) {
    return detail::keep_callback_error(p->callback_error, "root function");
  }
}

// per connection: the mode (a) force and seat reaction at the run's first angle, and whether
// its lash gap is open there (the quasi-static start)
struct StartLoads {
  Eigen::VectorXd lambda, seat;
  std::vector<char> open;
};

// the problem's sizes and buffers for a run from start_deg at cam speed omega [rad/s]
void size_problem(Problem& p, double omega, double start_deg) {
  p.omega = omega;
  p.theta0 = start_deg * rad_per_deg;
  p.rows = static_cast<int>(p.model.free_variables.size());
  p.nc = static_cast<int>(p.mech.connections.size());
  p.lay = PathLayout(p.rows, p.nc);
  p.f.setZero(p.rows);
  p.dq.setZero(p.rows);
  p.dv.setZero(p.rows);
  p.acc.setZero(p.rows);
  p.m.setZero(p.rows, p.rows);
  p.path.assign(static_cast<std::size_t>(p.lay.size), 0.0);
  CAMOPT_ASSERT(p.nc == p.rows);
}

// one table row: what the integrator needs of the kinematic path at the workspace's angle
void fill_row(const Problem& p, const RigidWorkspace& ws, double* row) {
  const kin::Mechanism& mech = p.mech;
  const Model& model = p.model;
  for (int r = 0; r < p.rows; ++r) {
    const int v = model.free_variables[r];
    double x = 0.0;
    for (int j = 0; j < ws.cases(); ++j) x += ws.case_weight(j, p.omega) * ws.loads(v, j);
    row[p.lay.load + r] = x;
    for (int c = 0; c < p.nc; ++c) {
      const bool contact = model.contacts[c].is_contact;
      const double mu = contact && !model.contacts[c].rolling ? model.contacts[c].friction : 0.0;
      row[p.lay.g_normal + r + p.rows * c] = contact ? ws.g_normal(v, c) : ws.g(v, c);
      row[p.lay.g_force + r + p.rows * c] =
          contact ? ws.g_normal(v, c) + mu * ws.slide_sign[c] * ws.g_tangent(v, c) : ws.g(v, c);
    }
    for (int j = 0; j < p.rows; ++j) row[p.lay.mass + r + p.rows * j] = ws.mass(r, j);
  }
  for (int r = 0; r < p.rows; ++r)
    for (int j = 0; j < p.rows; ++j) row[p.lay.spring_k + r + p.rows * j] = ws.spring_stiffness(r, j);
  for (int c = 0; c < p.nc; ++c) {
    if (!model.contacts[c].is_contact) continue;
    row[p.lay.gap + c] = ws.kin.contacts[c].gap;
    const int held = model.contacts[c].held_node;
    if (held > 0) row[p.lay.held + c] = ws.kin.vars[mech.nodes[held].first_variable].value() - mech.nodes[held].rest;
  }
}

// the mode (a) force and seat reaction of every connection at the workspace's angle
void read_start_loads(const Problem& p, const RigidWorkspace& ws, StartLoads& start) {
  start.lambda.resize(p.nc);
  start.seat.resize(p.nc);
  start.open.assign(p.nc, 0);
  for (int c = 0; c < p.nc; ++c) {
    start.lambda(c) = start.seat(c) = 0.0;
    for (int j = 0; j < ws.cases(); ++j) {
      start.lambda(c) += ws.case_weight(j, p.omega) * ws.force(c, j);
      start.seat(c) += ws.case_weight(j, p.omega) * ws.seat(c, j);
    }
    start.open[c] = p.model.contacts[c].is_contact && ws.kin.contacts[c].open;
  }
}

// tabulate the path by a monotone sweep, two grid steps beyond each end
Status tabulate_path(Problem& p, RigidWorkspace& ws, double span_deg, double step_deg, StartLoads& start) {
  p.grid_step = std::min(p.opt.table_step_deg, step_deg) * rad_per_deg;
  p.grid_first = p.theta0 - 2 * p.grid_step;
  p.grid_points = static_cast<int>(std::ceil(span_deg * rad_per_deg / p.grid_step - 1e-9)) + 5;
  p.table.assign(static_cast<std::size_t>(p.grid_points) * p.lay.size, 0.0);
  for (int i = 0; i < p.grid_points; ++i) {
    const double theta = p.grid_first + i * p.grid_step;
    const Status st = solve_rigid(p.mech, p.model, ws, theta);
    if (!st.ok()) return st;
    fill_row(p, ws, &p.table[static_cast<std::size_t>(i) * p.lay.size]);
    if (i == 2) read_start_loads(p, ws, start);  // theta0
  }
  p.evaluate(0.0);
  return Status::success();
}

// contact stiffness (Hertz secant at the reference load), damping (from the contact's
// effective mass) and the compliant seats of lash contacts, at the start; links keep
// link_stiffness
Status set_stiffness(Problem& p, RigidWorkspace& ws) {
  const kin::Mechanism& mech = p.mech;
  const Model& model = p.model;
  const CompliantOptions& options = p.opt;
  Eigen::MatrixXd m0(p.rows, p.rows);
  for (int r = 0; r < p.rows; ++r)
    for (int j = 0; j < p.rows; ++j) m0(r, j) = p.path[p.lay.mass + r + p.rows * j];
  const Eigen::MatrixXd m_inv = m0.inverse();
  p.k.assign(p.nc, options.link_stiffness);
  p.damping.assign(p.nc, 0.0);
  p.held_row.assign(p.nc, -1);
  p.seat_sign.assign(p.nc, 1.0);
  p.seat_k.assign(p.nc, 0.0);
  p.seat_damping.assign(p.nc, 0.0);
  const double f_ref = options.reference_force > 0 ? options.reference_force : kDefaultReferenceForce;
  // contact curvatures and rest loads at the start
  if (const Status st = solve_rigid(mech, model, ws, p.theta0); !st.ok()) return st;
  for (int c = 0; c < p.nc; ++c) {
    const ContactData& cd = model.contacts[c];
    if (!cd.is_contact) continue;
    if (!cd.has_hertz)
      throw InputError("connection '" + mech.connections[c].name +
                       "': the compliant contact model needs materials and width_mm (Hertz stiffness)");
    const kin::ContactState& cs = ws.kin.contacts[c];
    const double curvature = cs.curvature_a + cs.curvature_b;
    const double radius = curvature > 1e-6 ? 1.0 / curvature : 1e6;  // flat on flat: a long cylinder
    p.k[c] = options.stiffness_scale * line_contact_secant_stiffness(f_ref, cd.width, cd.e_star, radius);
    Eigen::VectorXd gnc(p.rows);
    for (int r = 0; r < p.rows; ++r) gnc(r) = p.gn(r, c);
    const double inv_mass = gnc.dot(m_inv * gnc);
    const double m_c = inv_mass > 0 ? 1.0 / inv_mass : 0.0;
    p.damping[c] = cd.damping >= 0 ? cd.damping : 2.0 * options.damping_ratio * std::sqrt(p.k[c] * m_c);
    p.unilateral.push_back(c);
    if (cd.held_node > 0) {
      const int hv = mech.nodes[cd.held_node].first_variable;
      const int hr = model.row_of_variable[hv];
      p.held_row[c] = hr;
      // the seat pushes against the applied loads of the node at rest (springs, gas)
      double rest_load = 0.0;
      for (int j = 1; j < ws.damping_case(); ++j) rest_load += ws.loads(hv, j);
      p.seat_sign[c] = rest_load >= 0 ? 1.0 : -1.0;
      p.seat_k[c] = p.k[c];
      p.seat_damping[c] = 2.0 * options.damping_ratio * std::sqrt(p.seat_k[c] / m_inv(hr, hr));
    }
  }
  p.contact_roots = static_cast<int>(p.unilateral.size());
  for (int c = 0; c < p.nc; ++c)
    if (p.held_row[c] >= 0) p.unilateral.push_back(c);
  p.roots = static_cast<int>(p.unilateral.size());
  return Status::success();
}

// quasi-static start: every connection carries its mode (a) force through its stiffness, a
// contact open behind its lash puts its held node on the seat
Eigen::VectorXd quasi_static_start(const Problem& p, const StartLoads& start) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p.rows, p.rows);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(p.rows);
  for (int c = 0; c < p.nc; ++c) {
    if (start.open[c]) {
      a(c, p.held_row[c]) = 1.0;
      b(c) = -start.seat(c) / p.seat_k[c];
      continue;
    }
    for (int r = 0; r < p.rows; ++r) a(c, r) = p.gn(r, c);
    b(c) = p.model.contacts[c].is_contact ? -std::max(start.lambda(c), 0.0) / p.k[c] : -start.lambda(c) / p.k[c];
  }
  return a.partialPivLu().solve(b);
}

// CVODE on the state [dq; dq/dt], starting at (q0, 0)
Status setup_cvode(Problem& p, const Eigen::VectorXd& q0, detail::Sundials& s) {
  const int n = 2 * p.rows;
  if (SUNContext_Create(nullptr, &s.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  s.y = N_VNew_Serial(n, s.ctx);
  s.atol = N_VNew_Serial(n, s.ctx);
  for (int r = 0; r < p.rows; ++r) {
    NV_Ith_S(s.y, r) = q0(r);
    NV_Ith_S(s.y, p.rows + r) = 0.0;
    NV_Ith_S(s.atol, r) = p.opt.absolute_tolerance;
    NV_Ith_S(s.atol, p.rows + r) = p.opt.absolute_tolerance * 1e4;  // rates [per s]
  }
  if (!s.create_bdf(rhs_callback, root_callback, p.roots, &p, p.opt.relative_tolerance, p.opt.max_steps,
                    detail::path_max_step_s(p.grid_step, p.omega)))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};
  return Status::success();
}

// the events of a root return, then a restart (the force law kinks there); fails when the
// steps and events exceed the budget
Status on_roots(Problem& p, detail::Sundials& s, double t, double start_deg, double rpm, std::vector<int>& found,
                CompliantResult& out) {
  CVodeGetRootInfo(s.cvode, found.data());
  for (int r = 0; r < p.roots; ++r) {
    if (found[r] == 0) continue;
    const int c = p.unilateral[r];
    const std::string name = r < p.contact_roots ? p.mech.connections[c].name
                                                 : p.mech.nodes[p.model.contacts[c].held_node].name + " seat";
    // penetration falling through zero: the contact opens
    out.events.push_back({t, start_deg + t * p.omega / rad_per_deg, name, found[r] < 0});
  }
  out.steps += detail::steps_since_restart(s.cvode);
  const std::string chatter = detail::step_budget_exceeded(out.steps, static_cast<long>(out.events.size()),
                                                           p.opt.max_steps, out.events.back().contact);
  if (!chatter.empty())
    return {StatusCode::integrator_failure, chatter,
            "t = " + detail::format_number(t) + " s, cam " +
                detail::format_number(start_deg + t * p.omega / rad_per_deg) + " deg, " +
                detail::format_number(rpm) + " rpm"};
  if (CVodeReInit(s.cvode, t, s.y) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVodeReInit failed", "t = " + detail::format_number(t) + " s"};
  return Status::success();
}

// a failed CVode call: its flag, a callback's message, the time, cam angle and state
Status cvode_failure(const Problem& p, const detail::Sundials& s, int flag, double t, double start_deg) {
  std::string state;
  for (int r = 0; r < 2 * p.rows; ++r) state += (r ? ", " : "") + detail::format_number(NV_Ith_S(s.y, r));
  return {StatusCode::integrator_failure,
          "CVODE failed: " + detail::cvode_flag_name(flag) + detail::callback_note(p.callback_error),
          "t = " + detail::format_number(t) + " s, cam " +
              detail::format_number(start_deg + t * p.omega / rad_per_deg) + " deg, state [dq; dq/dt] = [" + state +
              "]"};
}

// integrate point by point through the contact events, recording forces and deviations
Status integrate(Problem& p, detail::Sundials& s, double start_deg, double stop_deg, double step_deg, double rpm,
                 CompliantResult& out) {
  const auto points = static_cast<std::size_t>(std::floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1;
  out = CompliantResult{};
  out.connections = p.nc;
  out.rows = p.rows;
  out.stiffness = p.k;
  out.cam_deg.resize(points);
  out.force.assign(points * p.nc, 0.0);
  out.deviation.assign(points * p.rows, 0.0);
  std::vector<int> found(static_cast<std::size_t>(std::max(p.roots, 1)));
  Eigen::VectorXd q(p.rows), v(p.rows);
  double t = 0.0;
  for (std::size_t i = 0; i < points; ++i) {
    const double deg = start_deg + step_deg * static_cast<double>(i);
    const double tout = (deg - start_deg) * rad_per_deg / p.omega;
    while (i > 0 && t < tout) {
      const int flag = CVode(s.cvode, tout, s.y, &t, CV_NORMAL);
      if (flag == CV_ROOT_RETURN) {
        if (const Status st = on_roots(p, s, t, start_deg, rpm, found, out); !st.ok()) return st;
        continue;
      }
      if (flag < 0) return cvode_failure(p, s, flag, t, start_deg);
    }
    p.evaluate(tout);
    for (int r = 0; r < p.rows; ++r) {
      q(r) = NV_Ith_S(s.y, r);
      v(r) = NV_Ith_S(s.y, p.rows + r);
    }
    out.cam_deg[i] = deg;
    for (int c = 0; c < p.nc; ++c) out.force[i * p.nc + c] = p.force(c, q, v);
    for (int r = 0; r < p.rows; ++r) out.deviation[i * p.rows + r] = q(r);
  }
  long steps = 0;
  CVodeGetNumSteps(s.cvode, &steps);
  out.steps += steps;
  out.rhs_evaluations = p.rhs_calls;
  return Status::success();
}

// "CompliantOptions::<name> = <value>" for a rule's message
std::string option(const char* name, double value) {
  return std::string("CompliantOptions::") + name + " = " + format_value(value);
}

}  // namespace

void CompliantOptions::validate() const {
  CAMOPT_THROW_UNLESS(stiffness_scale > 0, option("stiffness_scale", stiffness_scale) + " must be > 0");
  CAMOPT_THROW_UNLESS(damping_ratio >= 0, option("damping_ratio", damping_ratio) + " must be >= 0");
  CAMOPT_THROW_UNLESS(link_stiffness > 0, option("link_stiffness", link_stiffness) + " must be > 0");
  CAMOPT_THROW_UNLESS(reference_force >= 0, option("reference_force", reference_force) + " must be >= 0");
  CAMOPT_THROW_UNLESS(table_step_deg > 0, option("table_step_deg", table_step_deg) + " must be > 0");
  CAMOPT_THROW_UNLESS(relative_tolerance > 0, option("relative_tolerance", relative_tolerance) + " must be > 0");
  CAMOPT_THROW_UNLESS(absolute_tolerance > 0, option("absolute_tolerance", absolute_tolerance) + " must be > 0");
  CAMOPT_THROW_UNLESS(max_steps >= 1, option("max_steps", static_cast<double>(max_steps)) + " must be >= 1");
}

Status run_compliant(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                     double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                     const CompliantOptions& options, CompliantResult& out) {
  // the arguments and the options
  CAMOPT_THROW_UNLESS(step_deg > 0, "run_compliant: step_deg = " + format_value(step_deg) + " must be > 0");
  CAMOPT_THROW_UNLESS(stop_deg > start_deg, "run_compliant: stop_deg = " + format_value(stop_deg) +
                                                " must be > start_deg = " + format_value(start_deg));
  CAMOPT_THROW_UNLESS(engine_rpm_value > 0,
                      "run_compliant: engine_rpm_value = " + format_value(engine_rpm_value) + " must be > 0");
  options.validate();
  Problem p(mech, model, options);
  size_problem(p, cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam), start_deg);
  // the kinematic path over the run, and the mode (a) loads at its start
  RigidWorkspace ws(mech, model);
  ws.kin.set_controls(controls);
  StartLoads start;
  if (const Status st = tabulate_path(p, ws, stop_deg - start_deg, step_deg, start); !st.ok()) return st;
  // contact stiffness, damping and seats
  if (const Status st = set_stiffness(p, ws); !st.ok()) return st;
  // the quasi-static start and CVODE
  const Eigen::VectorXd q0 = quasi_static_start(p, start);
  detail::Sundials s;
  if (const Status st = setup_cvode(p, q0, s); !st.ok()) return st;
  // integrate through the contact events
  return integrate(p, s, start_deg, stop_deg, step_deg, engine_rpm_value, out);
}

}  // namespace camopt::dynamics
