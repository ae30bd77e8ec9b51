// flexible lumped-parameter dynamics (see flexible.hpp and docs/dynamics.md)
#include "camopt/dynamics/flexible.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <memory>
#include <cmath>
#include <numbers>

#include "camopt/dynamics/hertz.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"

namespace camopt::dynamics {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kMilli = 1e-3;  // kg mm/s^2 -> N
using detail::format_number;

// a compliant node: near end (its mode (a) row) and far end joined by a spring-damper
struct Element {
  int node = -1, near = -1, far = -1;
  double k = 0.0, c = 0.0;  // [N/mm, N s/mm] or [N mm/rad, N mm s/rad]
};

// a compression spring as N + 1 equal segments with N internal masses (N may be 0)
struct Chain {
  std::string name;
  Spring law;           // whole-spring load law
  int node = -1, row = -1;
  int masses = 0, first = -1;  // internal masses: extended rows first .. first + masses - 1
  double mass = 0.0;           // each internal mass, generalized [N per mm/s^2]
  double segment_damping = 0.0;  // [N s/mm] on the whole-spring travel rate
  double solid_travel = -1.0;    // node travel at which the coils touch [mm]; < 0: unknown
  int table_index = -1;          // position in the path table
};

// the path table: per grid point, what the model needs of the kinematic path (free rows R,
// connections C, chains S)
struct Layout {
  int R = 0, C = 0, S = 0;
  int inertia = 0, gas, other, spring_k, vel, gn, gt, gap, curv, slide, held, gn_drv, gt_drv, load_drv, mass, xs, xs1,
      out, size;
  Layout() = default;
  Layout(int r, int c, int s) : R(r), C(c), S(s) {
    gas = inertia + R;        // R: gas load on the row [N or N mm]
    other = gas + R;          // R: remaining springs (torsion, ...)
    spring_k = other + R;     // R: their stiffness on the row
    vel = spring_k + R;       // R: dq/dtheta
    gn = vel + R;             // R x C (column-major): gap gradient (links: length)
    gt = gn + R * C;          // R x C: tangent gradient (friction)
    gap = gt + R * C;         // C: kinematic gap (lash)
    curv = gap + C;           // C: curvature sum 1/R* [1/mm]
    slide = curv + C;         // C: sliding of a over b per rad [mm/rad]
    held = slide + C;         // C: held node displacement from rest
    gn_drv = held + C;        // C: d gap / d driver
    gt_drv = gn_drv + C;      // C: tangent gradient on the driver
    load_drv = gt_drv + C;    // 1: driver load (inertia per omega^2 excluded: constant speed)
    mass = load_drv + 1;      // R x R
    xs = mass + R * R;        // S: chain node displacement [mm]
    xs1 = xs + S;             // S: its d/dtheta [mm/rad]
    out = xs1 + S;            // 1: output node displacement from rest
    size = out + 1;
  }
};

// generalized forces and everything derived from them at one state
struct Forces {
  Eigen::VectorXd f;              // extended rows
  std::vector<double> connection; // per connection
  std::vector<double> mu_eff;     // per connection: regularised friction coefficient
  std::vector<double> friction_power;  // [N mm/s]
  double seat = 0.0;              // [N]
  double torque = 0.0;            // drive torque [N mm]
  double drive_power = 0.0, gas_power = 0.0, viscous_power = 0.0, friction_total = 0.0;  // [N mm/s]
  std::vector<double> coil_top, coil_base, static_load;  // per chain [N]
};

struct System {
  const kin::Mechanism& mech;
  const FlexibleOptions& opt;
  Model flex;  // the mode (a) model without the chained springs, spring end masses on the nodes
  int R = 0, C = 0, N = 0;
  std::vector<Element> elements;
  std::vector<int> far_of_row;                 // row -> far row (-1: rigid)
  std::vector<std::vector<int>> row_map;       // per connection: row -> extended row
  std::vector<Chain> chains;
  std::vector<int> seat_row;                   // per connection: extended row of the held node (-1)
  std::vector<double> seat_sign;
  std::vector<double> damping;                 // per connection [N s/mm] (links; contacts: at reference_force)
  std::vector<double> alpha;                   // per contact: Hunt-Crossley alpha [s/mm]
  std::vector<double> seat_alpha;
  std::vector<char> frozen;                    // per connection: force held at frozen_force
  std::vector<double> frozen_force;
  std::vector<int> roots;                      // root kinds, see root_value
  int output_row = -1;
  bool output_angle = false;
  double train_frequency_hz = 0.0;

  // the path table (one revolution, periodic)
  Layout L;
  std::vector<double> table, path;
  double grid_first = 0.0, grid_step = 0.0, gap_rate_scale = 0.0;
  int grid_points = 0;
  std::vector<double> gap_slope;  // per connection: d gap / d theta at evaluated_theta
  double evaluated_theta = std::nan("");

  double omega = 0.0, theta0 = 0.0;
  Eigen::MatrixXd m;
  // m is block diagonal: the free rows' R x R block (coupled through the kinematic path),
  // then a diagonal (far ends, spring masses); factored block by block
  Eigen::LDLT<Eigen::MatrixXd> ldlt;  // R x R block
  Eigen::VectorXd inv_diagonal;       // rows R .. N - 1
  double factored_theta = std::nan("");  // angle of m and its factors
  Forces fr;
  Eigen::VectorXd x, v, acc;
  Eigen::MatrixXd jk, jd;  // Jacobian work: stiffness and damping
  long rhs_calls = 0, jacobian_calls = 0;

  System(const kin::Mechanism& me, const FlexibleOptions& o) : mech(me), opt(o) {}

  void evaluate(double t) { evaluate_angle(theta0 + omega * t); }
  void evaluate_angle(double theta) {
    if (theta == evaluated_theta) return;
    evaluated_theta = theta;
    const double xg = (theta - grid_first) / grid_step;
    const double fl = std::floor(xg);
    const double u = xg - fl;
    int i = static_cast<int>(std::fmod(fl, grid_points));
    if (i < 0) i += grid_points;
    double w[4], dw[4];
    detail::catmull_rom_weights(u, w);
    detail::catmull_rom_slopes(u, dw);
    const double* p[4];
    for (int k = 0; k < 4; ++k) {
      const int j = ((i + k - 1) % grid_points + grid_points) % grid_points;
      p[k] = &table[static_cast<std::size_t>(j) * L.size];
    }
    for (int j = 0; j < L.size; ++j) path[j] = w[0] * p[0][j] + w[1] * p[1][j] + w[2] * p[2][j] + w[3] * p[3][j];
    for (int c = 0; c < C; ++c) {
      const int j = L.gap + c;
      gap_slope[c] = (dw[0] * p[0][j] + dw[1] * p[1][j] + dw[2] * p[2][j] + dw[3] * p[3][j]) / grid_step;
    }
  }

  double gn(int r, int c) const { return path[L.gn + r + R * c]; }
  double gt(int r, int c) const { return path[L.gt + r + R * c]; }
  double reduced_radius(int c) const {
    const double k = path[L.curv + c];
    return k > 1e-6 ? 1.0 / k : 1e6;  // flat on flat: a long cylinder
  }
  double normal_dot(int c, const Eigen::VectorXd& q) const {
    double s = 0.0;
    for (int r = 0; r < R; ++r) s += gn(r, c) * q(row_map[c][r]);
    return s;
  }
  double penetration(int c, const Eigen::VectorXd& q) const { return -(path[L.gap + c] + normal_dot(c, q)); }
  double penetration_rate(int c, const Eigen::VectorXd& qd) const {
    return -(gap_slope[c] * omega + normal_dot(c, qd));
  }
  double seat_penetration(int c, const Eigen::VectorXd& q) const {
    return -seat_sign[c] * (path[L.held + c] + q(seat_row[c]));
  }
  double seat_rate(int c, const Eigen::VectorXd& qd) const {
    // the kinematic held displacement is constant while the seat can close
    return -seat_sign[c] * qd(seat_row[c]);
  }
  // Hertz forces, Newton started from each contact's last load length (per connection; the
  // seats their own): consecutive right-hand sides differ little
  mutable std::vector<double> hertz_start, seat_hertz_start;
  double hertz(int c, double pen) const {
    const ContactData& cd = flex.contacts[c];
    return opt.contact_stiffness_scale *
           line_contact_force(pen, cd.width, cd.e_star, reduced_radius(c), hertz_start[c]);
  }
  double seat_hertz(int c, double pen) const {
    return opt.contact_stiffness_scale * line_contact_force(pen, opt.seat_length_mm, flex.contacts[c].e_star,
                                                            opt.seat_radius_mm, seat_hertz_start[c]);
  }
  // chain node travel and rate
  double chain_x(const Chain& ch, const Eigen::VectorXd& q) const { return path[L.xs + ch.table_index] + q(ch.row); }
  double chain_v(const Chain& ch, const Eigen::VectorXd& qd) const {
    return path[L.xs1 + ch.table_index] * omega + qd(ch.row);
  }
  double chain_u(const Chain& ch, int j, const Eigen::VectorXd& q) const {  // j = 0 .. masses + 1
    return j == 0 ? 0.0 : j == ch.masses + 1 ? chain_x(ch, q) : q(ch.first + j - 1);
  }
  double chain_ud(const Chain& ch, int j, const Eigen::VectorXd& qd) const {
    return j == 0 ? 0.0 : j == ch.masses + 1 ? chain_v(ch, qd) : qd(ch.first + j - 1);
  }
  // kinematic velocity of an extended row [per s]
  double kinematic_rate(int e) const {
    if (e < R) return path[L.vel + e] * omega;
    if (e < R + static_cast<int>(elements.size())) return path[L.vel + elements[e - R].near] * omega;
    return 0.0;  // chain masses are absolute
  }

