// the flexible model's forces, Newton matrices, mass and energy (flexible_system.hpp)
#include <algorithm>

#include "camopt/dynamics/hertz.hpp"
#include <numbers>

#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics::detail {

ForceLaw::Value ForceLaw::evaluate(double pen, double rate, double radius, double& start) const {
  Value v;
  if (two_sided && pen < 0.0) {
    // the slot's other wall: the same law in the mirrored penetration, force reversed
    ForceLaw one = *this;
    one.two_sided = false;
    v = one.evaluate(-pen, -rate, radius, start);
    v.force = -v.force;
    v.elastic = -v.elastic;
    v.unclamped = -v.unclamped;
    return v;
  }
  if (!(pen > 0.0)) return v;
  if (law == ContactLaw::linear) {
    // one-sided spring-damper: F = max(0, k d + c d')
    v.elastic = k * pen;
    v.elastic_tangent = k;
    const double f = k * pen + c * rate;
    v.unclamped = f;
    if (f > 0.0) v.force = f, v.d_pen = k, v.d_rate = c;
    return v;
  }
  v.elastic = scale * line_contact_force(pen, length, e_star, radius, start);
  v.elastic_tangent = scale * line_contact_tangent_stiffness(v.elastic / scale, length, e_star, radius);
  if (damping_law == ContactDampingLaw::hunt_crossley) {
    // F = max(0, F_e (1 + 3/2 alpha d')) (Hunt & Crossley 1975)
    const double f = v.elastic * (1.0 + 1.5 * alpha * rate);
    v.unclamped = f;
    if (f > 0.0) v.force = f, v.d_pen = v.elastic_tangent * (1.0 + 1.5 * alpha * rate), v.d_rate = 1.5 * alpha * v.elastic;
  } else {
    // F = max(0, F_e + c d')
    const double f = v.elastic + c * rate;
    v.unclamped = f;
    if (f > 0.0) v.force = f, v.d_pen = v.elastic_tangent, v.d_rate = c;
  }
  return v;
}

double ForceLaw::energy(double pen, double radius, double& start) const {
  if (two_sided && pen < 0.0) pen = -pen;
  if (!(pen > 0.0)) return 0.0;
  if (law == ContactLaw::linear) return 0.5 * k * pen * pen;
  const double f = line_contact_force(pen, length, e_star, radius, start);
  return scale * line_contact_energy(f, length, e_star, radius);
}

double ForceLaw::damping_at(double force) const {
  if (law == ContactLaw::hertz && damping_law == ContactDampingLaw::hunt_crossley) return 1.5 * alpha * force;
  return c;
}

ForceLaw::Value System::seat_force(const Seat& s, double pen, double rate) const {
  // a conical seat: the normal approach is cos(angle) x the axial one, the axial force cos x the normal one
  const double ca = s.cos_angle;
  ForceLaw::Value n = s.law.evaluate(ca * pen, ca * rate, s.radius, s.start);
  n.force *= ca;
  n.elastic *= ca;
  n.d_pen *= ca * ca;
  n.d_rate *= ca * ca;
  n.elastic_tangent *= ca * ca;
  n.unclamped *= ca;
  return n;
}

