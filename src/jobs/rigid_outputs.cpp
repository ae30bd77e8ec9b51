#include "rigid_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "camopt/dynamics/ehl.hpp"
#include "camopt/dynamics/hertz.hpp"
#include "camopt/io/csv.hpp"
#include "film_outputs.hpp"

namespace camopt::jobs {

namespace {

using Sweep = dynamics::RigidSweep;

// a NaN in a column that may be empty: an empty cell
constexpr double kEmpty = std::numeric_limits<double>::quiet_NaN();

// json number, or null for +-inf
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// the columns of the rigid model's dynamics.csv (long format: rpm, control, cam angle)
class RigidTable {
 public:
  RigidTable(const DynamicsSetup& su, const std::vector<Sweep>& sweeps) : su_(su), sweeps_(sweeps) {}

  // a column filled by value(sweep, point, omega, rpm, position); with may_be_empty a NaN is
  // written as an empty cell (a quantity that does not exist at that point)
  template <class Value>
  void add(std::string name, Value&& value, bool may_be_empty = false) {
    header.push_back(std::move(name));
    may_be_empty_.push_back(may_be_empty);
    std::vector<double> col;
    col.reserve(su_.rpms.size() * sweeps_.size() * sweeps_[0].points());
    for (double rpm : su_.rpms) {
      const double w = dynamics::cam_speed_rad_per_s(rpm, su_.model.crank_per_cam);
      for (std::size_t p = 0; p < sweeps_.size(); ++p)
        for (std::size_t i = 0; i < sweeps_[p].points(); ++i) col.push_back(value(sweeps_[p], i, w, rpm, p));
    }
    cols.push_back(std::move(col));
  }
  // the table, moved out
  io::Columns take() { return {std::move(header), std::move(cols), std::move(may_be_empty_)}; }

  std::vector<std::string> header;
  std::vector<std::vector<double>> cols;

