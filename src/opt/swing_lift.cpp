#include "camopt/opt/swing_lift.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "camopt/core/bspline_basis.hpp"
#include "camopt/core/jet.hpp"
#include "camopt/core/units.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/kinematics/solver.hpp"
#include "camopt/synthesis/hermite.hpp"
#include "camopt/synthesis/lift_law.hpp"
#include "camopt/synthesis/mechanism_cut.hpp"

namespace camopt::opt {

namespace {

constexpr int kZeroCoefficients = 4;  // h, h', h'', h''' = 0 at s_a

std::string num(double v) { return format_value(v, 8); }

const NodeSpec* find_node(const DesignSpec& d, const std::string& name) {
  for (const auto& n : d.nodes)
    if (n.name == name) return &n;
  return nullptr;
}

Eigen::Vector2d vec(const Vec2& v) { return {v[0], v[1]}; }

}  // namespace

void validate(const SwingProfileSpec& s) {
  if (!std::isfinite(s.start_deg) || s.start_deg < 0.0 || s.start_deg >= 90.0)
    throw InputError("swing_profile.start_deg = " + num(s.start_deg) + " swing deg: must be in [0, 90)");
  if (!std::isfinite(s.end_deg) || (s.end_deg != 0.0 && (s.end_deg <= s.start_deg + 5.0 || s.end_deg > 170.0)))
    throw InputError("swing_profile.end_deg = " + num(s.end_deg) + " swing deg: must be 0 (automatic) or in (start_deg + 5, 170]"
                     " with start_deg = " + num(s.start_deg));
  if (s.degree < 4 || s.degree > 7)
    throw InputError("swing_profile.degree = " + std::to_string(s.degree) + ": must be in [4, 7]");
  if (s.coefficients < s.degree + kZeroCoefficients + 1 || s.coefficients > 200)
    throw InputError("swing_profile.coefficients = " + std::to_string(s.coefficients) + ": must be in [" +
                     std::to_string(s.degree + kZeroCoefficients + 1) + ", 200] for degree " + std::to_string(s.degree));
  for (double p : s.positions)
    if (!std::isfinite(p)) throw InputError("swing_profile.positions: every position must be finite");
}

struct SwingCamLift::Impl {
  struct Build;  // the construction steps
  struct Point {
    int position = 0;
    double cam_deg = 0.0;
    Jet<3> psi;               // swing angle [rad] and its derivatives per cam rad
    Eigen::Vector2d pivot;    // swing pivot at this control position [mm]
    double q = 0.0;           // follower angle of the last solve (warm start) [rad]
  };
  SwingProfileSpec spec;
  std::string profile, connection;
  kin::Mechanism up;
  std::vector<kin::Workspace> up_ws;  // per position
  int swing_var = -1, swing_node = -1;
  std::vector<double> positions;
  std::vector<std::vector<double>> controls;
  std::vector<Point> pts;
  std::vector<SwingPoint> public_pts;
  // geometry (drawing) [mm]
  Eigen::Vector2d ps0, e0, pf, f0, c0, p0, n, d;
  double sigma = 1.0, rho0 = 0.0, r_roller = 0.0, r_pad = 0.0, nd = 1.0;
  Eigen::Vector2d profile_origin;
  double profile_orientation = 0.0;  // [rad]
  // spline of h on [s_a, s_b] [rad]
  int p = 5, ncoef = 20;
  double sa = 0.0, sb = 1.0;
  std::vector<double> knots;                                // of h (clamped, uniform)
  std::vector<double> initial;

  int free() const { return ncoef - kZeroCoefficients; }

  // the follower roller centre relative to the swing pivot in the swing frame, and its
  // polar angle s from the rest direction (sigma applied)
  template <class T>
  void frame(const T& q, const T& psi, const Eigen::Vector2d& pivot, T& px, T& py, T& s) const {
    using std::cos;
    using std::sin;
    const T cq = cos(q), sq = sin(q), cp = cos(psi), sp = sin(psi);
    const Eigen::Vector2d a = f0 - pf;
    const T dx = pf.x() + cq * a.x() - sq * a.y() - pivot.x();
    const T dy = pf.y() + sq * a.x() + cq * a.y() - pivot.y();
    px = cp * dx + sp * dy;
    py = cp * dy - sp * dx;
    using std::atan2;
    s = sigma * atan2(e0.x() * py - e0.y() * px, e0.x() * px + e0.y() * py);
  }

  // sum_m hd[m]/m! ds^m, ds = s - s0 (a jet with no constant part)
  template <class T>
  static T taylor(const double* hd, int terms, const T& ds) {
    static constexpr double inv_fact[] = {1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0};
    T out = T(hd[terms - 1] * inv_fact[terms - 1]);
    for (int m = terms - 2; m >= 0; --m) out = out * ds + hd[m] * inv_fact[m];
    return out;
  }

  // the degree-p basis functions of the span of s on knots (the span rule of
  // synthesis::bspline_value: s outside [t_p, t_n] takes the end span) and their derivatives
  // up to min(p, 4): ders[m][r] = N_{k-p+r}^(m)(s). returns k. (Piegl & Tiller, The NURBS
  // Book, 2nd ed., algorithm A2.3)
  int basis_derivatives(double s, double (&ders)[5][8]) const {
    const auto& t = knots;
    const int orders = std::min(p, 4);
    const int k = static_cast<int>(std::upper_bound(t.begin() + p + 1, t.begin() + ncoef, s) - t.begin()) - 1;
    bspline_basis_derivatives(t.data(), k, p, s, orders, ders);
    for (int m = orders + 1; m <= 4; ++m)
      for (int r = 0; r <= p; ++r) ders[m][r] = 0.0;
    return k;
  }