void System::forces(const double* q, const double* qd, bool powers_only) {
  Eigen::VectorXd& f = fr.f;
  f.setZero(N);
  const double w2 = omega * omega;
  fr.viscous_power = fr.friction_total = fr.gas_power = fr.path_spring_power = 0.0;
  // inertia of the kinematic motion, gas and the springs left in the path
  for (int r = 0; r < R; ++r) {
    const int far = far_of_row[r];
    const double inertia = path[L.inertia + r] * w2, gas = path[L.gas + r];
    double applied = path[L.other + r];
    for (int j = 0; j < R; ++j) applied += path[L.spring_k + r + R * j] * q[j];
    fr.path_spring_power -= applied * (kinematic_rate(r) + qd[r]);
    if (far < 0) {
      f(r) = -inertia - gas - applied;
      fr.gas_power -= gas * (kinematic_rate(r) + qd[r]);
    } else {
      f(r) = -0.5 * inertia - applied;
      f(far) = -0.5 * inertia - gas;
      fr.gas_power -= gas * (kinematic_rate(far) + qd[far]);
    }
  }
  for (const Element& e : elements) {
    const double rate = qd[e.far] - qd[e.near];
    const double fe = e.k * (q[e.far] - q[e.near]) + e.c * rate;
    f(e.near) += fe;
    f(e.far) -= fe;
    fr.viscous_power += e.c * rate * rate;
  }
  // plungers: the node's kinematic acceleration along the axis, the HLA and its stops (the
  // HLA's power on the train: an input, as the drive's)
  fr.hla_power = 0.0;
  for (const Plunger& p : plungers) {
    const double support = plunger_force(*this, p, q, qd);
    f(p.coord) = -path[L.pz_inertia + p.table_index] * w2 + support;
    fr.hla_power += support * qd[p.coord];
    if (p.series && p.far >= 0) {
      // a series body rides on the near end: its inertia leaves the far half (as its mass)
      const double shift = 0.5 * p.along * path[L.pz_inertia + p.table_index] * w2;
      f(p.row) -= shift;
      f(p.far) += shift;
    }
  }
  fr.torque = path[L.load_drv];
  for (int c = 0; c < C; ++c) {
    double fc = 0.0, mu = 0.0;
    const ContactData& cd = flex.contacts[c];
    if (frozen[c]) {
      fc = frozen_force[c];
    } else if (cd.is_contact) {
      const double pen = penetration(c, q);
      if (pen > 0.0 || cd.two_sided) {
        const double rate = penetration_rate(c, qd);
        const ForceLaw::Value v = laws[c].evaluate(pen, rate, reduced_radius(c), hertz_start[c]);
        fc = v.force;
        fr.viscous_power += (fc - v.elastic) * rate;
      }
    } else {
      const double rate = normal_dot(c, qd);
      fc = -link_k[c] * normal_dot(c, q) - link_c[c] * rate;
      fr.viscous_power += link_c[c] * rate * rate;
    }
    fr.friction_power[c] = 0.0;
    if (cd.is_contact && fc != 0.0 && cd.friction > 0.0 && !cd.rolling) {
      // sliding of a over b [mm/s]: kinematic plus the deviation's (g_t . dq' = -(v_a - v_b).t)
      double sliding = path[L.slide + c] * omega;
      sliding -= tangent_dot(c, qd);
      const double v0 = opt.friction_velocity_m_per_s * 1e3;
      mu = cd.friction * sliding / std::sqrt(sliding * sliding + v0 * v0);
      fr.friction_power[c] = mu * std::abs(fc) * sliding;
      fr.friction_total += fr.friction_power[c];
    }
    fr.connection[c] = fc;
    fr.mu_eff[c] = mu;
    if (fc != 0.0) {
      // friction mu |F| along the tangent, whichever wall carries the force
      for_gradient(c, [&](int row, double gn, double gt) { f(row) += fc * gn + std::abs(fc) * mu * gt; });
      fr.torque -= fc * path[L.gn_drv + c] + std::abs(fc) * mu * path[L.gt_drv + c];
    }
  }
  for (std::size_t i = 0; i < seats.size(); ++i) {
    const Seat& st = seats[i];
    fr.seat[i] = 0.0;
    const double pen = seat_penetration(st, q);
    if (pen > 0.0) {
      const double rate = seat_rate(st, qd);
      const ForceLaw::Value v = seat_force(st, pen, rate);
      fr.viscous_power += (v.force - v.elastic) * rate;
      f(st.row) += st.sign * v.force;
      fr.seat[i] = v.force;
    }
  }
  fr.drive_power = fr.torque * omega;
  for (std::size_t s = 0; s < chains.size(); ++s) chain_forces(s, q, qd, powers_only);
}