  // generalized forces at (q, qd) into fr; power terms too
  void forces(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    Eigen::VectorXd& f = fr.f;
    f.setZero(N);
    const double w2 = omega * omega;
    fr.viscous_power = 0.0;
    fr.friction_total = 0.0;
    fr.gas_power = 0.0;
    for (int r = 0; r < R; ++r) {
      const int far = far_of_row[r];
      const double inertia = path[L.inertia + r] * w2, gas = path[L.gas + r];
      const double applied = path[L.other + r] + path[L.spring_k + r] * q(r);
      if (far < 0) {
        f(r) = -inertia - gas - applied;
        fr.gas_power -= gas * (kinematic_rate(r) + qd(r));
      } else {
        f(r) = -0.5 * inertia - applied;
        f(far) = -0.5 * inertia - gas;
        fr.gas_power -= gas * (kinematic_rate(far) + qd(far));
      }
    }
    for (const Element& e : elements) {
      const double rate = qd(e.far) - qd(e.near);
      const double fe = e.k * (q(e.far) - q(e.near)) + e.c * rate;
      f(e.near) += fe;
      f(e.far) -= fe;
      fr.viscous_power += e.c * rate * rate;
    }
    fr.torque = path[L.load_drv];
    fr.seat = 0.0;
    for (int c = 0; c < C; ++c) {
      double fc = 0.0, mu = 0.0;
      const bool contact = flex.contacts[c].is_contact;
      if (frozen[c]) {
        fc = frozen_force[c];
      } else if (contact) {
        const double pen = penetration(c, q);
        if (pen > 0.0) {
          const double rate = penetration_rate(c, qd);
          const double elastic = hertz(c, pen);
          fc = hunt_crossley_force(elastic, rate, alpha[c]);
          fr.viscous_power += (fc - elastic) * rate;
        }
      } else {
        const double rate = normal_dot(c, qd);
        fc = -opt.link_stiffness * normal_dot(c, q) - damping[c] * rate;
        fr.viscous_power += damping[c] * rate * rate;
      }
      fr.friction_power[c] = 0.0;
      if (contact && fc > 0.0 && flex.contacts[c].friction > 0.0 && !flex.contacts[c].rolling) {
        // sliding of a over b [mm/s]: kinematic plus the deviation's (g_t . dq' = -(v_a - v_b).t)
        double sliding = path[L.slide + c] * omega;
        for (int r = 0; r < R; ++r) sliding -= gt(r, c) * qd(row_map[c][r]);
        const double v0 = opt.friction_velocity_m_per_s * 1e3;
        mu = flex.contacts[c].friction * sliding / std::sqrt(sliding * sliding + v0 * v0);
        fr.friction_power[c] = mu * fc * sliding;
        fr.friction_total += fr.friction_power[c];
      }
      fr.connection[c] = fc;
      fr.mu_eff[c] = mu;
      if (fc != 0.0) {
        for (int r = 0; r < R; ++r) f(row_map[c][r]) += fc * (gn(r, c) + mu * gt(r, c));
        fr.torque -= fc * (path[L.gn_drv + c] + mu * path[L.gt_drv + c]);
      }
      if (seat_row[c] >= 0) {
        const double pen = seat_penetration(c, q);
        if (pen > 0.0) {
          const double rate = seat_rate(c, qd);
          const double elastic = seat_hertz(c, pen);
          const double fs = hunt_crossley_force(elastic, rate, seat_alpha[c]);
          fr.viscous_power += (fs - elastic) * rate;
          f(seat_row[c]) += seat_sign[c] * fs;
          fr.seat += fs;
        }
      }
    }
    fr.drive_power = fr.torque * omega;
    for (std::size_t s = 0; s < chains.size(); ++s) {
      const Chain& ch = chains[s];
      const double n1 = ch.masses + 1.0;
      for (int j = 1; j <= ch.masses + 1; ++j) {
        const double d = n1 * (chain_u(ch, j, q) - chain_u(ch, j - 1, q));  // whole-spring travel
        const double dd = n1 * (chain_ud(ch, j, qd) - chain_ud(ch, j - 1, qd));
        double fs = ch.law.load(d) + ch.segment_damping * dd;
        fr.viscous_power += ch.segment_damping * dd * dd / n1;
        if (ch.solid_travel >= 0 && d > ch.solid_travel) {
          const double clash_rate = ch.segment_damping * 0.0;  // clash: elastic only
          fs += opt.coil_clash_stiffness * (d - ch.solid_travel) + clash_rate;
        }
        // segment j pushes u_j down and u_{j-1} up
        if (j <= ch.masses) f(ch.first + j - 1) -= fs;
        else f(ch.row) -= fs, fr.coil_top[s] = fs;
        if (j >= 2) f(ch.first + j - 2) += fs;
        else fr.coil_base[s] = fs;
      }
      fr.static_load[s] = ch.law.load(chain_x(ch, q));
    }
  }

  // tangent stiffness K = -df/dq at q (analytic: each element's law; friction and the
  // speed-dependent damping terms left out), for Newton statics and the modes
  void stiffness_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& k) const {
    k.setZero(N, N);
    for (int r = 0; r < R; ++r) k(r, r) += path[L.spring_k + r];
    for (const Element& e : elements) {
      k(e.near, e.near) += e.k;
      k(e.far, e.far) += e.k;
      k(e.near, e.far) -= e.k;
      k(e.far, e.near) -= e.k;
    }
    auto add_gradient_pair = [&](int c, double kc) {
      for (int i = 0; i < R; ++i)
        for (int j = 0; j < R; ++j) k(row_map[c][i], row_map[c][j]) += kc * gn(i, c) * gn(j, c);
    };
    for (int c = 0; c < C; ++c) {
      if (frozen[c]) continue;
      const ContactData& cd = flex.contacts[c];
      if (!cd.is_contact) {
        add_gradient_pair(c, opt.link_stiffness);
        continue;
      }
      const double pen = penetration(c, q);
      if (pen > 0.0)
        add_gradient_pair(c, opt.contact_stiffness_scale *
                                 line_contact_tangent_stiffness(hertz(c, pen) / opt.contact_stiffness_scale, cd.width,
                                                                cd.e_star, reduced_radius(c)));
      if (seat_row[c] >= 0) {
        const double sp = seat_penetration(c, q);
        if (sp > 0.0)
          k(seat_row[c], seat_row[c]) +=
              opt.contact_stiffness_scale * line_contact_tangent_stiffness(seat_hertz(c, sp) / opt.contact_stiffness_scale,
                                                                           opt.seat_length_mm, cd.e_star,
                                                                           opt.seat_radius_mm);
      }
    }
    for (const Chain& ch : chains) {
      const double n1 = ch.masses + 1.0;
      for (int j = 1; j <= ch.masses + 1; ++j) {
        const double d = n1 * (chain_u(ch, j, q) - chain_u(ch, j - 1, q));
        double ks = n1 * ch.law.stiffness(d);
        if (ch.solid_travel >= 0 && d > ch.solid_travel) ks += n1 * opt.coil_clash_stiffness;
        const int top = j == ch.masses + 1 ? ch.row : ch.first + j - 1;
        const int base = j == 1 ? -1 : ch.first + j - 2;
        k(top, top) += ks;
        if (base >= 0) {
          k(base, base) += ks;
          k(top, base) -= ks;
          k(base, top) -= ks;
        }
      }
    }
  }