  // free coefficient j of basis function k - p + r, or -1 when it is not a free one or its
  // support does not hold se
  int free_index(int k, int r, double se) const {
    const int jj = k - p + r, j = jj - kZeroCoefficients;
    if (j < 0 || j >= free()) return -1;
    if (se < knots[static_cast<std::size_t>(jj)] || se > knots[static_cast<std::size_t>(jj + p + 1)]) return -1;
    return j;
  }

  void h_derivatives(std::span<const double> c, double s, double out[5]) const {
    std::fill(out, out + 5, 0.0);
    if (s <= sa) return;
    const double se = std::min(s, sb);
    double ders[5][8];
    const int k = basis_derivatives(s, ders);
    for (int r = 0; r <= p; ++r) {
      const int j = free_index(k, r, se);
      if (j < 0) continue;
      const double cj = c[static_cast<std::size_t>(j)];
      if (cj == 0.0) continue;
      for (int m = 0; m <= 4 && m <= p; ++m) out[m] += cj * ders[m][r];
    }
  }

  // newton on G(q) = |p| - rho(s(p)) for fixed psi; false when it does not converge
  bool solve_q(std::span<const double> c, double psi, const Eigen::Vector2d& pivot, double& q, bool dwell) const {
    double hd[5];
    for (int it = 0; it < 40; ++it) {
      Jet<1> px, py, s;
      frame(Jet<1>::variable(q), Jet<1>(psi), pivot, px, py, s);
      const double s0 = s.value();
      if (dwell) std::fill(hd, hd + 5, 0.0);
      else h_derivatives(c, s0, hd);
      Jet<1> ds = s - s0;
      const Jet<1> g = sqrt(px * px + py * py) - rho0 - taylor(hd, 2, ds);
      const double gq = g.derivative(1);
      if (!(std::abs(gq) > 1e-12)) return false;
      const double step = std::clamp(-g.value() / gq, -0.2, 0.2);
      q += step;
      if (std::abs(step) < 1e-14) return true;
    }
    return false;
  }

  // the follower's motion at one point as series in the cam angle [per cam rad]
  struct FollowerSeries {
    Jet<3> q;             // follower angle q(theta) [rad]
    double s0 = 0.0;      // contact polar angle from the rest direction [rad]
    double hd[5] = {};    // h^(m)(s0) [mm / rad^m]
    Jet<3> ds;            // s(theta) - s0 [rad]
    Jet<3> g_q, s_q;      // G_q [mm/rad] and s_q along the motion
    Jet<3> lift, lift_q;  // valve lift [mm] and dL/dq [mm/rad]
  };

  // the pitch curvature kappa(rho, rho_phi, rho_phiphi) in polar form (phi = sigma s: only
  // rho_phi^2 enters) and its partials
  struct CurvaturePartials {
    double rho = 0.0;            // rho0 + h [mm]
    double num_k = 0.0, d15 = 0.0;  // kappa = num_k / d15
    double k_rho = 0.0, k_a = 0.0, k_b = 0.0;  // d kappa / d (rho, rho_phi, rho_phiphi)
    double k_s = 0.0;            // d kappa / ds along the curve
    double s_shift = 0.0;        // ds/dc_j = s_shift N_j
  };

  // partials of the contact quantities in q, rho and rho_phi (SwingContact)
  struct ContactPartials {
    double a_q = 0.0, a_rho = 0.0, a_rphi = 0.0;  // pressure angle
    double f_q = 0.0, f_rho = 0.0, f_rphi = 0.0;  // force ratio
    double w_q0 = 0.0, w_q1 = 0.0;                // roller speed, in q and q'
  };

  // the follower angle q [rad] on the pitch curve c: newton from q, else from the rest
  Status solve_follower(const Point& pt, std::span<const double> c, double& q) const {
    const double psi0 = pt.psi.value();
    double qn = q;
    if (!solve_q(c, psi0, pt.pivot, qn, false)) {
      qn = 0.0;  // restart from the rest
      if (!solve_q(c, psi0, pt.pivot, qn, false))
        return {StatusCode::no_convergence, "the follower roller finds no contact with the swing cam's pitch curve",
                "cam " + num(pt.cam_deg) + " deg, control position " +
                    num(positions[static_cast<std::size_t>(pt.position)])};
    }
    q = qn;
    return Status::success();
  }