// one spring chain: segment j (1 .. masses + 1) between u_{j-1} and u_j (u_0 = 0 the seat end,
// u_{masses+1} the node) carries the whole-spring law at (masses + 1) x its compression plus
// the segment damping, and pushes u_j down and u_{j-1} up
void System::chain_forces(std::size_t s, const double* q, const double* qd, bool powers_only) {
  const Chain& ch = chains[s];
  const int nm = ch.masses;
  const double n1 = nm + 1.0, cs = ch.segment_damping;
  const int first = nm > 0 ? ch.first : 0;  // the coil masses (none: unused)
  const double* u = q + first;
  const double* v = qd + first;
  double* fo = fr.f.data() + first;
  const double x_top = chain_x(ch, q), v_top = chain_v(ch, qd);
  // viscous power: (N + 1) segments of damping (N + 1) cs at rate (v_j - v_{j-1})
  const double v_first = nm > 0 ? v[0] : v_top, v_last = nm > 0 ? v[nm - 1] : 0.0;
  double power = v_first * v_first + (nm > 0 ? (v_top - v_last) * (v_top - v_last) : 0.0);
  for (int i = 0; i + 1 < nm; ++i) power += (v[i + 1] - v[i]) * (v[i + 1] - v[i]);
  fr.viscous_power += cs * n1 * power;
  if (powers_only) return;
  const double clash = ch.solid_travel >= 0 ? ch.solid_travel : 1e300, kc = opt.coil_clash_stiffness;
  auto segment = [&](double d, double dd) {
    double f = ch.law.load(d) + cs * dd;
    if (d > clash) f += kc * (d - clash);
    return f;
  };
  // the seat-end segment, then the inner ones (between two coil masses): f[i] gets
  // +F(above) - F(below)
  const double u_first = nm > 0 ? u[0] : x_top;
  double below = segment(n1 * u_first, n1 * v_first);
  fr.coil_base[s] = below;
  if (ch.law.table_x.empty()) {
    // the linear law, branch-free: preload + rate d + cs d' + clash max(0, d - solid)
    const double p0 = ch.law.preload, k = ch.law.rate * n1, c = cs * n1;
    for (int i = 0; i + 1 < nm; ++i) {
      const double d = u[i + 1] - u[i];
      const double above = p0 + k * d + c * (v[i + 1] - v[i]) + kc * std::max(0.0, n1 * d - clash);
      fo[i] += above - below;
      below = above;
    }
  } else {
    for (int i = 0; i + 1 < nm; ++i) {
      const double above = segment(n1 * (u[i + 1] - u[i]), n1 * (v[i + 1] - v[i]));
      fo[i] += above - below;
      below = above;
    }
  }
  const double top = nm > 0 ? segment(n1 * (x_top - u[nm - 1]), n1 * (v_top - v[nm - 1])) : below;
  if (nm > 0) fo[nm - 1] += top - below;
  fr.f(ch.row) -= top;
  fr.coil_top[s] = top;
  fr.static_load[s] = ch.law.load(x_top);
}

namespace {

// segment j of a chain (j = 1 .. masses + 1: between u_{j-1} and u_j) with coefficient v
void add_segment(Structured& a, const Chain& ch, int j, double v) {
  const bool top = j == ch.masses + 1, bottom = j == 1;
  if (top) a.core(ch.row, ch.row) += v;
  if (ch.masses == 0) return;
  Band& b = a.bands[ch.band];
  if (top) {
    b.diag[ch.masses - 1] += v;
    b.couple -= v;
    return;
  }
  b.diag[j - 1] += v;
  if (!bottom) {
    b.diag[j - 2] += v;
    b.off[j - 2] -= v;
  }
}

}  // namespace