  // velocity damping D = -df/d(dq/dt) at (q, qd): elements, Hunt-Crossley contacts and seats
  // (dF/d rate = 1.5 alpha F_e), links, spring segments; friction's left out (as in K)
  void damping_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& d) const {
    d.setZero(N, N);
    for (const Element& e : elements) {
      d(e.near, e.near) += e.c;
      d(e.far, e.far) += e.c;
      d(e.near, e.far) -= e.c;
      d(e.far, e.near) -= e.c;
    }
    for (int c = 0; c < C; ++c) {
      if (frozen[c]) continue;
      double dc = 0.0;
      if (!flex.contacts[c].is_contact) {
        dc = damping[c];
      } else {
        const double pen = penetration(c, q);
        if (pen > 0.0) dc = 1.5 * alpha[c] * hertz(c, pen);
      }
      if (dc != 0.0)
        for (int i = 0; i < R; ++i)
          for (int j = 0; j < R; ++j) d(row_map[c][i], row_map[c][j]) += dc * gn(i, c) * gn(j, c);
      if (seat_row[c] >= 0) {
        const double sp = seat_penetration(c, q);
        if (sp > 0.0) d(seat_row[c], seat_row[c]) += 1.5 * seat_alpha[c] * seat_hertz(c, sp);
      }
    }
    for (const Chain& ch : chains) {
      const double n1 = ch.masses + 1.0, cs = n1 * ch.segment_damping;
      for (int j = 1; j <= ch.masses + 1; ++j) {
        const int top = j == ch.masses + 1 ? ch.row : ch.first + j - 1;
        const int base = j == 1 ? -1 : ch.first + j - 2;
        d(top, top) += cs;
        if (base >= 0) {
          d(base, base) += cs;
          d(top, base) -= cs;
          d(base, top) -= cs;
        }
      }
    }
  }

  // the Newton matrices at (q, qd): K = -df/dq and D = -df/d(dq/dt) in full. Adds to K and D
  // above what they leave out: the Hunt-Crossley force F_e (1 + 1.5 alpha rate) has
  // dF/d delta = k_t (1 + 1.5 alpha rate) (K has k_t alone) and none where it is clamped at 0;
  // friction mu(v) F g_t with v = v_kin - g_t . dq': K += dF/d delta mu g_t g_n^T,
  // D += dF/d rate mu g_t g_n^T + F dmu/dv g_t g_t^T, dmu/dv = mu_c v0^2 / (v^2 + v0^2)^1.5
  void newton_matrices(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::MatrixXd& k, Eigen::MatrixXd& d) const {
    stiffness_matrix(q, k);
    damping_matrix(q, d);
    auto add_outer = [&](Eigen::MatrixXd& a, int c, double w, int left, int right) {  // 0: g_n, 1: g_t
      for (int i = 0; i < R; ++i)
        for (int j = 0; j < R; ++j)
          a(row_map[c][i], row_map[c][j]) += w * (left ? gt(i, c) : gn(i, c)) * (right ? gt(j, c) : gn(j, c));
    };
    for (int c = 0; c < C; ++c) {
      const ContactData& cd = flex.contacts[c];
      if (frozen[c] || !cd.is_contact) continue;
      const double pen = penetration(c, q);
      if (pen > 0.0) {
        const double elastic = hertz(c, pen), rate = penetration_rate(c, qd);
        const double kt = opt.contact_stiffness_scale *
                          line_contact_tangent_stiffness(elastic / opt.contact_stiffness_scale, cd.width, cd.e_star,
                                                         reduced_radius(c));
        const double fc = hunt_crossley_force(elastic, rate, alpha[c]);
        // K and D hold k_t and 1.5 alpha F_e: the clamped force has no derivative
        const double k_full = fc > 0.0 ? kt * (1.0 + 1.5 * alpha[c] * rate) : 0.0;
        const double d_full = fc > 0.0 ? 1.5 * alpha[c] * elastic : 0.0;
        add_outer(k, c, k_full - kt, 0, 0);
        add_outer(d, c, d_full - 1.5 * alpha[c] * elastic, 0, 0);
        if (fc > 0.0 && cd.friction > 0.0 && !cd.rolling) {
          double sliding = path[L.slide + c] * omega;
          for (int r = 0; r < R; ++r) sliding -= gt(r, c) * qd(row_map[c][r]);
          const double v0 = opt.friction_velocity_m_per_s * 1e3, root = std::sqrt(sliding * sliding + v0 * v0);
          const double mu = cd.friction * sliding / root, dmu = cd.friction * v0 * v0 / (root * root * root);
          add_outer(k, c, k_full * mu, 1, 0);
          add_outer(d, c, d_full * mu, 1, 0);
          add_outer(d, c, fc * dmu, 1, 1);
        }
      }
      if (seat_row[c] >= 0) {
        const double sp = seat_penetration(c, q);
        if (sp > 0.0) {
          const double elastic = seat_hertz(c, sp), rate = seat_rate(c, qd);
          const double kt = opt.contact_stiffness_scale *
                            line_contact_tangent_stiffness(elastic / opt.contact_stiffness_scale, opt.seat_length_mm,
                                                           cd.e_star, opt.seat_radius_mm);
          const bool pressed = hunt_crossley_force(elastic, rate, seat_alpha[c]) > 0.0;
          const int e = seat_row[c];
          k(e, e) += (pressed ? kt * (1.0 + 1.5 * seat_alpha[c] * rate) : 0.0) - kt;
          if (!pressed) d(e, e) -= 1.5 * seat_alpha[c] * elastic;
        }
      }
    }
  }

  // extended generalized mass
  void mass_matrix() {
    m.setZero(N, N);
    for (int r = 0; r < R; ++r)
      for (int j = 0; j < R; ++j) m(r, j) = path[L.mass + r + R * j];
    for (const Element& e : elements) {
      const double half = 0.5 * m(e.near, e.near);
      m(e.near, e.near) = half;
      m(e.far, e.far) = half;
    }
    for (const Chain& ch : chains)
      for (int j = 0; j < ch.masses; ++j) m(ch.first + j, ch.first + j) = ch.mass;
  }

  // the mass matrix depends on the cam angle only: factored once per angle (CVODE's Newton
  // iterations call the right-hand side repeatedly at one time)
  void factor_mass() {
    if (factored_theta == evaluated_theta) return;
    mass_matrix();
    ldlt.compute(m.topLeftCorner(R, R));
    inv_diagonal = m.diagonal().tail(N - R).cwiseInverse();
    factored_theta = evaluated_theta;
  }
  // b <- M^-1 b (a vector or the columns of a matrix), after factor_mass
  template <class Rows>
  void solve_mass(Rows& b) const {
    auto coupled = b.topRows(R);
    ldlt.solveInPlace(coupled);
    b.bottomRows(N - R) = inv_diagonal.asDiagonal() * b.bottomRows(N - R);
  }
  void accelerations(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    forces(q, qd);
    factor_mass();
    acc = fr.f;
    solve_mass(acc);
  }

  // root function i: contacts' penetration, seats' penetration, coil gaps
  struct Root {
    int kind;  // 0 contact, 1 seat, 2 coil
    int index, segment;
  };
  std::vector<Root> root_list;
  double root_value(const Root& rt, const Eigen::VectorXd& q) const {
    if (rt.kind == 0) return penetration(rt.index, q);
    if (rt.kind == 1) return seat_penetration(rt.index, q);
    const Chain& ch = chains[rt.index];
    const double d = (ch.masses + 1.0) * (chain_u(ch, rt.segment, q) - chain_u(ch, rt.segment - 1, q));
    return d - ch.solid_travel;  // > 0: the coils touch
  }
  std::string root_name(const Root& rt) const {
    if (rt.kind == 0) return mech.connections[rt.index].name;
    if (rt.kind == 1) return mech.nodes[flex.contacts[rt.index].held_node].name + " seat";
    return chains[rt.index].name + " coil " + std::to_string(rt.segment);
  }
};

int rhs_callback(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    ++s->rhs_calls;
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    double* yd = N_VGetArrayPointer(ydot);
    for (int i = 0; i < s->N; ++i) s->x(i) = yv[i], s->v(i) = yv[s->N + i];
    s->accelerations(s->x, s->v);
    for (int i = 0; i < s->N; ++i) yd[i] = s->v(i), yd[s->N + i] = s->acc(i);
    for (int i = 0; i < 2 * s->N; ++i)
      if (!std::isfinite(yd[i])) return 1;  // recoverable: CVODE retries with a smaller step
    return 0;
  } catch (...) {
    return -1;
  }
}