  // q(theta) by implicit differentiation of the closure, order by order: q_k = -G_k / G_q;
  // then G_q and s_q along the motion and the valve lift of the pad on the valve face
  FollowerSeries follower_series(const Point& pt, std::span<const double> c, double qn) const {
    FollowerSeries f;
    const double psi0 = pt.psi.value();
    double* hd = f.hd;
    Jet<3> Q(qn), px, py, s;
    frame(Q, pt.psi, pt.pivot, px, py, s);
    const double s0 = s.value();
    h_derivatives(c, s0, hd);
    double gq = 0.0;
    {
      Jet<1> x1, y1, s1;
      frame(Jet<1>::variable(qn), Jet<1>(psi0), pt.pivot, x1, y1, s1);
      gq = (sqrt(x1 * x1 + y1 * y1) - taylor(hd, 2, s1 - s0)).derivative(1);
    }
    for (int k = 1; k <= 3; ++k) {
      frame(Q, pt.psi, pt.pivot, px, py, s);
      const Jet<3> g = sqrt(px * px + py * py) - taylor(hd, 4, s - s0);
      Q.c[static_cast<std::size_t>(k)] = -g.c[static_cast<std::size_t>(k)] / gq;
    }
    // G_q along the motion: |p|_q - rho'(s) s_q, p_q = R(-psi) J (F - P_f)
    frame(Q, pt.psi, pt.pivot, px, py, s);
    const Jet<3> ds = s - s0;
    Jet<3> cq, sq, cp, sp;
    sincos(Q, sq, cq);
    sincos(pt.psi, sp, cp);
    const Eigen::Vector2d a = f0 - pf;
    const Jet<3> fx = cq * a.x() - sq * a.y(), fy = sq * a.x() + cq * a.y();  // F - P_f
    const Jet<3> gx = -fy, gy = fx;                                           // dF/dq
    const Jet<3> pqx = cp * gx + sp * gy, pqy = cp * gy - sp * gx;
    const Jet<3> r2 = px * px + py * py, r = sqrt(r2);
    const Jet<3> r_q = (px * pqx + py * pqy) / r;
    f.s_q = sigma * (px * pqy - py * pqx) / r2;
    f.g_q = r_q - taylor(hd + 1, 4, ds) * f.s_q;
    // valve: pad centre C(q) on the line through P_0 + L d with normal n
    const Eigen::Vector2d b = c0 - pf;
    const Jet<3> cx = pf.x() + cq * b.x() - sq * b.y(), cy = pf.y() + sq * b.x() + cq * b.y();
    f.lift = (n.x() * (cx - p0.x()) + n.y() * (cy - p0.y()) - r_pad) / nd;
    f.lift_q = (n.x() * (-(sq * b.x() + cq * b.y())) + n.y() * (cq * b.x() - sq * b.y())) / nd;
    f.q = Q;
    f.s0 = s0;
    f.ds = ds;
    return f;
  }

  CurvaturePartials curvature_partials(const FollowerSeries& f) const {
    CurvaturePartials k;
    const double* hd = f.hd;
    k.rho = rho0 + hd[0];
    const double rho = k.rho, ra = hd[1], rb = hd[2];
    const double dd = rho * rho + ra * ra, d15 = dd * std::sqrt(dd), d25 = d15 * dd;
    k.num_k = rho * rho + 2 * ra * ra - rho * rb;
    k.d15 = d15;
    k.k_rho = (2 * rho - rb) / d15 - 3.0 * k.num_k * rho / d25;
    k.k_a = 4 * ra / d15 - 3.0 * k.num_k * ra / d25;
    k.k_b = -rho / d15;
    k.k_s = k.k_rho * hd[1] + k.k_a * hd[2] + k.k_b * hd[3];
    k.s_shift = f.s_q.value() / f.g_q.value();  // ds/dc_j = s_shift N_j
    return k;
  }

  // the contact quantities at the point (into contact, rows zeroed) and their partials.
  // pressure angle alpha = atan2(|cr|, |dt|), dt = n . p_q, cr = p_q x n, as a function of
  // q (through the frame and the contact's shift along the profile), rho and rho_phi
  ContactPartials contact_quantities(const Point& pt, double qn, const FollowerSeries& f, const CurvaturePartials& kp,
                                     SwingContact& contact) const {
    ContactPartials cp;
    const double psi0 = pt.psi.value();
    const double* hd = f.hd;
    const double rho = kp.rho;
    const Eigen::Vector2d b = c0 - pf;
    Jet<2> x2, y2, s2;
    frame(Jet<2>::variable(qn), Jet<2>(psi0), pt.pivot, x2, y2, s2);
    const Jet<2> r_ = sqrt(x2 * x2 + y2 * y2), ph = atan2(y2, x2);
    const double sq0 = s2.derivative(1);
    Jet<1> r1(r_.value()), rq(r_.derivative(1)), phq(ph.derivative(1)), rh(rho), rph(sigma * hd[1]);
    r1.c[1] = r_.derivative(1);
    rq.c[1] = r_.derivative(2);
    phq.c[1] = ph.derivative(2);
    rh.c[1] = hd[1] * sq0;
    rph.c[1] = sigma * hd[2] * sq0;
    const Jet<1> dt = rh * rq - rph * r1 * phq, cr = -(rq * rph) - r1 * phq * rh;
    const double sx = dt.value() < 0 ? -1.0 : 1.0, sy = cr.value() < 0 ? -1.0 : 1.0;
    const double X = std::abs(dt.value()), Y = std::abs(cr.value()), den = X * X + Y * Y;
    contact.pressure_angle = std::atan2(Y, X);
    cp.a_q = (X * sy * cr.c[1] - Y * sx * dt.c[1]) / den;
    cp.a_rho = (X * sy * (-r1.value() * phq.value()) - Y * sx * rq.value()) / den;
    cp.a_rphi = (X * sy * (-rq.value()) - Y * sx * (-r1.value() * phq.value())) / den;
    // force ratio |L_q| N / |dt|, N = |n|; L_q, L_qq of the pad on the valve face
    const double cq0 = std::cos(qn), sq0n = std::sin(qn);
    const double lq = (n.x() * (-(sq0n * b.x() + cq0 * b.y())) + n.y() * (cq0 * b.x() - sq0n * b.y())) / nd;
    const double lqq = -(n.x() * (cq0 * b.x() - sq0n * b.y()) + n.y() * (sq0n * b.x() + cq0 * b.y())) / nd;
    const Jet<1> nn = sqrt(rh * rh + rph * rph);
    const double sl = lq < 0 ? -1.0 : 1.0, alq = std::abs(lq);
    contact.force_ratio = alq * nn.value() / X;
    cp.f_q = sl * lqq * nn.value() / X + alq * nn.c[1] / X - alq * nn.value() * sx * dt.c[1] / (X * X);
    cp.f_rho = alq * (rho / nn.value()) / X - alq * nn.value() * sx * rq.value() / (X * X);
    cp.f_rphi = alq * (sigma * hd[1] / nn.value()) / X - alq * nn.value() * sx * (-r1.value() * phq.value()) / (X * X);
    // roller speed: p' = p_q q' + p_psi psi', p_psi = -J p
    const Eigen::Vector2d p0v{x2.value(), y2.value()}, pq{x2.derivative(1), y2.derivative(1)},
        pqq{x2.derivative(2), y2.derivative(2)};
    const double q1 = f.q.derivative(1), psi1 = pt.psi.derivative(1);
    auto mj = [](const Eigen::Vector2d& v) { return Eigen::Vector2d{v.y(), -v.x()}; };  // -J v
    const Eigen::Vector2d vel = pq * q1 + mj(p0v) * psi1;
    const double speed = vel.norm();
    const double sgn = p0v.x() * vel.y() - p0v.y() * vel.x() < 0 ? -1.0 : 1.0;
    contact.roller_speed = sgn * speed / r_roller + psi1 - q1;
    if (speed > 1e-12) {
      cp.w_q0 = sgn / r_roller * vel.dot(pqq * q1 + mj(pq) * psi1) / speed;
      cp.w_q1 = sgn / r_roller * vel.dot(pq) / speed - 1.0;
    } else {
      cp.w_q1 = -1.0;
    }
    contact.s_rad = f.s0;
    contact.curvature = kp.num_k / kp.d15;
    contact.curvature_row.setZero(free());
    contact.pressure_angle_row.setZero(free());
    contact.force_ratio_row.setZero(free());
    contact.roller_speed_row.setZero(free());
    return cp;
  }