 private:
  const DynamicsSetup& su_;
  const std::vector<Sweep>& sweeps_;
  std::vector<bool> may_be_empty_;
};

// Hertz line contact of contact c at a point, at cam speed w
dynamics::HertzLine hertz_at(const DynamicsSetup& su, const Sweep& s, std::size_t i, int c, double w) {
  const auto& cs = s.contact[i * su.mech.connections.size() + static_cast<std::size_t>(c)];
  const auto& cd = su.model.contacts[static_cast<std::size_t>(c)];
  return dynamics::hertz_line(s.force_at(i, c, w), cd.width, cd.e_star, cs.curvature_a + cs.curvature_b);
}

// the EHL film of a contact with Hertz data, for a design with [oil]: the Dowson-Higginson
// minimum film [um] and, with a composite roughness, lambda; an empty cell where the contact
// has no film (open, tensile, conforming)
void add_film_columns(const DynamicsSetup& su, RigidTable& t, const std::string& prefix, int ci) {
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const OilSpec& oil = *su.model.oil;
  t.add(
      prefix + "film_thickness_um",
      [&mech, &model, &oil, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
        return film_um(mech, s, model, oil, i, ci, w).value_or(kEmpty);
      },
      true);
  if (oil.composite_roughness_um)
    t.add(
        prefix + "lambda",
        [&mech, &model, &oil, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          const auto h = film_um(mech, s, model, oil, i, ci, w);
          return h ? dynamics::film_lambda(*h, *oil.composite_roughness_um) : kEmpty;
        },
        true);
}

// per contact: force, Hertz, sliding, entrainment, film (with [oil]) and gap; per link its
// force, per gear its torque
void add_connection_columns(const DynamicsSetup& su, RigidTable& t) {
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t nc = mech.connections.size();
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& conn = mech.connections[c];
    const int ci = static_cast<int>(c);
    switch (conn.kind) {
      case ConnectionKind::contact: {
        const std::string n = "contact_" + conn.name + "_";
        t.add(n + "force_N", [ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          return s.force_at(i, ci, w);
        });
        if (model.contacts[c].has_hertz) {
          t.add(n + "hertz_MPa", [&su, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
            return hertz_at(su, s, i, ci, w).max_pressure;
          });
          t.add(n + "half_width_mm", [&su, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
            return hertz_at(su, s, i, ci, w).half_width;
          });
        }
        // [mm per rad] * [rad/s] -> [m/s]
        t.add(n + "sliding_m_per_s", [nc, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          return s.contact[i * nc + ci].sliding * w * 1e-3;
        });
        t.add(n + "entrainment_m_per_s", [nc, ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          return s.contact[i * nc + ci].entrainment * w * 1e-3;
        });
        if (has_film(model, su.model.oil, c)) add_film_columns(su, t, n, ci);
        t.add(n + "gap_mm", [nc, ci](const Sweep& s, std::size_t i, double, double, std::size_t) {
          return s.contact[i * nc + ci].gap;
        });
        break;
      }
      case ConnectionKind::link:
      case ConnectionKind::crank_slider:
      case ConnectionKind::rack_pinion:
        t.add("link_" + conn.name + "_force_N", [ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          return s.force_at(i, ci, w);
        });
        break;
      case ConnectionKind::gear:
      case ConnectionKind::variable_gear:
        t.add("gear_" + conn.name + "_torque_Nm", [ci](const Sweep& s, std::size_t i, double w, double, std::size_t) {
          return s.force_at(i, ci, w) * 1e-3;
        });
        break;
    }
  }
}

// springs (load, margin), the gas force, and per moving node and coordinate the generalized
// force of each load on it [N or N m]: d'Alembert inertia -m a, the springs, their dampers
// -c v, the gas force
void add_load_columns(const DynamicsSetup& su, RigidTable& t) {
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  for (std::size_t k = 0; k < model.springs.size(); ++k) {
    const auto& sp = model.springs[k];
    const bool torsion = sp.kind == SpringKind::torsion;
    const double scale = torsion ? 1e-3 : 1.0;  // N mm -> N m
    const std::string unit = torsion ? "Nm" : "N";
    const int si = static_cast<int>(k);
    t.add("spring_" + sp.name + "_load_" + unit,
          [si, scale](const Sweep& s, std::size_t i, double, double, std::size_t) {
            return s.spring_load[i * s.springs + si] * scale;
          });
    t.add("spring_" + sp.name + "_margin_" + unit,
          [&model, si, scale](const Sweep& s, std::size_t i, double w, double, std::size_t) {
            return dynamics::spring_margin(s, model, i, si, w) * scale;
          });
  }
  if (!model.gas_forces.empty())
    t.add("gas_force_N", [](const Sweep& s, std::size_t i, double, double, std::size_t) { return s.gas_force[i]; });
  for (int v = 0; v < static_cast<int>(mech.variables.size()); ++v) {
    if (model.row_of_variable[v] < 0) continue;
    int n = 0;
    for (int k = 0; k < static_cast<int>(mech.nodes.size()); ++k)
      if (mech.nodes[k].first_variable >= 0 && v >= mech.nodes[k].first_variable &&
          v < mech.nodes[k].first_variable + (mech.nodes[k].kind == NodeKind::floating ? 3 : 1))
        n = k;
    const auto& node = mech.nodes[n];
    const int sub = v - node.first_variable;
    const bool angle = node.kind == NodeKind::rotational || (node.kind == NodeKind::floating && sub == 2);
    const std::string pre = "node_" + node.name + "_" +
                            (node.kind == NodeKind::floating ? std::string(sub == 0 ? "x_" : sub == 1 ? "y_" : "phi_") : "");
    const std::string unit = angle ? "Nm" : "N";
    const double scale = angle ? 1e-3 : 1.0;  // N mm -> N m
    auto load = [v, scale](const Sweep& s, std::size_t i, int first, int last, double weight) {
      double f = 0.0;
      for (int j = first; j < last; ++j) f += s.loads[(i * s.variables + v) * s.cases + j];
      return -f * weight * scale;
    };
    t.add(pre + "inertia_" + unit,
          [load](const Sweep& s, std::size_t i, double w, double, std::size_t) { return load(s, i, 0, 1, w * w); });
    t.add(pre + "spring_" + unit, [load](const Sweep& s, std::size_t i, double, double, std::size_t) {
      return load(s, i, 2, s.cases - 1, 1.0);
    });
    t.add(pre + "damping_" + unit, [load](const Sweep& s, std::size_t i, double w, double, std::size_t) {
      return load(s, i, s.cases - 1, s.cases, w);
    });
    t.add(pre + "gas_" + unit,
          [load](const Sweep& s, std::size_t i, double, double, std::size_t) { return load(s, i, 1, 2, 1.0); });
  }
}

// pivot reactions of rotational nodes, guide forces of translational ones
void add_reaction_columns(const DynamicsSetup& su, RigidTable& t) {
  const kin::Mechanism& mech = su.mech;
  for (std::size_t n = 1; n < mech.nodes.size(); ++n) {
    const auto& node = mech.nodes[n];
    if (node.kind == NodeKind::floating) continue;  // held by its connections only
    const int ni = static_cast<int>(n);
    const std::string pre = "node_" + node.name + "_";
    if (node.kind == NodeKind::rotational) {
      t.add(pre + "reaction_x_N", [ni](const Sweep& s, std::size_t i, double w, double, std::size_t) {
        return s.reaction_at(i, ni, 0, w);
      });
      t.add(pre + "reaction_y_N", [ni](const Sweep& s, std::size_t i, double w, double, std::size_t) {
        return s.reaction_at(i, ni, 1, w);
      });
      t.add(pre + "reaction_N", [ni](const Sweep& s, std::size_t i, double w, double, std::size_t) {
        return std::hypot(s.reaction_at(i, ni, 0, w), s.reaction_at(i, ni, 1, w));
      });
    } else {
      // the guide's reaction across the line of travel, along z x direction
      const Eigen::Vector2d across(-node.direction.y(), node.direction.x());
      t.add(pre + "guide_N", [ni, across](const Sweep& s, std::size_t i, double w, double, std::size_t) {
        return across.x() * s.reaction_at(i, ni, 0, w) + across.y() * s.reaction_at(i, ni, 1, w);
      });
    }
  }
}

// the whole dynamics.csv of the rigid model
RigidTable rigid_table(const DynamicsSetup& su, const std::vector<Sweep>& sweeps) {
  RigidTable t(su, sweeps);
  const double crank_per_cam = su.model.crank_per_cam;
  t.add("rpm", [](const Sweep&, std::size_t, double, double rpm, std::size_t) { return rpm; });
  t.add("control_" + su.controls.unit,
        [&su](const Sweep&, std::size_t, double, double, std::size_t p) { return su.controls.values[p]; });
  t.add("cam_deg", [](const Sweep& s, std::size_t i, double, double, std::size_t) { return s.cam_deg[i]; });
  t.add("crank_deg", [crank_per_cam](const Sweep& s, std::size_t i, double, double, std::size_t) {
    return s.cam_deg[i] * crank_per_cam;
  });
  const kin::Node& out_node = su.mech.nodes[su.mech.output_node];
  t.add(out_node.kind == NodeKind::translational ? "lift_mm" : "lift_deg",
        [](const Sweep& s, std::size_t i, double, double, std::size_t) { return s.output[i]; });
  add_connection_columns(su, t);
  t.add("cam_torque_Nm", [](const Sweep& s, std::size_t i, double w, double, std::size_t) {
    return s.torque_at(i, w) * 1e-3;
  });
  add_load_columns(su, t);
  add_reaction_columns(su, t);
  return t;
}

// cam torque extremes and mean [N m] at cam speed w
void add_torque_fields(const Sweep& s, double w, nlohmann::json& j) {
  const std::size_t np = s.points();
  Extremes torque;
  double torque_mean = 0.0;
  for (std::size_t i = 0; i < np; ++i) {
    const double t = s.torque_at(i, w) * 1e-3;
    torque.add(t, s.cam_deg[i]);
    torque_mean += t / static_cast<double>(np);
  }
  j["max_cam_torque_Nm"] = torque.max;
  j["max_cam_torque_at_cam_deg"] = torque.max_at;
  j["min_cam_torque_Nm"] = torque.min;
  j["min_cam_torque_at_cam_deg"] = torque.min_at;
  j["mean_cam_torque_Nm"] = torque_mean;
}

// connection c at cam speed w over the points where it is closed: force extremes (gears:
// torque); contacts add Hertz, sliding, the film (with [oil]) and whether it separates
nlohmann::json connection_fields(const DynamicsSetup& su, const Sweep& s, std::size_t c, double w, bool& separates) {
  const auto& conn = su.mech.connections[c];
  const auto& cd = su.model.contacts[c];
  const std::size_t nc = su.mech.connections.size();
  const int ci = static_cast<int>(c);
  const bool contact = conn.kind == ConnectionKind::contact;
  Extremes f, hz;
  double max_sliding = 0.0;
  for (std::size_t i = 0; i < s.points(); ++i) {
    if (contact && s.contact[i * nc + c].open) continue;
    f.add(s.force_at(i, ci, w), s.cam_deg[i]);
    if (cd.has_hertz) hz.add(hertz_at(su, s, i, ci, w).max_pressure, s.cam_deg[i]);
    if (contact) max_sliding = std::max(max_sliding, std::abs(s.contact[i * nc + c].sliding * w * 1e-3));
  }
  nlohmann::json cj;
  const double scale = conn.kind == ConnectionKind::gear || conn.kind == ConnectionKind::variable_gear ? 1e-3 : 1.0;
  const std::string unit = scale != 1.0 ? "Nm" : "N";
  if (std::isfinite(f.max)) {
    cj["max_force_" + unit] = f.max * scale;
    cj["max_force_at_cam_deg"] = f.max_at;
    cj["min_force_" + unit] = f.min * scale;
    cj["min_force_at_cam_deg"] = f.min_at;
  }
  if (contact) {
    if (std::isfinite(hz.max)) {
      cj["max_hertz_MPa"] = hz.max;
      cj["max_hertz_at_cam_deg"] = hz.max_at;
    }
    cj["max_sliding_m_per_s"] = max_sliding;
    if (has_film(su.model, su.model.oil, c)) cj.update(film_fields(su.mech, s, su.model, *su.model.oil, ci, w));
    const bool opens = !cd.two_sided && std::isfinite(f.min) && f.min < 0.0;
    cj["separates"] = opens;
    separates |= opens;
  }
  return cj;
}

// one results[] entry: the run at one rpm and control position
nlohmann::json rigid_result(const DynamicsSetup& su, const Sweep& s, double rpm, std::size_t p) {
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  const std::size_t np = s.points();
  const double w = dynamics::cam_speed_rad_per_s(rpm, model.crank_per_cam);
  nlohmann::json j;
  j["rpm"] = rpm;
  j["control_" + su.controls.unit] = su.controls.values[p];
  add_torque_fields(s, w, j);
  bool separates = false;
  for (std::size_t c = 0; c < mech.connections.size(); ++c)
    j["connections"][mech.connections[c].name] = connection_fields(su, s, c, w, separates);
  j["any_contact_separates"] = separates;
  for (std::size_t k = 0; k < model.springs.size(); ++k) {
    const auto& sp = model.springs[k];
    const double scale = sp.kind == SpringKind::torsion ? 1e-3 : 1.0;
    const std::string unit = sp.kind == SpringKind::torsion ? "Nm" : "N";
    Extremes margin, fraction;
    for (std::size_t i = 0; i < np; ++i) {
      const double m = dynamics::spring_margin(s, model, i, static_cast<int>(k), w);
      const double load = s.spring_load[i * s.springs + k];
      margin.add(m * scale, s.cam_deg[i]);
      if (load != 0.0) fraction.add(m / load, s.cam_deg[i]);
    }
    j["springs"][sp.name] = {{"min_margin_" + unit, margin.min},
                             {"min_margin_at_cam_deg", margin.min_at},
                             {"min_margin_fraction", finite_or_null(fraction.min)},
                             {"min_margin_fraction_at_cam_deg", fraction.min_at}};
  }
  for (std::size_t n = 1; n < mech.nodes.size(); ++n) {
    if (mech.nodes[n].kind != NodeKind::rotational) continue;
    Extremes r;
    for (std::size_t i = 0; i < np; ++i)
      r.add(std::hypot(s.reaction_at(i, static_cast<int>(n), 0, w), s.reaction_at(i, static_cast<int>(n), 1, w)),
            s.cam_deg[i]);
    j["pivot_reactions"][mech.nodes[n].name] = {{"max_N", r.max}, {"max_at_cam_deg", r.max_at}};
  }
  return j;
}

}  // namespace