// energy bookkeeping: drive, gas, viscous and friction power as CVODE quadratures (once per
// step, outside the Newton system and the error test; as 4 extra states they made the dense
// Newton matrix 24 x 24 instead of 20 x 20 on the CVVL)
int quadrature_callback(sunrealtype t, N_Vector y, N_Vector q_dot, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    for (int i = 0; i < s->N; ++i) s->x(i) = yv[i], s->v(i) = yv[s->N + i];
    s->forces(s->x, s->v);
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

// Newton matrix for CVODE: y = [q, qd, work integrals], d(qd)/dt = M^-1 f(q, qd):
// J = [[0, I, 0], [-M^-1 K, -M^-1 D, 0], [0, 0, 0]] with the analytic K = -df/dq and
// D = -df/dqd of newton_matrices (Hunt-Crossley rate factor and friction included; until
// then they were left out, CVODE only needing an approximate Jacobian).
// The power rows are zero: the integrals feed back into nothing.
int jacobian_callback(sunrealtype t, N_Vector y, N_Vector, SUNMatrix jac, void* data, N_Vector, N_Vector, N_Vector) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    const int n = s->N;
    for (int i = 0; i < n; ++i) s->x(i) = yv[i], s->v(i) = yv[n + i];
    s->newton_matrices(s->x, s->v, s->jk, s->jd);
    s->factor_mass();
    s->solve_mass(s->jk);
    s->solve_mass(s->jd);
    SUNMatZero(jac);
    for (int i = 0; i < n; ++i) {
      SM_ELEMENT_D(jac, i, n + i) = 1.0;
      for (int j = 0; j < n; ++j) {
        SM_ELEMENT_D(jac, n + i, j) = -s->jk(i, j);
        SM_ELEMENT_D(jac, n + i, n + j) = -s->jd(i, j);
      }
    }
    ++s->jacobian_calls;
    return s->jk.allFinite() && s->jd.allFinite() ? 0 : 1;
  } catch (...) {
    return -1;
  }
}

// CVODE's Newton matrix A = I - gamma J with the analytic J above is [[I, -gamma I], [A21, A22]]
// (A21 = -gamma (-M^-1 K), A22 = I - gamma (-M^-1 D)). Its solve reduces exactly to the N x N
// Schur complement: x_q = b_q + gamma x_v, (A22 + gamma A21) x_v = b_v - A21 b_q. LU of N x N
// instead of 2N x 2N (the dense GETRF / GETRS were 26 % of the CVVL's instructions).
// The triangular solves are plain loops: Eigen's general (blocked) triangular solvers cost
// ~3x as much on a 10 x 10 system.
struct SchurSolver {
  int n = 0;
  double gamma = 0.0;
  Eigen::MatrixXd s;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  Eigen::VectorXd rhs, xv;
};
// the lower-left N x N block A21 of CVODE's 2N x 2N dense Newton matrix (column-major)
Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> lower_left(SUNMatrix a, int n) {
  return {SM_DATA_D(a) + n, n, n, Eigen::OuterStride<>(2 * n)};
}
SUNLinearSolver_Type schur_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID schur_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int schur_setup(SUNLinearSolver ls, SUNMatrix a) {
  auto* c = static_cast<SchurSolver*>(ls->content);
  const int n = c->n;
  c->gamma = -SM_ELEMENT_D(a, 0, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) c->s(i, j) = SM_ELEMENT_D(a, n + i, n + j) + c->gamma * SM_ELEMENT_D(a, n + i, j);
  c->lu.compute(c->s);
  return c->lu.matrixLU().allFinite() && c->lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 0.0 ? 0 : 1;
}
int schur_solve(SUNLinearSolver ls, SUNMatrix a, N_Vector x, N_Vector b, sunrealtype) {
  auto* c = static_cast<SchurSolver*>(ls->content);
  const int n = c->n;
  const double* bv = N_VGetArrayPointer(b);
  double* xv = N_VGetArrayPointer(x);
  const Eigen::Map<const Eigen::VectorXd> b_q(bv, n), b_v(bv + n, n);
  c->rhs.noalias() = b_v - lower_left(a, n) * b_q;
  // P S = L U: x_v = U^-1 L^-1 P rhs (L unit lower, both stored in matrixLU)
  c->xv.noalias() = c->lu.permutationP() * c->rhs;
  const Eigen::MatrixXd& lu = c->lu.matrixLU();
  double* z = c->xv.data();
  for (int i = 1; i < n; ++i)
    for (int j = 0; j < i; ++j) z[i] -= lu(i, j) * z[j];
  for (int i = n - 1; i >= 0; --i) {
    for (int j = i + 1; j < n; ++j) z[i] -= lu(i, j) * z[j];
    z[i] /= lu(i, i);
  }
  for (int i = 0; i < n; ++i) {
    xv[i] = bv[i] + c->gamma * c->xv(i);
    xv[n + i] = c->xv(i);
  }
  return 0;
}
int schur_free(SUNLinearSolver ls) {
  if (!ls) return 0;
  delete static_cast<SchurSolver*>(ls->content);
  ls->content = nullptr;
  SUNLinSolFreeEmpty(ls);
  return 0;
}
// owned by the caller (SUNLinSolFree)
SUNLinearSolver make_schur_solver(SUNContext ctx, int n) {
  SUNLinearSolver ls = SUNLinSolNewEmpty(ctx);
  if (!ls) return nullptr;
  auto* c = new SchurSolver;
  c->n = n;
  c->s.resize(n, n);
  c->rhs.resize(n);
  c->xv.resize(n);
  ls->content = c;
  ls->ops->gettype = schur_type;
  ls->ops->getid = schur_id;
  ls->ops->setup = schur_setup;
  ls->ops->solve = schur_solve;
  ls->ops->free = schur_free;
  return ls;
}

int root_callback(sunrealtype t, N_Vector y, sunrealtype* gout, void* data) {
  auto* s = static_cast<System*>(data);
  try {
    s->evaluate(t);
    const double* yv = N_VGetArrayPointer(y);
    for (int i = 0; i < s->N; ++i) s->x(i) = yv[i];
    for (std::size_t i = 0; i < s->root_list.size(); ++i) gout[i] = s->root_value(s->root_list[i], s->x);
    return 0;
  } catch (...) {
    return -1;
  }
}

// the connections that solve a node in the kinematic plan (its drive side)
std::vector<int> drive_side(const kin::Mechanism& mech, int node) {
  const int v = mech.nodes[node].first_variable;
  for (const kin::SolveStep& step : mech.plan)
    if (std::find(step.unknowns.begin(), step.unknowns.end(), v) != step.unknowns.end()) {
      std::vector<int> out;
      for (int c : step.connections)
        if (mech.connections[c].node_a == node || mech.connections[c].node_b == node) out.push_back(c);
      return out;
    }
  return {};
}

// first natural frequency [rad/s] of the train at the output's kinematic peak: every contact
// closed (lash taken up) at its tangent stiffness under reference_force, links stiff, the
// springs lumped on their nodes (surge masses left out), seats open. 0 when none is positive.
double train_frequency(System& s) {
  int peak = 0;
  for (int i = 1; i < s.grid_points; ++i)
    if (std::abs(s.table[static_cast<std::size_t>(i) * s.L.size + s.L.out]) >
        std::abs(s.table[static_cast<std::size_t>(peak) * s.L.size + s.L.out]))
      peak = i;
  s.evaluate_angle(s.grid_first + peak * s.grid_step);
  const int n = s.R + static_cast<int>(s.elements.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < s.R; ++r) k(r, r) += s.path[s.L.spring_k + r];
  for (const Element& e : s.elements) {
    k(e.near, e.near) += e.k;
    k(e.far, e.far) += e.k;
    k(e.near, e.far) -= e.k;
    k(e.far, e.near) -= e.k;
  }
  for (int c = 0; c < s.C; ++c) {
    const ContactData& cd = s.flex.contacts[c];
    const double kc = !cd.is_contact ? s.opt.link_stiffness
                                     : s.opt.contact_stiffness_scale *
                                           line_contact_tangent_stiffness(s.opt.reference_force, cd.width, cd.e_star,
                                                                          s.reduced_radius(c));
    for (int i = 0; i < s.R; ++i)
      for (int j = 0; j < s.R; ++j) k(s.row_map[c][i], s.row_map[c][j]) += kc * s.gn(i, c) * s.gn(j, c);
  }
  for (const Chain& ch : s.chains) k(ch.row, ch.row) += ch.law.stiffness(s.path[s.L.xs + ch.table_index]);
  s.mass_matrix();
  const Eigen::MatrixXd m = s.m.topLeftCorner(n, n);
  s.evaluated_theta = std::nan("");
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (k + k.transpose()), m);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) return 0.0;
  return std::sqrt(eig.eigenvalues().minCoeff());
}