  // the gradients of the motion and of the contact quantities in the free coefficients
  // c_j: dq/dc_j = N_j(s(theta)) / G_q along theta (rows zero on the dwell)
  void coefficient_rows(const FollowerSeries& f, const CurvaturePartials& kp, const ContactPartials& cp,
                        SwingContact* contact, Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows) const {
    const double q_shift = 1.0 / f.g_q.value();  // dq/dc_j = q_shift N_j
    const double s0 = f.s0;
    if (s0 <= sa) return;
    const double se = std::min(s0, sb);
    double ders[5][8];
    const int span = basis_derivatives(s0, ders);
    for (int ib = 0; ib <= p; ++ib) {
      const int j = free_index(span, ib, se);
      if (j < 0) continue;
      double nd_[4];
      for (int m = 0; m < 4; ++m) nd_[m] = ders[m][ib];  // N_j^(m)(s0)
      const Jet<3> sj = taylor(nd_, 4, f.ds) / f.g_q;  // dq/dc_j along theta
      const Jet<3> dl = f.lift_q * sj;
      if (contact) {
        contact->force_ratio_row(j) = cp.f_q * q_shift * nd_[0] + cp.f_rho * nd_[0] + cp.f_rphi * sigma * nd_[1];
        contact->roller_speed_row(j) = cp.w_q0 * sj.c[0] + cp.w_q1 * sj.c[1];
        contact->curvature_row(j) = kp.k_rho * nd_[0] + kp.k_a * nd_[1] + kp.k_b * nd_[2] + kp.k_s * kp.s_shift * nd_[0];
        contact->pressure_angle_row(j) = cp.a_q * q_shift * nd_[0] + cp.a_rho * nd_[0] + cp.a_rphi * sigma * nd_[1];
      }
      double sc = 1.0;
      for (int k = 0; k <= 3; ++k) {
        rows(k, j) = dl.derivative(k) * sc;
        sc *= rad_per_deg;
      }
    }
  }

