// mode (b): stiff separable contacts integrated with CVODE (see compliant.hpp)
#include "camopt/dynamics/compliant.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <sstream>

#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"

namespace camopt::dynamics {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
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

// the integrated system; every callback returns a code, never throws
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
    return -1;  // fatal: reported by CVode's return flag with the time and state
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
    return -1;
  }
}

}  // namespace

Status run_compliant(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                     double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                     const CompliantOptions& options, CompliantResult& out) {
  CAMOPT_ASSERT(step_deg > 0 && stop_deg > start_deg && engine_rpm_value > 0);
  Problem p(mech, model, options);
  p.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  p.theta0 = start_deg * kDeg;
  p.rows = static_cast<int>(model.free_variables.size());
  p.nc = static_cast<int>(mech.connections.size());
  p.lay = PathLayout(p.rows, p.nc);
  p.f.setZero(p.rows);
  p.dq.setZero(p.rows);
  p.dv.setZero(p.rows);
  p.acc.setZero(p.rows);
  p.m.setZero(p.rows, p.rows);
  p.path.assign(static_cast<std::size_t>(p.lay.size), 0.0);
  CAMOPT_ASSERT(p.nc == p.rows);

  // tabulate the path by a monotone sweep, two grid steps beyond each end
  RigidWorkspace ws(mech, model);
  ws.kin.set_controls(controls);
  p.grid_step = std::min(options.table_step_deg, step_deg) * kDeg;
  p.grid_first = p.theta0 - 2 * p.grid_step;
  p.grid_points = static_cast<int>(std::ceil((stop_deg - start_deg) * kDeg / p.grid_step - 1e-9)) + 5;
  p.table.assign(static_cast<std::size_t>(p.grid_points) * p.lay.size, 0.0);
  // per connection: start-of-run mode (a) force and seat reaction, for the initial state
  Eigen::VectorXd lambda0(p.nc), seat0(p.nc);
  std::vector<char> open0(p.nc, 0);
  for (int i = 0; i < p.grid_points; ++i) {
    const double theta = p.grid_first + i * p.grid_step;
    const Status st = solve_rigid(mech, model, ws, theta);
    if (!st.ok()) return st;
    double* row = &p.table[static_cast<std::size_t>(i) * p.lay.size];
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
    if (i == 2) {  // theta0
      for (int c = 0; c < p.nc; ++c) {
        lambda0(c) = seat0(c) = 0.0;
        for (int j = 0; j < ws.cases(); ++j) {
          lambda0(c) += ws.case_weight(j, p.omega) * ws.force(c, j);
          seat0(c) += ws.case_weight(j, p.omega) * ws.seat(c, j);
        }
        open0[c] = model.contacts[c].is_contact && ws.kin.contacts[c].open;
      }
    }
  }
  p.evaluate(0.0);

  // stiffness, damping and seats at the start
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

  // quasi-static start: every connection carries its mode (a) force through its stiffness
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p.rows, p.rows);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(p.rows);
  for (int c = 0; c < p.nc; ++c) {
    if (open0[c]) {
      a(c, p.held_row[c]) = 1.0;
      b(c) = -seat0(c) / p.seat_k[c];
      continue;
    }
    for (int r = 0; r < p.rows; ++r) a(c, r) = p.gn(r, c);
    b(c) = model.contacts[c].is_contact ? -std::max(lambda0(c), 0.0) / p.k[c] : -lambda0(c) / p.k[c];
  }
  const Eigen::VectorXd q0 = a.partialPivLu().solve(b);

  detail::Sundials s;
  const int n = 2 * p.rows;
  if (SUNContext_Create(nullptr, &s.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  s.y = N_VNew_Serial(n, s.ctx);
  s.atol = N_VNew_Serial(n, s.ctx);
  for (int r = 0; r < p.rows; ++r) {
    NV_Ith_S(s.y, r) = q0(r);
    NV_Ith_S(s.y, p.rows + r) = 0.0;
    NV_Ith_S(s.atol, r) = options.absolute_tolerance;
    NV_Ith_S(s.atol, p.rows + r) = options.absolute_tolerance * 1e4;  // rates [per s]
  }
  if (!s.create_bdf(rhs_callback, root_callback, p.roots, &p, options.relative_tolerance, options.max_steps,
                    detail::path_max_step_s(p.grid_step, p.omega)))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};

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
  const int contact_roots = p.contact_roots;
  for (std::size_t i = 0; i < points; ++i) {
    const double deg = start_deg + step_deg * static_cast<double>(i);
    const double tout = (deg - start_deg) * kDeg / p.omega;
    while (i > 0 && t < tout) {
      const int flag = CVode(s.cvode, tout, s.y, &t, CV_NORMAL);
      if (flag == CV_ROOT_RETURN) {
        CVodeGetRootInfo(s.cvode, found.data());
        for (int r = 0; r < p.roots; ++r) {
          if (found[r] == 0) continue;
          const int c = p.unilateral[r];
          const std::string name = r < contact_roots ? mech.connections[c].name
                                                     : mech.nodes[model.contacts[c].held_node].name + " seat";
          // penetration falling through zero: the contact opens
          out.events.push_back({t, start_deg + t * p.omega / kDeg, name, found[r] < 0});
        }
        out.steps += detail::steps_since_restart(s.cvode);
        const std::string chatter = detail::step_budget_exceeded(out.steps, static_cast<long>(out.events.size()),
                                                                 options.max_steps, out.events.back().contact);
        if (!chatter.empty())
          return {StatusCode::integrator_failure, chatter,
                  "t = " + detail::format_number(t) + " s, cam " +
                      detail::format_number(start_deg + t * p.omega / kDeg) + " deg, " +
                      detail::format_number(engine_rpm_value) + " rpm"};
        if (CVodeReInit(s.cvode, t, s.y) != CV_SUCCESS)
          return {StatusCode::integrator_failure, "CVodeReInit failed", "t = " + detail::format_number(t) + " s"};
        continue;
      }
      if (flag < 0) {
        std::string state;
        for (int r = 0; r < n; ++r) state += (r ? ", " : "") + detail::format_number(NV_Ith_S(s.y, r));
        const std::string why = detail::cvode_flag_name(flag);
        return {StatusCode::integrator_failure, "CVODE failed: " + why,
                "t = " + detail::format_number(t) + " s, cam " + detail::format_number(start_deg + t * p.omega / kDeg) + " deg, state [dq; dq/dt] = [" +
                    state + "]"};
      }
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

}  // namespace camopt::dynamics