// build the extended model, tabulate the path and set stiffness / damping. Throws InputError.
Status build_system(System& s, const Model& model, const std::vector<double>& controls, double theta_first,
                    Eigen::VectorXd& lambda0, Eigen::VectorXd& seat0, std::vector<char>& open0) {
  const kin::Mechanism& mech = s.mech;
  const FlexibleOptions& opt = s.opt;
  const DesignSpec& spec = mech.spec;
  s.flex = model;
  s.R = static_cast<int>(model.free_variables.size());
  s.C = static_cast<int>(mech.connections.size());
  CAMOPT_ASSERT(s.R == s.C);

  // compliant nodes
  s.far_of_row.assign(s.R, -1);
  int next = s.R;
  for (const NodeSpec& ns : spec.nodes) {
    const std::optional<double> stiffness =
        ns.torsional_stiffness_Nm_per_rad ? std::optional<double>(*ns.torsional_stiffness_Nm_per_rad * 1e3)
                                          : ns.axial_stiffness_N_per_mm;
    if (!stiffness) continue;
    const int n = mech.node_index(ns.name);
    const kin::Node& node = mech.nodes[n];
    if (node.kind == NodeKind::floating)
      throw InputError(ns.where, "node '" + ns.name +
                                     "': torsional_stiffness_Nm_per_rad on a floating node is not supported by the "
                                     "flexible model (split it into two nodes joined by a connection)");
    if (n == mech.driver_node || node.control >= 0) continue;  // a prescribed motion does not deform the train
    Element e;
    e.node = n;
    e.near = model.row_of_variable[node.first_variable];
    e.far = next++;
    e.k = *stiffness;
    s.far_of_row[e.near] = e.far;
    s.elements.push_back(e);
  }
  // springs: every compression spring becomes a chain; its end mass goes to the node
  std::vector<Spring> kept;
  int chain_masses = 0;
  for (std::size_t i = 0; i < model.springs.size(); ++i) {
    const Spring& sp = model.springs[i];
    const SpringSpec& ss = spec.springs[i];
    if (sp.kind != SpringKind::compression || mech.nodes[sp.node].control >= 0) {
      kept.push_back(sp);
      continue;
    }
    Chain ch;
    ch.name = sp.name;
    ch.law = sp;
    ch.node = sp.node;
    ch.row = model.row_of_variable[mech.nodes[sp.node].first_variable];
    ch.masses = ss.surge_masses;
    const double spring_mass = ss.mass_kg.value_or(0.0);
    if (ch.masses > 0) {
      // internal masses m/(N+1), half a segment's mass at each end; the rigid model had m/3
      s.flex.bodies[sp.node].mass += spring_mass / (2.0 * (ch.masses + 1)) - spring_mass / 3.0;
      ch.mass = kMilli * spring_mass / (ch.masses + 1);
      ch.first = next;
      next += ch.masses;
      chain_masses += ch.masses;
      // stiffness-proportional damping giving the first surge mode (fixed-fixed,
      // w1 = pi sqrt(k/m)) the ratio spring_damping_ratio: c = 2 zeta k_seg / w1
      const double rate = sp.stiffness(0.0);
      const double w1 = kPi * std::sqrt(rate / (kMilli * spring_mass));
      ch.segment_damping = 2.0 * opt.spring_damping_ratio * rate / w1;
    }
    if (ss.installed_length_mm && ss.solid_length_mm) ch.solid_travel = *ss.installed_length_mm - *ss.solid_length_mm;
    ch.table_index = static_cast<int>(s.chains.size());
    s.chains.push_back(ch);
  }
  s.flex.springs = kept;
  s.N = next;
  (void)chain_masses;

  // connection row maps: the far end takes the connections not on a node's drive side
  s.row_map.assign(s.C, std::vector<int>(s.R));
  for (int c = 0; c < s.C; ++c)
    for (int r = 0; r < s.R; ++r) s.row_map[c][r] = r;
  for (const Element& e : s.elements) {
    const std::vector<int> drive = drive_side(mech, e.node);
    for (int c = 0; c < s.C; ++c) {
      const auto& conn = mech.connections[c];
      if ((conn.node_a == e.node || conn.node_b == e.node) && std::find(drive.begin(), drive.end(), c) == drive.end())
        s.row_map[c][e.near] = e.far;
    }
  }

  // tabulate one revolution
  s.L = Layout(s.R, s.C, static_cast<int>(s.chains.size()));
  s.grid_points = static_cast<int>(std::ceil(360.0 / opt.table_step_deg - 1e-9));
  s.grid_step = 2.0 * kPi / s.grid_points;
  s.grid_first = theta_first;
  s.table.assign(static_cast<std::size_t>(s.grid_points) * s.L.size, 0.0);
  s.path.assign(s.L.size, 0.0);
  s.gap_slope.assign(s.C, 0.0);
  RigidWorkspace ws(mech, s.flex);
  ws.kin.set_controls(controls);
  const int dv = mech.driver_variable();
  const kin::Node& on = mech.nodes[mech.output_node];
  for (int i = 0; i < s.grid_points; ++i) {
    const Status st = solve_rigid(mech, s.flex, ws, theta_first + i * s.grid_step);
    if (!st.ok()) return st;
    double* row = &s.table[static_cast<std::size_t>(i) * s.L.size];
    for (int r = 0; r < s.R; ++r) {
      const int v = s.flex.free_variables[r];
      row[s.L.inertia + r] = ws.loads(v, 0);
      row[s.L.gas + r] = ws.loads(v, 1);
      for (int j = 2; j < ws.cases(); ++j) row[s.L.other + r] += ws.loads(v, j);
      row[s.L.vel + r] = ws.kin.vars[v].c[1];
      for (int c = 0; c < s.C; ++c) {
        const bool contact = s.flex.contacts[c].is_contact;
        row[s.L.gn + r + s.R * c] = contact ? ws.g_normal(v, c) : ws.g(v, c);
        row[s.L.gt + r + s.R * c] = contact ? ws.g_tangent(v, c) : 0.0;
      }
      for (int j = 0; j < s.R; ++j) row[s.L.mass + r + s.R * j] = ws.mass(r, j);
    }
    for (const Spring& sp : s.flex.springs) {
      const int v = mech.nodes[sp.node].first_variable;
      const int r = s.flex.row_of_variable[v];
      if (r >= 0) row[s.L.spring_k + r] += sp.stiffness(ws.kin.vars[v].value());
    }
    for (int c = 0; c < s.C; ++c) {
      const bool contact = s.flex.contacts[c].is_contact;
      row[s.L.gn_drv + c] = contact ? ws.g_normal(dv, c) : ws.g(dv, c);
      row[s.L.gt_drv + c] = contact ? ws.g_tangent(dv, c) : 0.0;
      if (!contact) continue;
      const kin::ContactState& cs = ws.kin.contacts[c];
      row[s.L.gap + c] = cs.gap;
      row[s.L.curv + c] = cs.curvature_a + cs.curvature_b;
      row[s.L.slide + c] = cs.sliding;
      const int held = s.flex.contacts[c].held_node;
      if (held > 0) row[s.L.held + c] = ws.kin.vars[mech.nodes[held].first_variable].value() - mech.nodes[held].rest;
    }
    row[s.L.load_drv] = 0.0;
    for (int j = 1; j < ws.cases(); ++j) row[s.L.load_drv] += ws.loads(dv, j);
    for (const Chain& ch : s.chains) {
      const auto& var = ws.kin.vars[mech.nodes[ch.node].first_variable];
      row[s.L.xs + ch.table_index] = var.value();
      row[s.L.xs1 + ch.table_index] = var.c[1];
    }
    row[s.L.out] = ws.kin.vars[on.first_variable].value() - on.rest;
  }

  // start loads: mode (a) of the full model at the first angle
  RigidWorkspace ws0(mech, model);
  ws0.kin.set_controls(controls);
  const Status st0 = solve_rigid(mech, model, ws0, theta_first);
  if (!st0.ok()) return st0;
  const double w2 = s.omega * s.omega;
  lambda0.setZero(s.C);
  seat0.setZero(s.C);
  open0.assign(s.C, 0);
  for (int c = 0; c < s.C; ++c) {
    lambda0(c) = ws0.force(c, 0) * w2;
    seat0(c) = ws0.seat(c, 0) * w2;
    for (int j = 1; j < ws0.cases(); ++j) lambda0(c) += ws0.force(c, j), seat0(c) += ws0.seat(c, j);
    open0[c] = s.flex.contacts[c].is_contact && ws0.kin.contacts[c].open;
  }

  // stiffness-based damping at the start
  s.evaluated_theta = std::nan("");
  s.theta0 = theta_first;
  s.evaluate(0.0);
  s.mass_matrix();
  CAMOPT_ASSERT(s.m.bottomLeftCorner(s.N - s.R, s.R).isZero(0.0) &&
                s.m.bottomRightCorner(s.N - s.R, s.N - s.R).isDiagonal(0.0));  // factor_mass relies on it
  const Eigen::MatrixXd m_inv = s.m.inverse();
  s.damping.assign(s.C, 0.0);
  s.seat_row.assign(s.C, -1);
  s.seat_sign.assign(s.C, 1.0);
  s.alpha.assign(s.C, 0.0);
  s.seat_alpha.assign(s.C, 0.0);
  const double alpha_default =
      hunt_crossley_alpha(opt.contact_restitution, opt.restitution_speed_m_per_s * 1e3);
  s.frozen.assign(s.C, 0);
  s.frozen_force.assign(s.C, 0.0);
  s.hertz_start.assign(s.C, 0.0);
  s.seat_hertz_start.assign(s.C, 0.0);
  s.fr.connection.assign(s.C, 0.0);
  s.fr.mu_eff.assign(s.C, 0.0);
  s.fr.friction_power.assign(s.C, 0.0);
  s.fr.coil_top.assign(s.chains.size(), 0.0);
  s.fr.coil_base.assign(s.chains.size(), 0.0);
  s.fr.static_load.assign(s.chains.size(), 0.0);
  for (int c = 0; c < s.C; ++c) {
    const ContactData& cd = s.flex.contacts[c];
    Eigen::VectorXd g = Eigen::VectorXd::Zero(s.N);
    for (int r = 0; r < s.R; ++r) g(s.row_map[c][r]) += s.gn(r, c);
    const double inv_mass = g.dot(m_inv * g);
    const double m_c = inv_mass > 0 ? 1.0 / inv_mass : 0.0;
    if (!cd.is_contact) {
      s.damping[c] = 2.0 * opt.contact_damping_ratio * std::sqrt(opt.link_stiffness * m_c);
      continue;
    }
    if (!cd.has_hertz)
      throw InputError("connection '" + mech.connections[c].name +
                       "': the flexible model needs materials and width_mm (Hertz contact law)");
    // Hunt-Crossley: a design damping c is matched at the reference force (dF/d rate = 1.5 alpha F)
    s.alpha[c] = cd.damping >= 0 ? cd.damping / (1.5 * opt.reference_force) : alpha_default;
    s.seat_alpha[c] = s.alpha[c];
    s.damping[c] = 1.5 * s.alpha[c] * opt.reference_force;
    if (cd.held_node > 0) {
      const int hv = mech.nodes[cd.held_node].first_variable;
      const int hr = s.flex.row_of_variable[hv];
      const int seat = s.far_of_row[hr] >= 0 ? s.far_of_row[hr] : hr;
      s.seat_row[c] = seat;
      double rest_load = 0.0;  // the seat pushes against the node's applied loads at rest
      for (int j = 1; j < ws0.cases(); ++j) rest_load += ws0.loads(hv, j);
      s.seat_sign[c] = rest_load >= 0 ? 1.0 : -1.0;
    }
  }
  // components: stiffness-proportional (Rayleigh) damping c = 2 zeta k / w1 gives the train's
  // first mode the ratio zeta (Clough & Penzien, Dynamics of Structures, 2nd ed., sec. 12-5).
  // (A ratio of each component's own two-half mode, c = 2 zeta sqrt(k M/4), left the CVVL's
  // 2.2 kHz train mode at ~0.7 % and it rang through the whole lift.)
  const double w1 = train_frequency(s);
  s.train_frequency_hz = w1 / (2.0 * kPi);
  s.evaluated_theta = std::nan("");
  s.evaluate(0.0);
  s.mass_matrix();
  for (Element& e : s.elements) {
    double zeta = opt.component_damping_ratio;
    for (const NodeSpec& ns : spec.nodes)
      if (ns.name == mech.nodes[e.node].name && ns.damping_ratio) zeta = *ns.damping_ratio;
    // without a train mode (no positive frequency): the ratio of the two halves' own mode (reduced mass M/4)
    e.c = w1 > 0.0 ? 2.0 * zeta * e.k / w1 : 2.0 * zeta * std::sqrt(e.k * 0.5 * s.m(e.near, e.near));
  }
  // roots
  for (int c = 0; c < s.C; ++c)
    if (s.flex.contacts[c].is_contact) s.root_list.push_back({0, c, 0});
  for (int c = 0; c < s.C; ++c)
    if (s.seat_row[c] >= 0) s.root_list.push_back({1, c, 0});
  for (std::size_t i = 0; i < s.chains.size(); ++i)
    if (s.chains[i].solid_travel >= 0)
      for (int j = 1; j <= s.chains[i].masses + 1; ++j) s.root_list.push_back({2, static_cast<int>(i), j});
  // output
  const int ov = on.first_variable;
  s.output_angle = on.kind != NodeKind::translational;
  if (ov >= 0 && s.flex.row_of_variable[ov] >= 0) {
    const int r = s.flex.row_of_variable[ov];
    s.output_row = s.far_of_row[r] >= 0 ? s.far_of_row[r] : r;
  }
  s.x.setZero(s.N);
  s.v.setZero(s.N);
  s.acc.setZero(s.N);
  return Status::success();
}