  // valve lift and derivatives [mm/deg^k] at one point for the free coefficients c, their
  // gradients rows(k, j) [per mm], and the contact quantities (contact non-null)
  Status evaluate(const Point& pt, std::span<const double> c, double& q, double motion[4],
                  Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows, SwingContact* contact = nullptr) const {
    // the follower angle on the pitch curve
    if (Status st = solve_follower(pt, c, q); !st.ok()) return st;
    // its series in the cam angle, and the valve's
    const FollowerSeries f = follower_series(pt, c, q);
    double scale = 1.0;
    for (int k = 0; k <= 3; ++k) {
      motion[k] = f.lift.derivative(k) * scale;
      scale *= rad_per_deg;
    }
    rows.setZero();
    // the pitch curvature at the contact and its partials
    const CurvaturePartials kp = curvature_partials(f);
    // the contact quantities and their partials
    const ContactPartials cp = contact ? contact_quantities(pt, q, f, kp, *contact) : ContactPartials{};
    // the gradients in the free coefficients
    coefficient_rows(f, kp, cp, contact, rows);
    return Status::success();
  }
};

struct SwingCamLift::Impl::Build {
  // the design's geometry the model works in (drawing) [mm]: the swing pivot, the follower's
  // pivot and roller, and the pad on the valve face. InputError unless the follower is a
  // rotational node on a fixed pivot, with a convex circle on the swing cam, that moves the
  // output node (translational) through a circle on a line.
  static void read_geometry(const DesignSpec& design, const synthesis::MechanismCut& cut, Impl& m) {
    const auto& conn = design.connections[static_cast<std::size_t>(cut.connection)];
    m.profile = cut.profile;
    m.connection = conn.name;
    const SurfaceSpec& cam_s = cut.profile_on_a ? conn.surface_a : conn.surface_b;
    const SurfaceSpec& fol_s = cut.profile_on_a ? conn.surface_b : conn.surface_a;
    if (fol_s.shape != SurfaceShape::circle || fol_s.concave)
      throw InputError(conn.where, "optimize --cam swing: the follower of contact '" + conn.name +
                                       "' must be a convex circle (roller or pad)");
    const NodeSpec* swing = find_node(design, cut.cam_node);
    const NodeSpec* fol = find_node(design, cut.follower_node);
    if (!fol || fol->kind != NodeKind::rotational || fol->pivot_motion)
      throw InputError(conn.where, "optimize --cam swing: the follower '" + cut.follower_node +
                                       "' must be a rotational node on a fixed pivot");
    // the follower drives the output node through a circle on a line
    const NodeSpec* out = find_node(design, design.output_node);
    const ConnectionSpec* valve = nullptr;
    bool circle_on_a = true;
    for (const auto& k : design.connections) {
      if (k.kind != ConnectionKind::contact) continue;
      for (int side = 0; side < 2; ++side) {
        const SurfaceSpec& s1 = side == 0 ? k.surface_a : k.surface_b;
        const SurfaceSpec& s2 = side == 0 ? k.surface_b : k.surface_a;
        if (s1.node == cut.follower_node && s1.shape == SurfaceShape::circle && !s1.concave && s2.node == design.output_node &&
            s2.shape == SurfaceShape::line) {
          valve = &k;
          circle_on_a = side == 0;
        }
      }
    }
    if (!valve || !out || out->kind != NodeKind::translational)
      throw InputError("optimize --cam swing: the follower '" + cut.follower_node + "' must move the output node '" +
                       design.output_node + "' (translational) through a circle on a line");
    const SurfaceSpec& pad = circle_on_a ? valve->surface_a : valve->surface_b;
    const SurfaceSpec& line = circle_on_a ? valve->surface_b : valve->surface_a;
    m.ps0 = vec(swing->pivot_mm);
    m.pf = vec(fol->pivot_mm);
    m.f0 = vec(fol_s.origin_mm);
    m.r_roller = fol_s.radius_mm;
    m.c0 = vec(pad.origin_mm);
    m.r_pad = pad.radius_mm;
    m.p0 = vec(line.origin_mm);
    m.n = vec(line.normal).normalized();
    m.d = vec(out->direction).normalized();
    m.nd = m.n.dot(m.d);
    if (std::abs(m.nd) < 1e-6)
      throw InputError(valve->where, "optimize --cam swing: the valve face of contact '" + valve->name +
                                         "' is parallel to the valve's direction of motion");
    m.rho0 = (m.f0 - m.ps0).norm();
    m.e0 = (m.f0 - m.ps0) / m.rho0;
    m.profile_origin = vec(cam_s.origin_mm);
    m.profile_orientation = cam_s.orientation_deg * rad_per_deg;
  }

  // control positions: the first control's values (17 over its range by default), the
  // others at their defaults
  static void set_positions(const DesignSpec& design, const SwingProfileSpec& spec, Impl& m) {
    if (design.controls.empty())
      throw InputError("optimize --cam swing: design '" + design.name + "' has no [[control]]");
    m.positions = spec.positions;
    if (m.positions.empty()) {
      const auto& c = design.controls[0];
      for (int i = 0; i < 17; ++i) m.positions.push_back(c.min + (c.max - c.min) * i / 16.0);
    }
    for (double v : m.positions) {
      std::vector<double> ctl;
      for (const auto& c : design.controls) ctl.push_back(c.default_value);
      ctl[0] = v;
      m.controls.push_back(ctl);
    }
  }

  // the design's own swing profile traced by the full kinematics at position 0 over one
  // turn: the pitch curve's polar angle s [rad] and lift h [mm] at each point, and the side
  // the roller runs onto (sigma)
  static Status trace_design_profile(const DesignSpec& design, const synthesis::MechanismCut& cut, Impl& m,
                                     std::vector<double>& s_raw, std::vector<double>& h_raw) {
    const kin::Mechanism full = kin::compile(design);
    kin::Workspace ws(full);
    ws.set_controls(m.controls[0]);
    const int sn = full.node_index(cut.cam_node), fn = full.node_index(cut.follower_node);
    for (int i = 0; i < 1440; ++i) {
      const Status st = kin::solve(full, ws, 2 * pi * i / 1440, {0, false});
      if (!st.ok()) return {st.code, "tracing the design's swing profile: " + st.message, st.where};
      const double psi = ws.vars[static_cast<std::size_t>(full.nodes[static_cast<std::size_t>(sn)].first_variable)].value();
      const double q = ws.vars[static_cast<std::size_t>(full.nodes[static_cast<std::size_t>(fn)].first_variable)].value();
      double px, py, s;
      m.sigma = 1.0;
      m.frame(q, psi, ws.pivots()[static_cast<std::size_t>(sn)], px, py, s);
      s_raw.push_back(s);
      h_raw.push_back(std::hypot(px, py) - m.rho0);
    }
    double lifted = 0.0;
    for (std::size_t i = 0; i < s_raw.size(); ++i)
      if (h_raw[i] > 1e-3) lifted += s_raw[i];
    if (lifted == 0.0)
      throw InputError("optimize --cam swing: the design's swing profile never lifts the follower at control " +
                       num(m.positions[0]));
    m.sigma = lifted > 0 ? 1.0 : -1.0;
    for (double& s : s_raw) s *= m.sigma;
    return Status::success();
  }

