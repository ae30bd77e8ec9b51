// the flexible model linearised: natural frequencies and mode shapes about the static
// equilibrium at one cam angle, and the forces with their Newton matrices at a given state
// (flexible.hpp, flexible_system.hpp)
#include <Eigen/Eigenvalues>
#include <string>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/flexible.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "cvode_support.hpp"
#include "flexible_system.hpp"

namespace camopt::dynamics {

using detail::System;

Status flexible_modes(const kin::Mechanism& mech, const Model& model, const std::vector<double>& controls,
                      double cam_deg, const FlexibleOptions& options, bool release_driver_contacts,
                      FlexibleModes& out) {
  options.validate();
  System s(mech, options);
  s.omega = 0.0;
  Eigen::VectorXd x, v;
  {
    const Status st = detail::static_start(s, model, controls, cam_deg * rad_per_deg, x, v);
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
  // an HLA holds its oil: the chamber is a spring A^2 beta / V (no leak over a vibration)
  for (const detail::Plunger& p : s.plungers)
    s.jk.core(p.coord, p.coord) += detail::hla_static_stiffness(s, p) - detail::plunger_stiffness(s, p, x.data());
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
  for (const detail::Plunger& p : s.plungers) out.coordinates.push_back(mech.nodes[p.node].name + ".hla"), out.units.push_back("mm");
  for (const detail::Chain& ch : s.chains)
    for (int j = 1; j <= ch.masses; ++j) out.coordinates.push_back(ch.name + ".coil" + std::to_string(j)), out.units.push_back("mm");
  const int n = s.N;
  for (int i = 0; i < n; ++i) {
    out.frequencies_hz.push_back(std::sqrt(std::max(eig.eigenvalues()(i), 0.0)) / (2 * pi));
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
  CAMOPT_THROW_UNLESS(engine_rpm_value > 0,
                      "flexible_linearise: engine_rpm_value = " + format_value(engine_rpm_value) + " must be > 0");
  options.validate();
  System s(mech, options);
  s.omega = cam_speed_rad_per_s(engine_rpm_value, model.crank_per_cam);
  Eigen::VectorXd x, v;
  {
    const Status st = detail::static_start(s, model, controls, cam_deg * rad_per_deg, x, v);
    if (!st.ok()) return st;
  }
  const int n = s.N;
  if (!q.empty()) {
    CAMOPT_THROW_UNLESS(static_cast<int>(q.size()) == n, "flexible_linearise: q has " + std::to_string(q.size()) +
                                                             " entries; the extended coordinates are " +
                                                             std::to_string(n) + " (or none: the static start)");
    x = Eigen::Map<const Eigen::VectorXd>(q.data(), n);
  }
  if (!qd.empty()) {
    CAMOPT_THROW_UNLESS(static_cast<int>(qd.size()) == n, "flexible_linearise: qd has " + std::to_string(qd.size()) +
                                                              " entries; the extended coordinates are " +
                                                              std::to_string(n) + " (or none: the static start)");
    v = Eigen::Map<const Eigen::VectorXd>(qd.data(), n);
  }
  s.evaluate(0.0);
  s.forces(x.data(), v.data());
  s.newton_matrices(x.data(), v.data(), s.jk, s.jd);
  const Eigen::MatrixXd k = s.jk.dense(s.chains, n), d = s.jd.dense(s.chains, n);
  out.layout = {s.R, s.E, n - s.core(), s.P, 0};
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