// static start: every connection carries its mode (a) force (contacts at the Hertz approach
// of that force), each element the far end's load, each chain a uniform compression
Eigen::VectorXd initial_deviation(System& s, const Eigen::VectorXd& lambda0, const Eigen::VectorXd& seat0,
                                  const std::vector<char>& open0) {
  s.evaluate(0.0);
  const int N = s.N;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(N);
  const double w2 = s.omega * s.omega;
  int eq = 0;
  for (int c = 0; c < s.C; ++c, ++eq) {
    const ContactData& cd = s.flex.contacts[c];
    if (open0[c]) {  // seat: held + x = -sign * approach
      const double pen = line_contact_approach(std::max(seat0(c), 0.0) / s.opt.contact_stiffness_scale,
                                               s.opt.seat_length_mm, cd.e_star, s.opt.seat_radius_mm);
      a(eq, s.seat_row[c]) = 1.0;
      b(eq) = -s.seat_sign[c] * pen - s.path[s.L.held + c];
      continue;
    }
    for (int r = 0; r < s.R; ++r) a(eq, s.row_map[c][r]) += s.gn(r, c);
    if (cd.is_contact)
      b(eq) = -s.path[s.L.gap + c] - line_contact_approach(std::max(lambda0(c), 0.0) / s.opt.contact_stiffness_scale,
                                                           cd.width, cd.e_star, s.reduced_radius(c));
    else
      b(eq) = -lambda0(c) / s.opt.link_stiffness;
  }
  for (const Element& e : s.elements) {
    // far-end balance: the element carries half the inertia, the gas and the far connections
    double load = -0.5 * s.path[s.L.inertia + e.near] * w2 - s.path[s.L.gas + e.near];
    for (int c = 0; c < s.C; ++c) {
      if (open0[c]) {
        if (s.seat_row[c] == e.far) load += s.seat_sign[c] * std::max(seat0(c), 0.0);
        continue;
      }
      if (s.row_map[c][e.near] == e.far) load += lambda0(c) * s.gn(e.near, c);
    }
    // k (x_far - x_near) = load
    a(eq, e.far) = e.k;
    a(eq, e.near) = -e.k;
    b(eq) = load;
    ++eq;
  }
  for (const Chain& ch : s.chains)
    for (int j = 1; j <= ch.masses; ++j, ++eq) {
      const double share = j / (ch.masses + 1.0);
      a(eq, ch.first + j - 1) = 1.0;
      a(eq, ch.row) = -share;
      b(eq) = share * s.path[s.L.xs + ch.table_index];
    }
  CAMOPT_ASSERT(eq == N);
  return a.partialPivLu().solve(b);
}

// Newton polish of the static balance f(x, v) = 0 in x with the analytic tangent stiffness;
// returns the stiffness at the result in k
void polish_static(System& s, Eigen::VectorXd& x, const Eigen::VectorXd& v, Eigen::MatrixXd& k, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    s.forces(x, v);
    s.stiffness_matrix(x, k);
    const Eigen::VectorXd dx = k.partialPivLu().solve(s.fr.f);
    if (!dx.allFinite()) break;
    x += dx;
  }
  s.stiffness_matrix(x, k);
}