  // the working curve [s_a, s_b] [rad]: from the spec, s_b by default 3 deg past the
  // farthest traced contact
  static void set_working_range(const SwingProfileSpec& spec, const std::vector<double>& s_raw,
                                const std::vector<double>& h_raw, Impl& m) {
    m.sa = spec.start_deg * rad_per_deg;
    double s_max = m.sa;
    for (std::size_t i = 0; i < s_raw.size(); ++i)
      if (h_raw[i] > 1e-6) s_max = std::max(s_max, s_raw[i]);
    m.sb = spec.end_deg > 0 ? spec.end_deg * rad_per_deg : s_max + 3.0 * rad_per_deg;
    if (m.sb <= m.sa + 5.0 * rad_per_deg)
      throw InputError("swing_profile.end_deg: the working curve [" + num(spec.start_deg) + ", " +
                       num(m.sb / rad_per_deg) + "] swing deg is shorter than 5 deg");
  }

  // the spline basis of h, and the initial coefficients: least squares to the traced pitch
  // curve over [s_a, s_max], with a weak penalty on the coefficients' second differences
  // (the zero ones at s_a included) that carries the curve on smoothly past the traced range
  static void fit_initial(const SwingProfileSpec& spec, const std::vector<double>& s_raw,
                          const std::vector<double>& h_raw, Impl& m) {
    m.p = spec.degree;
    m.ncoef = spec.coefficients;
    m.knots = synthesis::clamped_uniform_knots(m.ncoef, m.p, m.sa, m.sb);
    const int nf = m.free();
    Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(nf, nf);
    Eigen::VectorXd atb = Eigen::VectorXd::Zero(nf);
    Eigen::VectorXd row(nf);
    for (std::size_t i = 0; i < s_raw.size(); ++i) {
      if (s_raw[i] < m.sa || s_raw[i] > m.sb) continue;
      double ders[5][8];
      const int k = m.basis_derivatives(s_raw[i], ders);
      row.setZero();
      for (int r = 0; r <= m.p; ++r)
        if (const int j = m.free_index(k, r, s_raw[i]); j >= 0) row(j) = ders[0][r];
      ata += row * row.transpose();
      atb += row * h_raw[i];
    }
    const double penalty = 1e-4 * std::max(ata.trace() / nf, 1.0);
    for (int j = -2; j + 2 < nf; ++j) {  // (c_j - 2 c_{j+1} + c_{j+2})^2 over free indices j.. (j < 0: a zero coefficient)
      row.setZero();
      const double w3[3] = {1.0, -2.0, 1.0};
      for (int t = 0; t < 3; ++t)
        if (j + t >= 0) row(j + t) = w3[t];
      ata += penalty * row * row.transpose();
    }
    const Eigen::VectorXd c = ata.ldlt().solve(atb);
    m.initial.assign(c.data(), c.data() + nf);
  }

  // upstream: the swing angle at every position and grid angle, each position's working
  // points in a run starting on the dwell (cam angles unwrapped past 360); points on the
  // dwell for every design are left out
  static Status solve_drive(const synthesis::MechanismCut& cut, double grid_step_deg, Impl& m) {
    m.up = kin::compile(cut.upstream);
    m.swing_node = m.up.node_index(cut.cam_node);
    m.swing_var = m.up.nodes[static_cast<std::size_t>(m.swing_node)].first_variable;
    const int steps = static_cast<int>(std::lround(360.0 / grid_step_deg));
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
      m.up_ws.emplace_back(m.up);
      kin::Workspace& ws = m.up_ws.back();
      ws.set_controls(m.controls[k]);
      std::vector<Impl::Point> all;
      std::vector<char> working;
      for (int i = 0; i < steps; ++i) {
        const double deg = 360.0 * i / steps;
        const Status st = kin::solve(m.up, ws, deg * rad_per_deg, {3, false});
        if (!st.ok())
          return {st.code, "solving the swing cam's drive: " + st.message,
                  "cam " + num(deg) + " deg, control position " + num(m.positions[k])};
        Impl::Point pt;
        pt.position = static_cast<int>(k);
        pt.cam_deg = deg;
        pt.psi = ws.vars[static_cast<std::size_t>(m.swing_var)];
        pt.pivot = ws.pivots()[static_cast<std::size_t>(m.swing_node)];
        double q = 0.0;
        if (!m.solve_q({}, pt.psi.value(), pt.pivot, q, true))
          return {StatusCode::no_convergence, "the follower roller finds no contact with the dwell arc",
                  "cam " + num(deg) + " deg, control position " + num(m.positions[k])};
        double px, py, s;
        m.frame(q, pt.psi.value(), pt.pivot, px, py, s);
        pt.q = q;
        all.push_back(pt);
        working.push_back(s >= m.sa ? 1 : 0);
      }
      // start the position's run on the dwell, so its working points are consecutive
      int first_dwell = 0;
      while (first_dwell < steps && working[static_cast<std::size_t>(first_dwell)]) ++first_dwell;
      if (first_dwell == steps)
        throw InputError("optimize --cam swing: the follower never rests on the dwell arc at control position " +
                         num(m.positions[k]));
      for (int i = first_dwell; i < first_dwell + steps; ++i) {
        const std::size_t w = static_cast<std::size_t>(i % steps);
        if (!working[w]) continue;
        Impl::Point pt = all[w];
        if (i >= steps) pt.cam_deg += 360.0;
        m.pts.push_back(pt);
        m.public_pts.push_back({pt.position, pt.cam_deg});
      }
    }
    return Status::success();
  }