void System::newton_matrices(const double* q, const double* qd, Structured& k, Structured& d, bool statics) const {
  k.set_zero();
  d.set_zero();
  for (int r = 0; r < R; ++r)
    for (int j = 0; j < R; ++j) k.core(r, j) += path[L.spring_k + r + R * j];
  auto add_pair = [](Eigen::MatrixXd& a, int i, int j, double v) {
    a(i, i) += v;
    a(j, j) += v;
    a(i, j) -= v;
    a(j, i) -= v;
  };
  for (const Element& e : elements) {
    add_pair(k.core, e.near, e.far, e.k);
    add_pair(d.core, e.near, e.far, e.c);
  }
  // w g_left g_right^T on the connection's rows (0: g_n, 1: g_t)
  auto add_outer = [&](Eigen::MatrixXd& a, int c, double w, int left, int right) {
    if (w == 0.0) return;
    for_gradient(c, [&](int i, double gni, double gti) {
      for_gradient(c, [&](int j, double gnj, double gtj) { a(i, j) += w * (left ? gti : gni) * (right ? gtj : gnj); });
    });
  };
  for (int c = 0; c < C; ++c) {
    if (frozen[c]) continue;
    const ContactData& cd = flex.contacts[c];
    if (!cd.is_contact) {
      add_outer(k.core, c, link_k[c], 0, 0);
      add_outer(d.core, c, link_c[c], 0, 0);
      continue;
    }
    const double pen = penetration(c, q);
    if (!(pen > 0.0) && !cd.two_sided) continue;
    const double rate = statics ? 0.0 : penetration_rate(c, qd);
    const ForceLaw::Value v = laws[c].evaluate(pen, rate, reduced_radius(c), hertz_start[c]);
    if (statics) {
      add_outer(k.core, c, v.elastic_tangent, 0, 0);
      continue;
    }
    add_outer(k.core, c, v.d_pen, 0, 0);
    add_outer(d.core, c, v.d_rate, 0, 0);
    // friction mu(v) F g_t with v = v_kin - g_t . dq': dmu/dv = mu_c v0^2 / (v^2 + v0^2)^1.5
    if (v.force != 0.0 && cd.friction > 0.0 && !cd.rolling && !cd.two_sided) {
      double sliding = path[L.slide + c] * omega;
      sliding -= tangent_dot(c, qd);
      const double v0 = opt.friction_velocity_m_per_s * 1e3, root = std::sqrt(sliding * sliding + v0 * v0);
      const double mu = cd.friction * sliding / root, dmu = cd.friction * v0 * v0 / (root * root * root);
      add_outer(k.core, c, v.d_pen * mu, 1, 0);
      add_outer(d.core, c, v.d_rate * mu, 1, 0);
      add_outer(d.core, c, v.force * dmu, 1, 1);
    }
  }
  for (const Plunger& p : plungers) {
    k.core(p.coord, p.coord) += plunger_stiffness(*this, p, q);
    if (!statics) d.core(p.coord, p.coord) += plunger_damping(*this, p, q);
  }
  for (const Seat& st : seats) {
    const double pen = seat_penetration(st, q);
    if (!(pen > 0.0)) continue;
    const ForceLaw::Value v = seat_force(st, pen, statics ? 0.0 : seat_rate(st, qd));
    k.core(st.row, st.row) += statics ? v.elastic_tangent : v.d_pen;
    if (!statics) d.core(st.row, st.row) += v.d_rate;
  }
  for (const Chain& ch : chains) {
    const double n1 = ch.masses + 1.0;
    for (int j = 1; j <= ch.masses + 1; ++j) {
      const double dj = n1 * (chain_u(ch, j, q) - chain_u(ch, j - 1, q));
      double ks = n1 * ch.law.stiffness(dj);
      if (ch.solid_travel >= 0 && dj > ch.solid_travel) ks += n1 * opt.coil_clash_stiffness;
      add_segment(k, ch, j, ks);
      add_segment(d, ch, j, n1 * ch.segment_damping);
    }
  }
}

void System::mass_matrix(Structured& out) const {
  out.set_zero();
  for (int r = 0; r < R; ++r)
    for (int j = 0; j < R; ++j) out.core(r, j) = path[L.mass + r + R * j];
  for (const Element& e : elements) {
    const double half = 0.5 * out.core(e.near, e.near);
    out.core(e.near, e.near) = half;
    out.core(e.far, e.far) = half;
  }
  // a plunger carries the node's mass and its own; the node's centre of gravity couples it
  // with the node's angle (split between the halves of a compliant node, as its mass). In
  // series it carries the contact side, which rides on the near end: the valve side's mass
  // M - m_b is split between the halves
  for (const Plunger& p : plungers) {
    out.core(p.coord, p.coord) = p.mass;
    const double couple = path[L.pz_mass + p.table_index];
    if (p.series) {
      out.core(p.coord, p.row) = out.core(p.row, p.coord) = couple;
      if (p.far >= 0) out.core(p.row, p.row) += 0.5 * p.mass, out.core(p.far, p.far) -= 0.5 * p.mass;
      continue;
    }
    for (int end : {p.row, p.far}) {
      if (end < 0) continue;
      const double share = p.far < 0 ? couple : 0.5 * couple;
      out.core(p.coord, end) = out.core(end, p.coord) = share;
    }
  }
  for (const Chain& ch : chains)
    if (ch.masses > 0) std::fill(out.bands[ch.band].diag.begin(), out.bands[ch.band].diag.end(), ch.mass);
}

// the mass matrix depends on the cam angle only: factored once per angle (CVODE's Newton
// iterations call the right-hand side repeatedly at one time)
void System::factor_mass() {
  if (factored_theta == evaluated_theta) return;
  mass_matrix(m);
  core_mass_lu.compute(m.core);
  factored_theta = evaluated_theta;
}