// the system built at cam angle theta [rad] (s.omega set) and the state run_flexible starts
// from: the static deviation, Newton-polished when that lowers the force residual, and the
// chain masses moving with the kinematic spring compression
Status static_start(System& s, const Model& model, const std::vector<double>& controls, double theta,
                    Eigen::VectorXd& x0, Eigen::VectorXd& v0) {
  Eigen::VectorXd lambda0, seat0;
  std::vector<char> open0;
  const Status st = build_system(s, model, controls, theta, lambda0, seat0, open0);
  if (!st.ok()) return st;
  x0 = initial_deviation(s, lambda0, seat0, open0);
  v0 = Eigen::VectorXd::Zero(s.N);
  for (const Chain& ch : s.chains)
    for (int j = 1; j <= ch.masses; ++j) v0(ch.first + j - 1) = j / (ch.masses + 1.0) * s.path[s.L.xs1 + ch.table_index] * s.omega;
  {
    Eigen::MatrixXd k;
    Eigen::VectorXd xp = x0;
    polish_static(s, xp, v0, k, 3);
    s.forces(x0, v0);
    const double before = s.fr.f.norm();
    s.forces(xp, v0);
    if (xp.allFinite() && s.fr.f.norm() < before) x0 = xp;
  }
  return Status::success();
}

}  // namespace