  static Status build(const DesignSpec& design, const SwingProfileSpec& spec, double grid_step_deg, Impl& m) {
    // the spec's own rules
    validate(spec);
    m.spec = spec;
    // the swing cam's contact and the geometry from the swing cam to the valve
    const synthesis::MechanismCut cut = synthesis::cut_mechanism(design, "swing", design.output_node);
    read_geometry(design, cut, m);
    // control positions
    set_positions(design, spec, m);
    // the design's own swing profile, traced at position 0
    std::vector<double> s_raw, h_raw;
    if (Status st = trace_design_profile(design, cut, m, s_raw, h_raw); !st.ok()) return st;
    // the working curve's extent
    set_working_range(spec, s_raw, h_raw, m);
    // the spline of h and its initial fit
    fit_initial(spec, s_raw, h_raw, m);
    // the drive's swing angle at every grid point
    return solve_drive(cut, grid_step_deg, m);
  }
};

Status SwingCamLift::create(const DesignSpec& design, const SwingProfileSpec& spec, double grid_step_deg,
                            std::unique_ptr<SwingCamLift>& out) {
  std::unique_ptr<SwingCamLift> model(new SwingCamLift());
  if (Status st = Impl::Build::build(design, spec, grid_step_deg, *model->impl_); !st.ok()) return st;
  out = std::move(model);
  return Status::success();
}

SwingCamLift::SwingCamLift() : impl_(std::make_unique<Impl>()) {}

SwingCamLift::SwingCamLift(const DesignSpec& design, const SwingProfileSpec& spec, double grid_step_deg)
    : impl_(std::make_unique<Impl>()) {
  if (Status st = Impl::Build::build(design, spec, grid_step_deg, *impl_); !st.ok()) throw NumericalError(st);
}

SwingCamLift::~SwingCamLift() = default;
SwingCamLift::SwingCamLift(SwingCamLift&&) noexcept = default;

int SwingCamLift::variables() const noexcept { return impl_->free(); }
const std::vector<double>& SwingCamLift::positions() const noexcept { return impl_->positions; }
const std::vector<double>& SwingCamLift::controls(int k) const { return impl_->controls[static_cast<std::size_t>(k)]; }
const std::vector<SwingPoint>& SwingCamLift::points() const noexcept { return impl_->public_pts; }
const std::vector<double>& SwingCamLift::initial() const noexcept { return impl_->initial; }
double SwingCamLift::start_rad() const noexcept { return impl_->sa; }
double SwingCamLift::end_rad() const noexcept { return impl_->sb; }
double SwingCamLift::dwell_radius_mm() const noexcept { return impl_->rho0; }
double SwingCamLift::roller_radius_mm() const noexcept { return impl_->r_roller; }
const std::string& SwingCamLift::profile_name() const noexcept { return impl_->profile; }
const std::string& SwingCamLift::connection() const noexcept { return impl_->connection; }

Status SwingCamLift::evaluate(int point, std::span<const double> c, double motion[4],
                              Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows, SwingContact* contact) {
  CAMOPT_ASSERT(static_cast<int>(c.size()) == variables() && rows.cols() == variables());
  Impl::Point& pt = impl_->pts[static_cast<std::size_t>(point)];
  return impl_->evaluate(pt, c, pt.q, motion, rows, contact);
}

Status SwingCamLift::evaluate_at(int position, double cam_deg, std::span<const double> c, double motion[4],
                                 Eigen::Ref<Eigen::Matrix<double, 4, Eigen::Dynamic>> rows) {
  Impl& m = *impl_;
  // the nearest grid point of this position: its follower angle starts newton, and the
  // drive is solved there first so the solver's warm start stays on the assembled branch
  const Impl::Point* near = nullptr;
  double best = 1e300;
  for (const auto& o : m.pts) {
    if (o.position != position) continue;
    const double dd = std::abs(std::remainder(o.cam_deg - cam_deg, 360.0));
    if (dd < best) {
      best = dd;
      near = &o;
    }
  }
  CAMOPT_ASSERT(near != nullptr);
  kin::Workspace& ws = m.up_ws[static_cast<std::size_t>(position)];
  for (double deg : {near->cam_deg, cam_deg}) {
    const Status st = kin::solve(m.up, ws, deg * rad_per_deg, {3, false});
    if (!st.ok()) return st;
    if (deg == near->cam_deg &&
        std::abs(ws.vars[static_cast<std::size_t>(m.swing_var)].value() - near->psi.value()) > 1e-6) {
      // a jump to another assembly branch: walk there from the position's first point
      ws.reset();
      for (const auto& o : m.pts)
        if (o.position == position && o.cam_deg <= near->cam_deg)
          if (Status w = kin::solve(m.up, ws, o.cam_deg * rad_per_deg, {0, false}); !w.ok()) return w;
    }
  }
  Impl::Point pt;
  pt.position = position;
  pt.cam_deg = cam_deg;
  pt.psi = ws.vars[static_cast<std::size_t>(m.swing_var)];
  pt.pivot = ws.pivots()[static_cast<std::size_t>(m.swing_node)];
  double q = near->q;
  return m.evaluate(pt, c, q, motion, rows);
}

void SwingCamLift::pitch_lift(std::span<const double> c, double s_rad, double out[5]) const {
  impl_->h_derivatives(c, s_rad, out);
}