void System::accelerations(const double* q, const double* qd) {
  forces(q, qd);
  factor_mass();
  const int nc = core();
  acc.head(nc) = core_mass_lu.solve(fr.f.head(nc));
  acc.tail(N - nc) = fr.f.tail(N - nc).cwiseProduct(inv_coil_mass);
}

double System::energy(const double* q, const double* qd) const {
  Eigen::VectorXd vel(N), mv(N);
  for (int j = 0; j < N; ++j) vel(j) = kinematic_rate(j) + qd[j];
  CAMOPT_ASSERT(factored_theta == evaluated_theta);  // m is the mass at this angle (after accelerations)
  m.multiply(chains, vel.data(), mv.data());
  double e = 0.5 * vel.dot(mv);
  for (const Element& el : elements) e += 0.5 * el.k * std::pow(q[el.far] - q[el.near], 2);
  for (int c = 0; c < C; ++c) {
    if (flex.contacts[c].is_contact) e += laws[c].energy(penetration(c, q), reduced_radius(c), hertz_start[c]);
    else e += 0.5 * link_k[c] * std::pow(normal_dot(c, q), 2);
  }
  for (const Seat& st : seats) e += st.law.energy(st.cos_angle * seat_penetration(st, q), st.radius, st.start);
  for (const Chain& ch : chains) {
    const double n1 = ch.masses + 1.0;
    const bool linear = ch.law.table_x.empty();
    for (int j = 1; j <= ch.masses + 1; ++j) {
      const double d = n1 * (chain_u(ch, j, q) - chain_u(ch, j - 1, q));
      e += (linear ? d * (ch.law.preload + 0.5 * ch.law.rate * d) : ch.law.energy(d)) / n1;
      if (ch.solid_travel >= 0 && d > ch.solid_travel)
        e += 0.5 * opt.coil_clash_stiffness * std::pow(d - ch.solid_travel, 2) / n1;
    }
  }
  return e;
}

double System::gap_error(const double* q, int& contact) const {
  double worst = 0.0;
  contact = -1;
  for (int c = 0; c < C; ++c) {
    if (!flex.contacts[c].is_contact || fr.connection[c] == 0.0) continue;
    const double slide = tangent_dot(c, q);
    const double error = 0.5 * slide * slide * std::abs(path[L.curv2 + c]);
    if (error > worst) worst = error, contact = c;
  }
  return worst;
}

std::string System::gap_error_message(double error, int contact) const {
  return "contact '" + mech.connections[contact].name + "' carries force with its bodies slid so far from their " +
         "kinematic contact point that its linearised gap is off by " + format_number(error) +
         " mm: a body that no spring or closed contact holds floats off (add a return spring), or the train is " +
         "far past its separation speed";
}

double System::root_value(const Root& rt, const double* q, const double* qd) const {
  CAMOPT_ASSERT_MSG(rt.kind != 3, "root_value: an HLA's root needs the time (hla_root_value)");
  if (rt.kind == 0) {
    const double pen = penetration(rt.index, q);
    if (!(pen > 0.0)) return pen;
    const double f =
        laws[rt.index].evaluate(pen, penetration_rate(rt.index, qd), reduced_radius(rt.index), hertz_start[rt.index]).unclamped;
    return std::min(pen, f);
  }
  if (rt.kind == 1) {
    const Seat& st = seats[rt.index];
    const double pen = seat_penetration(st, q);
    if (!(pen > 0.0)) return pen;
    return std::min(pen, seat_force(st, pen, seat_rate(st, qd)).unclamped);
  }
  const Chain& ch = chains[rt.index];
  const double d = (ch.masses + 1.0) * (chain_u(ch, rt.segment, q) - chain_u(ch, rt.segment - 1, q));
  return d - ch.solid_travel;  // > 0: the coils touch
}

std::string System::root_name(const Root& rt) const {
  if (rt.kind == 3) return hla_root_name(*this, rt);
  if (rt.kind == 0) return mech.connections[rt.index].name;
  if (rt.kind == 1) return mech.nodes[seats[rt.index].node].name + " seat";
  return chains[rt.index].name + " coil " + std::to_string(rt.segment);
}

}  // namespace camopt::dynamics::detail