Status run_flexible(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                    double engine_rpm_value, double start_deg, double stop_deg, double step_deg,
                    const FlexibleOptions& options, FlexibleResult& out) {
  CAMOPT_ASSERT(step_deg > 0 && stop_deg > start_deg && engine_rpm_value > 0 && options.revolutions >= 1);
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  const double first_deg = start_deg - 360.0 * (options.revolutions - 1);
  Eigen::VectorXd x0, v0;
  {
    const Status st = static_start(s, model, controls, first_deg * kDeg, x0, v0);
    if (!st.ok()) return st;
  }
  const int N = s.N;

  // declared before su: CVODE (freed with su) may still refer to it
  std::unique_ptr<_generic_SUNLinearSolver, int (*)(SUNLinearSolver)> schur(nullptr, SUNLinSolFree);
  detail::Sundials su;
  const int n = 2 * N;  // coordinates, rates (the work / loss integrals are quadratures)
  if (SUNContext_Create(nullptr, &su.ctx) != 0) return {StatusCode::integrator_failure, "SUNContext_Create failed", ""};
  su.y = N_VNew_Serial(n, su.ctx);
  su.atol = N_VNew_Serial(n, su.ctx);
  for (int i = 0; i < N; ++i) {
    NV_Ith_S(su.y, i) = x0(i);
    NV_Ith_S(su.y, N + i) = v0(i);
    NV_Ith_S(su.atol, i) = options.absolute_tolerance;
    NV_Ith_S(su.atol, N + i) = options.absolute_tolerance * 1e4;
  }
  su.quad = N_VNew_Serial(4, su.ctx);
  detail::use_fast_ops(su.quad);
  N_VConst(0.0, su.quad);
  out = FlexibleResult{};
  out.initial_state.resize(2 * N);
  for (int i = 0; i < 2 * N; ++i) out.initial_state[i] = NV_Ith_S(su.y, i);
  const int nroots = static_cast<int>(s.root_list.size());
  if (!su.create_bdf(rhs_callback, root_callback, nroots, &s, options.relative_tolerance, options.max_steps,
                     detail::path_max_step_s(s.grid_step, s.omega)))
    return {StatusCode::integrator_failure, "CVODE setup failed", ""};
  // BDF orders 3-5 are unstable for lightly damped modes near the imaginary axis (spring
  // surge at 1 %): without stability-limit detection CVODE held h w small for them whatever
  // the speed (CVVL at 10 rpm: 1.27M steps per revolution, 11.7k with it; CVODE guide,
  // "BDF stability limit detection")
  if (CVodeQuadInit(su.cvode, quadrature_callback, su.quad) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (quadratures)", ""};
  if (CVodeSetStabLimDet(su.cvode, SUNTRUE) != CV_SUCCESS)
    return {StatusCode::integrator_failure, "CVODE setup failed (stability limit detection)", ""};
  // the Schur solver relies on the analytic Jacobian's [0, I] top rows
  if (options.analytic_jacobian) {
    schur.reset(make_schur_solver(su.ctx, N));
    if (!schur || CVodeSetLinearSolver(su.cvode, schur.get(), su.a) != CV_SUCCESS ||
        CVodeSetJacFn(su.cvode, jacobian_callback) != CV_SUCCESS)
      return {StatusCode::integrator_failure, "CVODE setup failed (Jacobian)", ""};
  }

  const auto points = static_cast<std::size_t>(std::floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1;
  const double report_t0 = (start_deg - first_deg) * kDeg / s.omega;
  out.layout = {s.R, static_cast<int>(s.elements.size()), N - s.R - static_cast<int>(s.elements.size())};
  out.connections = s.C;
  out.contact_damping = s.damping;
  out.train_frequency_hz = s.train_frequency_hz;
  for (const Element& e : s.elements) out.element_names.push_back(mech.nodes[e.node].name);
  for (const Chain& ch : s.chains) out.chain_names.push_back(ch.name), out.chain_segments.push_back(ch.masses + 1);
  const std::size_t nch = s.chains.size(), ne = s.elements.size();
  out.cam_deg.resize(points);
  out.lift_kinematic.resize(points);
  out.lift.resize(points);
  out.force.resize(points * s.C);
  out.friction_power.resize(points * s.C);
  out.seat_force.resize(points);
  out.cam_torque.resize(points);
  out.deformation.resize(points * ne);
  out.coil_force_top.resize(points * nch);
  out.coil_force_base.resize(points * nch);
  out.spring_static_load.resize(points * nch);
  out.state.resize(points * N);
  for (auto* vec : {&out.drive_work, &out.gas_work, &out.viscous_loss, &out.friction_loss, &out.energy})
    vec->resize(points);

  std::vector<int> found(std::max(nroots, 1));
  Eigen::VectorXd q(N), qd(N);
  auto read_state = [&] {
    for (int i = 0; i < N; ++i) q(i) = NV_Ith_S(su.y, i), qd(i) = NV_Ith_S(su.y, N + i);
  };
  long steps_total = 0, events_total = 0;
  auto failure = [&](const std::string& what, double t) {
    out.steps = steps_total + detail::steps_since_restart(su.cvode);
    std::string state;
    for (int i = 0; i < 2 * N; ++i) state += (i ? ", " : "") + format_number(NV_Ith_S(su.y, i));
    return Status{StatusCode::integrator_failure, what,
                  "t = " + format_number(t) + " s, cam " + format_number(first_deg + t * s.omega / kDeg) +
                      " deg, " + format_number(engine_rpm_value) + " rpm, state [x; dx/dt] = [" + state + "]"};
  };
  double t = 0.0;
  auto last_root = [&](const std::vector<int>& roots_found) {
    for (int r = nroots - 1; r > 0; --r)
      if (roots_found[r] != 0) return r;
    return 0;
  };
  // revolution by revolution: each records its window (start_deg .. stop_deg) over the last
  // one's; at the start of a window the state is compared with the previous window's start
  // (periodic steady state: stop, the previous window stands)
  const double period = 2.0 * kPi / s.omega;
  std::vector<double> window_start_state;
  double window_t0 = 0.0;
  for (int rev = 0; rev < options.revolutions && !out.periodic; ++rev) {
  window_t0 = report_t0 - (options.revolutions - 1 - rev) * period;
  for (std::size_t i = 0; i < points; ++i) {
    const double deg = start_deg + step_deg * static_cast<double>(i);
    const double tout = window_t0 + (deg - start_deg) * kDeg / s.omega;
    while (t < tout) {
      const int flag = CVode(su.cvode, tout, su.y, &t, CV_NORMAL);
      if (flag == CV_ROOT_RETURN) {
        CVodeGetRootInfo(su.cvode, found.data());
        s.evaluate(t);
        read_state();
        for (int r = 0; r < nroots; ++r) {
          if (found[r] == 0 || t < window_t0 - 1e-12) continue;
          const auto& rt = s.root_list[r];
          double speed = 0.0;
          if (rt.kind == 0) speed = std::abs(s.penetration_rate(rt.index, qd)) * 1e-3;
          if (rt.kind == 1) speed = std::abs(s.seat_rate(rt.index, qd)) * 1e-3;
          // penetration (coil: overlap) falling through zero: the pair opens
          out.events.push_back({t, first_deg + t * s.omega / kDeg, s.root_name(rt), found[r] < 0, speed});
        }
        ++events_total;  // every revolution's events count towards the budget
        const std::string chatter = detail::step_budget_exceeded(
            steps_total + detail::steps_since_restart(su.cvode), events_total, options.max_steps,
            s.root_name(s.root_list[last_root(found)]));
        if (!chatter.empty()) return failure(chatter, t);
        // a restart drops the history across the force law's kink (contact damping switches
        // on at touch-down); without it CVODE cuts its step through the kink instead
        if (options.restart_at_events) {
          steps_total += detail::steps_since_restart(su.cvode);
          long jacobians = 0;
          CVodeGetNumJacEvals(su.cvode, &jacobians);
          out.jacobian_evaluations += jacobians;
          double tq = t;
          if (CVodeGetQuad(su.cvode, &tq, su.quad) != CV_SUCCESS || CVodeReInit(su.cvode, t, su.y) != CV_SUCCESS ||
              CVodeQuadReInit(su.cvode, su.quad) != CV_SUCCESS)
            return failure("CVodeReInit failed", t);
        }
        continue;
      }
      if (flag < 0) return failure("CVODE failed: " + detail::cvode_flag_name(flag), t);
    }
    {  // the budget holds between events too (CVODE's own limit is per output interval)
      const std::string over = detail::step_budget_exceeded(steps_total + detail::steps_since_restart(su.cvode),
                                                            events_total, options.max_steps, "");
      if (!over.empty()) return failure(over, t);
    }
    s.evaluate(tout);
    read_state();
    if (!q.allFinite() || !qd.allFinite()) return failure("non-finite state", t);
    if (i == 0) {
      // in units of the integration tolerance, CVODE's weights rtol |y| + atol
      if (!window_start_state.empty() && options.periodic_tolerance > 0.0) {
        double diff = 0.0;
        for (int j = 0; j < 2 * N; ++j) {
          const double y = NV_Ith_S(su.y, j);
          const double weight = options.relative_tolerance * std::abs(y) + NV_Ith_S(su.atol, j);
          diff = std::max(diff, std::abs(y - window_start_state[j]) / weight);
        }
        out.periodic_difference = diff;
        if (diff <= options.periodic_tolerance) {
          out.periodic = true;
          break;
        }
      }
      window_start_state.assign(N_VGetArrayPointer(su.y), N_VGetArrayPointer(su.y) + 2 * N);
      out.events.erase(std::remove_if(out.events.begin(), out.events.end(),
                                      [&](const FlexibleEvent& e) { return e.time_s < window_t0 - 1e-12; }),
                       out.events.end());
      out.start_time_s = window_t0;
      ++out.revolutions_integrated;
    }
    s.forces(q, qd);
    s.mass_matrix();
    out.cam_deg[i] = deg;
    const double scale = s.output_angle ? 1.0 / kDeg : 1.0;
    out.lift_kinematic[i] = s.path[s.L.out] * scale;
    out.lift[i] = (s.path[s.L.out] + (s.output_row >= 0 ? q(s.output_row) : 0.0)) * scale;
    for (int c = 0; c < s.C; ++c) {
      out.force[i * s.C + c] = s.fr.connection[c];
      out.friction_power[i * s.C + c] = s.fr.friction_power[c] * 1e-3;  // N mm/s -> W
    }
    out.seat_force[i] = s.fr.seat;
    out.cam_torque[i] = s.fr.torque;
    for (std::size_t e = 0; e < ne; ++e)
      out.deformation[i * ne + e] = q(s.elements[e].far) - q(s.elements[e].near);
    for (std::size_t c = 0; c < nch; ++c) {
      out.coil_force_top[i * nch + c] = s.fr.coil_top[c];
      out.coil_force_base[i * nch + c] = s.fr.coil_base[c];
      out.spring_static_load[i * nch + c] = s.fr.static_load[c];
    }
    for (int j = 0; j < N; ++j) out.state[i * N + j] = q(j);
    if (t > 0.0) {  // before the first step the integrals are their initial zeros
      double tq = tout;
      if (CVodeGetQuad(su.cvode, &tq, su.quad) != CV_SUCCESS) return failure("CVodeGetQuad failed", t);
    }
    out.drive_work[i] = NV_Ith_S(su.quad, 0);
    out.gas_work[i] = NV_Ith_S(su.quad, 1);
    out.viscous_loss[i] = NV_Ith_S(su.quad, 2);
    out.friction_loss[i] = NV_Ith_S(su.quad, 3);
    // energy: kinetic of the true motion + elastic
    Eigen::VectorXd vel(N);
    for (int j = 0; j < N; ++j) vel(j) = s.kinematic_rate(j) + qd(j);
    double energy = 0.5 * vel.dot(s.m * vel);
    for (const Element& e : s.elements) energy += 0.5 * e.k * std::pow(q(e.far) - q(e.near), 2);
    for (int c = 0; c < s.C; ++c) {
      const ContactData& cd = s.flex.contacts[c];
      if (cd.is_contact) {
        const double pen = s.penetration(c, q);
        if (pen > 0)
          energy += options.contact_stiffness_scale *
                    line_contact_energy(s.hertz(c, pen) / options.contact_stiffness_scale, cd.width, cd.e_star,
                                        s.reduced_radius(c));
        if (s.seat_row[c] >= 0) {
          const double sp = s.seat_penetration(c, q);
          if (sp > 0)
            energy += options.contact_stiffness_scale *
                      line_contact_energy(s.seat_hertz(c, sp) / options.contact_stiffness_scale,
                                          options.seat_length_mm, cd.e_star, options.seat_radius_mm);
        }
      } else {
        energy += 0.5 * options.link_stiffness * std::pow(s.normal_dot(c, q), 2);
      }
    }
    for (const Chain& ch : s.chains) {
      const double n1 = ch.masses + 1.0;
      for (int j = 1; j <= ch.masses + 1; ++j) {
        const double d = n1 * (s.chain_u(ch, j, q) - s.chain_u(ch, j - 1, q));
        energy += ch.law.energy(d) / n1;
        if (ch.solid_travel >= 0 && d > ch.solid_travel)
          energy += 0.5 * options.coil_clash_stiffness * std::pow(d - ch.solid_travel, 2) / n1;
      }
    }
    out.energy[i] = energy;
  }
  }
  out.steps = steps_total + detail::steps_since_restart(su.cvode);
  out.rhs_evaluations = s.rhs_calls;
  long jacobians = 0;
  CVodeGetNumJacEvals(su.cvode, &jacobians);
  out.jacobian_evaluations += jacobians;
  return Status::success();
}

Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      std::vector<double>& frequencies_hz) {
  System s(mech, options);
  s.omega = 0.0;
  Eigen::VectorXd lambda0, seat0;
  std::vector<char> open0;
  {
    const Status st = build_system(s, model, controls, cam_deg * kDeg, lambda0, seat0, open0);
    if (!st.ok()) return st;
  }
  Eigen::VectorXd x = initial_deviation(s, lambda0, seat0, open0);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(s.N);
  Eigen::MatrixXd k;
  polish_static(s, x, v, k, 4);
  if (release_driver_contacts) {
    s.forces(x, v);
    for (int c = 0; c < s.C; ++c) {
      const auto& conn = mech.connections[c];
      if (conn.node_a == mech.driver_node || conn.node_b == mech.driver_node) {
        s.frozen[c] = 1;
        s.frozen_force[c] = s.fr.connection[c];
      }
    }
    polish_static(s, x, v, k, 0);
  }
  s.mass_matrix();
  const Eigen::MatrixXd ks = 0.5 * (k + k.transpose());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(ks, s.m);
  if (eig.info() != Eigen::Success)
    return {StatusCode::no_convergence, "the generalized eigenproblem K x = w^2 M x did not converge",
            "cam " + format_number(cam_deg) + " deg"};
  frequencies_hz.clear();
  for (int i = 0; i < s.N; ++i) frequencies_hz.push_back(std::sqrt(std::max(eig.eigenvalues()(i), 0.0)) / (2 * kPi));
  std::sort(frequencies_hz.begin(), frequencies_hz.end());
  return Status::success();
}

Status flexible_linearise(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                          double engine_rpm_value, double cam_deg, const FlexibleOptions& options,
                          const std::vector<double>& q, const std::vector<double>& qd, FlexibleLinearisation& out) {
  CAMOPT_ASSERT(engine_rpm_value > 0);
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  Eigen::VectorXd x, v;
  {
    const Status st = static_start(s, model, controls, cam_deg * kDeg, x, v);
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
  s.forces(x, v);
  Eigen::MatrixXd k, d;
  s.newton_matrices(x, v, k, d);
  out.layout = {s.R, static_cast<int>(s.elements.size()), n - s.R - static_cast<int>(s.elements.size())};
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