Status SwingCamLift::profile_table(std::span<const double> c, int points, double min_convex_radius_mm,
                                   std::vector<double>& angle_deg, std::vector<double>& radius_mm) const {
  const Impl& m = *impl_;
  // pitch curve over one turn: dwell, working curve to kNoseMargin past the farthest contact
  // at any position (the coefficients beyond it are free of every constraint, so it stops
  // there), a nose to zero slope (nose_at) and the mirror image of all of it back to the
  // dwell (c3 at the top). The nose is the shortest of kNoseLengths whose pitch curve keeps a
  // convex radius >= roller radius + min_convex_radius_mm (the surface then does not fold
  // and its convex radius is >= min_convex_radius_mm).
  constexpr double kNoseMargin = 0.25 * rad_per_deg;  // covers the grid's miss of the farthest contact
  constexpr double kNoseLengths[] = {4, 6, 8, 10, 12, 16, 20, 24, 32, 40, 48};  // [swing deg]
  double s_c = m.sa;
  for (const auto& pt : m.pts) {
    double q = pt.q, px, py, s;
    if (!m.solve_q(c, pt.psi.value(), pt.pivot, q, false)) continue;
    m.frame(q, pt.psi.value(), pt.pivot, px, py, s);
    s_c = std::max(s_c, s);
  }
  const double s_e = std::min(m.sb, s_c + kNoseMargin);
  double hb[5];
  m.h_derivatives(c, s_e, hb);
  hb[0] += m.rho0;
  const double kappa_max = 1.0 / (m.r_roller + min_convex_radius_mm);
  // rho and its derivatives per rad at `along` [rad] past s_e on a nose of `length`
  auto nose_at = [&](double length, double along, double r[3]) {
    double d[4];
    synthesis::nose_septic(hb[0], hb[1], hb[2], length).eval(along / length, d);
    r[0] = d[0], r[1] = d[1] / length, r[2] = d[2] / (length * length);
  };
  double nose = 0.0, tightest = 0.0;
  for (double length_deg : kNoseLengths) {
    const double length = length_deg * rad_per_deg;
    double worst = 0.0;
    for (int k = 0; k <= 200; ++k) {
      double r[3];
      nose_at(length, length * k / 200.0, r);
      worst = std::max(worst, synthesis::polar_curvature(r[0], r[1], r[2]));
    }
    if (worst <= kappa_max) {
      nose = length;
      break;
    }
    tightest = tightest == 0.0 ? worst : std::min(tightest, worst);
  }
  if (nose == 0.0)
    return {StatusCode::undercut,
            "the swing cam's nose past the farthest contact cannot turn back within " +
                num(kNoseLengths[std::size(kNoseLengths) - 1]) + " swing deg with a convex surface radius >= " +
                num(min_convex_radius_mm) + " mm (pitch slope there " + num(hb[1] * rad_per_deg) +
                " mm per swing deg; tightest pitch radius " + num(1.0 / tightest) + " mm against roller " +
                num(m.r_roller) + " mm)",
            "swing " + num(s_e / rad_per_deg) + " deg"};
  const double base = std::atan2(m.e0.y(), m.e0.x());
  const double s_n = s_e + nose, s_hi = 2 * s_n - m.sa;
  const double co = std::cos(m.profile_orientation), so = std::sin(m.profile_orientation);
  std::vector<std::pair<double, double>> polar;
  double previous = 0.0, turned = 0.0;  // the surface's polar angle, unwrapped along the table [rad]
  for (int i = 0; i < points; ++i) {
    const double sv = s_hi - 2 * pi + 2 * pi * (i + 0.5) / points;
    const double se = sv > s_n ? 2 * s_n - sv : sv, sign = sv > s_n ? -1.0 : 1.0;
    double rho = m.rho0, drho = 0.0;
    if (se <= s_e) {
      double hd[5];
      m.h_derivatives(c, se, hd);
      rho += hd[0];
      drho = sign * hd[1];
    } else {
      double r[3];
      nose_at(nose, se - s_e, r);
      rho = r[0];
      drho = sign * r[1];
    }
    const double phi = base + m.sigma * sv;
    const Eigen::Vector2d er{std::cos(phi), std::sin(phi)}, et{-std::sin(phi), std::cos(phi)};
    const Eigen::Vector2d x = m.ps0 + rho * er;
    const Eigen::Vector2d tangent = drho * er + m.sigma * rho * et;
    Eigen::Vector2d normal{tangent.y(), -tangent.x()};
    normal.normalize();
    if (normal.dot(er) < 0) normal = -normal;
    const Eigen::Vector2d y = x - m.r_roller * normal - m.profile_origin;
    const Eigen::Vector2d local{co * y.x() + so * y.y(), -so * y.x() + co * y.y()};
    const double a = std::atan2(local.y(), local.x());
    // the surface must run round its origin in one sense: a step back is a fold
    if (i > 0) {
      double step = a - previous;
      step -= 2 * pi * std::round(step / (2 * pi));
      if (i > 1 && step * turned <= 0)
        return {StatusCode::undercut,
                "the swing cam's surface folds back (undercut: the pitch curve's convex radius is below the roller "
                "radius " + num(m.r_roller) + " mm)",
                "swing " + num(se / rad_per_deg) + " deg, profile " + num(a / rad_per_deg) + " deg"};
      turned += step;
    }
    previous = a;
    polar.emplace_back(a < 0 ? a / rad_per_deg + 360.0 : a / rad_per_deg, local.norm());
  }
  std::sort(polar.begin(), polar.end());
  angle_deg.clear();
  radius_mm.clear();
  for (const auto& [a, r] : polar) {
    if (!angle_deg.empty() && a - angle_deg.back() < 1e-9) continue;
    angle_deg.push_back(a);
    radius_mm.push_back(r);
  }
  return Status::success();
}

}  // namespace camopt::opt