io::Columns rigid_columns(const DynamicsSetup& su, const std::vector<Sweep>& sweeps) {
  return rigid_table(su, sweeps).take();
}

nlohmann::json rigid_summary_head(const DynamicsSetup& su, const std::string& design_file, const std::string& what,
                                  const std::string& mode) {
  nlohmann::json summary;
  summary["design"] = su.mech.name;
  if (const auto held = held_rigid_hlas(su.spec, what, su.observer); !held.empty()) summary["hla_held_rigid"] = held;
  summary["design_file"] = design_file;
  summary["model"] = "rigid";
  summary["mode"] = mode;
  summary["step_cam_deg"] = su.range.step;
  return summary;
}

nlohmann::json rigid_summary(const DynamicsSetup& su, const std::string& design_file, const std::vector<Sweep>& sweeps,
                             double seconds) {
  const kin::Mechanism& mech = su.mech;
  const dynamics::Model& model = su.model;
  nlohmann::json summary =
      rigid_summary_head(su, design_file, "dynamics (rigid)", "kinematically constrained inverse dynamics (a)");
  summary["points_per_position"] = sweeps[0].points();
  summary["run_time_s"] = seconds;
  nlohmann::json separation = nlohmann::json::array();
  for (std::size_t p = 0; p < sweeps.size(); ++p) {
    nlohmann::json j;
    j["control_" + su.controls.unit] = su.controls.values[p];
    for (std::size_t c = 0; c < mech.connections.size(); ++c) {
      if (!model.contacts[c].is_contact) continue;
      // refined between the grid points
      dynamics::Separation sep;
      const Status st = dynamics::refined_separation_speed(mech, model, sweeps[p], static_cast<int>(c), sep);
      if (!st.ok()) fail_at_position(mech, su.controls, st, p);
      j["contacts"][mech.connections[c].name] = {{"separation_rpm", finite_or_null(sep.engine_rpm)},
                                                 {"at_cam_deg", std::isfinite(sep.engine_rpm) ? nlohmann::json(sep.cam_deg)
                                                                                              : nlohmann::json(nullptr)}};
    }
    separation.push_back(j);
  }
  summary["separation"] = separation;
  nlohmann::json results = nlohmann::json::array();
  for (double rpm : su.rpms)
    for (std::size_t p = 0; p < sweeps.size(); ++p) results.push_back(rigid_result(su, sweeps[p], rpm, p));
  summary["results"] = results;
  if (su.model.oil)
    summary["film"] =
        film_summary(mech, model, *su.model.oil, sweeps, su.rpms, su.controls.values, "control_" + su.controls.unit);
  return summary;
}

}  // namespace camopt::jobs
