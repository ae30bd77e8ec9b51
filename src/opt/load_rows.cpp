#include "load_rows.hpp"

#include <cmath>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/ehl.hpp"

namespace camopt::opt::detail {

namespace {

// the largest separation speed a row reports [rpm]: "none below this"
constexpr double kNoSeparationRpm = 1e6;
// Dowson-Higginson line contact (dynamics/ehl.hpp): h = 2.65 U^0.70 G^0.54 W^-0.13 R
constexpr double kFilmCoefficient = dynamics::kDowsonHigginsonCoefficient;
constexpr double kFilmSpeed = dynamics::kDowsonHigginsonSpeedExponent;
constexpr double kFilmMaterial = dynamics::kDowsonHigginsonMaterialExponent;
constexpr double kFilmLoad = dynamics::kDowsonHigginsonLoadExponent;

std::string num(double v) { return format_value(v, 8); }

Grad3 power(const Grad3& a, double e) {
  Grad3 out(std::pow(a.v, e));
  const double d = e * std::pow(a.v, e - 1.0);
  for (int k = 0; k < 3; ++k) out.d[static_cast<std::size_t>(k)] = d * a.d[static_cast<std::size_t>(k)];
  return out;
}
Grad3 at_least(const Grad3& a, double floor) { return a.v >= floor ? a : Grad3(floor); }
Grad3 magnitude(const Grad3& a) { return a.v < 0.0 ? -a : a; }

// smallest positive root of A + C w + B w^2 (the speed at which a force first reaches zero);
// 0 when A <= 0, infinity when none
double first_zero(double a, double b, double c) {
  if (a <= 0.0) return 0.0;
  if (b == 0.0) return c < 0.0 ? -a / c : INFINITY;
  const double disc = c * c - 4.0 * a * b;
  if (b > 0.0 && (c >= 0.0 || disc < 0.0)) return INFINITY;
  return (-c - std::sqrt(std::max(disc, 0.0))) / (2.0 * b);
}

const MaterialSpec* find_material(const DesignSpec& d, const std::string& name) {
  for (const auto& m : d.materials)
    if (m.name == name) return &m;
  return nullptr;
}

const SourceRef* given(const LoadSpec& ld, const std::string& key) {
  for (const auto& [k, where] : ld.given)
    if (k == key) return &where;
  return nullptr;
}

bool loads_needed(const OptimizationSpec& s) {
  const auto& l = s.limits;
  return l.max_hertz_stress_MPa || l.min_separation_speed_rpm || l.min_contact_force_N || l.min_spring_margin ||
         l.max_cam_torque_Nm || l.min_film_thickness_um || l.min_lambda ||
         (s.objective.peak_weight > 0 && s.objective.peak == Quantity::hertz_stress);
}

}  // namespace

LoadRows::~LoadRows() = default;

LoadRows::LoadRows(const DesignSpec& design, const OptimizationSpec& spec, const CamContactModel& contact, double omega,
                   const std::vector<std::vector<double>>& controls)
    : spec_(spec), omega_(omega), crank_per_cam_(design.driver.crank_per_cam) {
  if (!loads_needed(spec)) return;
  // the design's own rigid model, unless the set overrides it
  std::string design_lacks;
  try {
    design_ = std::make_unique<DownstreamLoads>(design, spec.cam);
  } catch (const InputError& e) {
    design_lacks = e.what();
  }
  if (design_ && spec.load) check_set_against_design(design, spec, contact);
  if (design_ && spec.load && spec.load->override_design) {
    design_.reset();
    source_ = "constraint set [load] (load.override_design = true): preload " + num(spec.load->spring_preload_N) +
              " N, rate " + num(spec.load->spring_rate_N_per_mm) + " N/mm, moving mass " + num(spec.load->moving_mass_kg) +
              " kg at the valve, in place of the design's rigid model";
  } else if (design_) {
    source_ = "the design's rigid model (masses, inertias, springs, dampers, gas force; camopt dynamics --model rigid)";
  } else if (spec.load) {
    source_ = "constraint set [load] (the design has no dynamics data: " + design_lacks + ")";
  } else {
    throw InputError("the load-based limits (separation, contact force, spring margin, torque, Hertz, film) need the "
                     "loads: the design " + design.file + " has no dynamics data (" + design_lacks +
                     "), and the constraint set has no [load] table");
  }
  if (!design_)  // the set's reduced model needs all of it
    for (const char* key : {"spring_preload_N", "spring_rate_N_per_mm", "moving_mass_kg"})
      if (!given(*spec.load, key))
        throw InputError(spec.load->where,
                         std::string("load.") + key + ": missing; the set's [load] replaces the design's loads (" + source_ +
                             ") and needs spring_preload_N, spring_rate_N_per_mm and moving_mass_kg");
  if (design_) {
    contacts_ = design_->contact_names();
    springs_ = design_->spring_names();
    for (const auto& c : controls) ws_.push_back(design_->make_workspace(c));
  } else {
    contacts_ = {contact.connection()};
    springs_ = {"[load] spring"};
  }
  contact_data(design, spec, contact);
  build_rows(spec);

  // row scales: each contact's static load with the valve at rest
  const double rest[3] = {0.0, 0.0, 0.0};
  reference_.assign(contacts_.size(), 1.0);
  if (prepare(spec.cam == "swing" ? 0.0 : spec.event.start_deg / deg_per_rad, rest, 0).ok())
    for (std::size_t k = 0; k < contacts_.size(); ++k)
      reference_[k] = std::max(1.0, std::abs(loads_[k].statics.v));
}

void LoadRows::check_set_against_design(const DesignSpec& design, const OptimizationSpec& spec,
                                        const CamContactModel& contact) {
  const LoadSpec& ld = *spec.load;
  auto disagree = [&](const std::string& key, double set_value, const std::string& unit, double design_value,
                      const std::string& design_where) {
    const SourceRef* where = given(ld, key);
    if (!where) return;
    if (ld.override_design) {
      overrides_.push_back({"load." + key, set_value, num(design_value) + " " + unit + " (" + design_where + ")"});
      return;
    }
    if (std::abs(set_value - design_value) <= 1e-3 * std::max(std::abs(design_value), 1e-12)) return;
    throw InputError(*where, "value " + num(set_value) + " " + unit + " disagrees with the design (" +
                                 design_where + ": " + num(design_value) + " " + unit +
                                 "): the optimiser takes its loads from the design, as camopt dynamics does; delete "
                                 "the key, or set load.override_design = true to optimise with the set's values "
                                 "(report.json echoes them)");
  };
  // the valve springs: every compression spring on the output node
  double preload = 0, rate = 0;
  std::string where = design.file + ": no [[spring]] on '" + design.output_node + "'";
  for (const SpringSpec& s : design.springs)
    if (s.node == design.output_node && s.kind == SpringKind::compression) {
      const bool table = !s.table_force_N.empty();
      preload += table ? s.table_force_N.front() : s.preload_N;
      rate += table ? 0.0 : s.rate_N_per_mm;
      where = s.where.str() + " preload_N / rate_N_per_mm";
    }
  disagree("spring_preload_N", ld.spring_preload_N, "N", preload, where);
  disagree("spring_rate_N_per_mm", ld.spring_rate_N_per_mm, "N/mm", rate, where);
  // the moving mass: the generalized mass at the valve with the valve shut
  auto ws = design_->make_workspace(contact.controls());
  std::vector<ContactLoad> at_rest;
  const double rest[3] = {0.0, 0.0, 1.0};
  if (design_->evaluate(0.0, rest, ws, at_rest).ok())
    disagree("moving_mass_kg", ld.moving_mass_kg, "kg", at_rest[0].inertia.d[2] * 1e3,
             design.file + ": the generalized mass of the bodies from '" + contact.follower_node() + "' to '" +
                 design.output_node + "' at the valve (node mass_kg, inertia_kg_mm2, 1/3 of spring mass_kg)");
  // the contact: width and materials
  const ConnectionSpec* conn = nullptr;
  for (const auto& c : design.connections)
    if (c.name == contact.connection()) conn = &c;
  if (conn && conn->width_mm && ld.width_mm)
    disagree("width_mm", *ld.width_mm, "mm", *conn->width_mm, conn->where.str() + " width_mm");
  const MaterialSpec* mc = find_material(design, contact.material_cam());
  const MaterialSpec* mf = find_material(design, contact.material_follower());
  if (mc && ld.youngs_modulus_cam_GPa) disagree("youngs_modulus_cam_GPa", *ld.youngs_modulus_cam_GPa, "GPa", mc->youngs_modulus_GPa, mc->where.str());
  if (mc && ld.poisson_cam) disagree("poisson_cam", *ld.poisson_cam, "", mc->poisson_ratio, mc->where.str());
  if (mf && ld.youngs_modulus_follower_GPa)
    disagree("youngs_modulus_follower_GPa", *ld.youngs_modulus_follower_GPa, "GPa", mf->youngs_modulus_GPa, mf->where.str());
  if (mf && ld.poisson_follower) disagree("poisson_follower", *ld.poisson_follower, "", mf->poisson_ratio, mf->where.str());
}

void LoadRows::contact_data(const DesignSpec& design, const OptimizationSpec& spec, const CamContactModel& contact) {
  const auto& l = spec.limits;
  const bool need = l.max_hertz_stress_MPa || l.min_film_thickness_um || l.min_lambda ||
                    (spec.objective.peak_weight > 0 && spec.objective.peak == Quantity::hertz_stress);
  if (!need) return;
  const LoadSpec* ld = spec.load ? &*spec.load : nullptr;
  const bool from_set = ld && (ld->override_design || !design_);
  width_mm_ = from_set && ld->width_mm ? *ld->width_mm : contact.width_mm();
  if (!(width_mm_ > 0))
    throw InputError("load.width_mm: the contact width is not given here nor as width_mm of connection '" +
                     contact.connection() + "' in the design");
  auto material = [&](const std::optional<double>& e, const std::optional<double>& nu, const std::string& name,
                      const std::string& side) {
    const MaterialSpec* m = find_material(design, name);
    if (from_set && e && nu) return std::pair{*e, *nu};
    if (!m)
      throw InputError("load.youngs_modulus_" + side + "_GPa / load.poisson_" + side + ": not given, and connection '" +
                       contact.connection() + "' names no [[material]] for the " + side +
                       (name.empty() ? std::string() : " ('" + name + "' is not defined)"));
    return std::pair{from_set && e ? *e : m->youngs_modulus_GPa, from_set && nu ? *nu : m->poisson_ratio};
  };
  const auto [e1, n1] = ld ? material(ld->youngs_modulus_cam_GPa, ld->poisson_cam, contact.material_cam(), "cam")
                           : material({}, {}, contact.material_cam(), "cam");
  const auto [e2, n2] = ld ? material(ld->youngs_modulus_follower_GPa, ld->poisson_follower, contact.material_follower(), "follower")
                           : material({}, {}, contact.material_follower(), "follower");
  // 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Johnson, Contact Mechanics, 1985, eq. 4.22) [MPa]
  e_star_MPa_ = 1.0 / ((1.0 - n1 * n1) / (e1 * 1e3) + (1.0 - n2 * n2) / (e2 * 1e3));
  if (!(l.min_film_thickness_um || l.min_lambda)) return;
  // the oil: the set's [oil] or the design's, and they agree when both are given
  if (spec.oil && design.oil) {
    const OilSpec& d = *design.oil;
    auto differ = [](double a, double b) { return std::abs(a - b) > 1e-9 * std::max(std::abs(b), 1e-300); };
    const std::string what = differ(spec.oil->viscosity_mPa_s, d.viscosity_mPa_s)                       ? "viscosity_mPa_s"
                             : differ(spec.oil->pressure_viscosity_per_GPa, d.pressure_viscosity_per_GPa) ? "pressure_viscosity_per_GPa"
                             : spec.oil->composite_roughness_um.value_or(-1) != d.composite_roughness_um.value_or(-1)
                                 ? "composite_roughness_um"
                                 : "";
    if (!what.empty())
      throw InputError(spec.oil->where, "oil." + what + " disagrees with the design's [oil] (" + d.where +
                                            "): the film takes one oil; delete the set's [oil] or make them agree");
  }
  if (spec.oil) {
    oil_ = *spec.oil;
  } else if (design.oil) {
    oil_ = {design.oil->viscosity_mPa_s, design.oil->pressure_viscosity_per_GPa, design.oil->composite_roughness_um, {}};
  } else {
    throw InputError("limits." + std::string(l.min_film_thickness_um ? "min_film_thickness_um" : "min_lambda") +
                     " needs an [oil] table (viscosity_mPa_s, pressure_viscosity_per_GPa, composite_roughness_um) in "
                     "the constraint set or the design");
  }
  if (l.min_lambda && !oil_.composite_roughness_um)
    throw InputError(spec.oil ? spec.oil->where : SourceRef{design.file, 0, 0, "oil"},
                     "limits.min_lambda needs oil.composite_roughness_um");
}

void LoadRows::build_rows(const OptimizationSpec& spec) {
  const auto& l = spec.limits;
  const std::size_t nc = contacts_.size(), ns = springs_.size();
  if (l.min_separation_speed_rpm)
    for (std::size_t k = 0; k < nc; ++k) rows_.push_back({ConstraintKind::separation, static_cast<int>(k)});
  if (l.min_contact_force_N) rows_.push_back({ConstraintKind::contact_force, 0});
  if (l.min_spring_margin)
    for (std::size_t k = 0; k < nc; ++k)
      for (std::size_t s = 0; s < ns; ++s)
        if (!design_ || design_->carries(k, s)) rows_.push_back({ConstraintKind::spring_margin, static_cast<int>(k * ns + s)});
  if (l.max_cam_torque_Nm) {
    rows_.push_back({ConstraintKind::cam_torque, 0});
    rows_.push_back({ConstraintKind::cam_torque, 1});
  }
  if (l.min_film_thickness_um) rows_.push_back({ConstraintKind::film_thickness, 0});
  if (l.min_lambda) rows_.push_back({ConstraintKind::lambda, 0});
}

Status LoadRows::prepare(double cam_rad, const double lift[3], int position) {
  for (int k = 0; k < 3; ++k) lift_[k] = lift[k];
  if (design_) return design_->evaluate(cam_rad, lift, ws_[static_cast<std::size_t>(position)], loads_);
  // the set's reduced model at the valve: F = preload + rate L + m L'' omega^2
  const LoadSpec& ld = *spec_.load;
  loads_.resize(1);
  ContactLoad& c = loads_[0];
  c.statics = Grad3(ld.spring_preload_N + ld.spring_rate_N_per_mm * lift[0]);
  c.statics.d = {ld.spring_rate_N_per_mm, 0.0, 0.0};
  c.damping = Grad3(0.0);
  c.inertia = Grad3(1e-3 * ld.moving_mass_kg * lift[2]);
  c.inertia.d = {0.0, 0.0, 1e-3 * ld.moving_mass_kg};
  c.spring = {c.statics};
  return Status::success();
}

Grad3 LoadRows::cam_force() const { return loads_[0].at(omega_); }

LoadRowValue LoadRows::row(const LoadRowSpec& r, const Grad3& ratio, const ContactQuantities* cq) const {
  const auto& l = spec_.limits;
  LoadRowValue out;
  const double to_rpm = 60.0 / (2.0 * pi) * crank_per_cam_;  // cam rad/s -> engine rpm
  switch (r.kind) {
    case ConstraintKind::separation: {
      // the least force over 0 .. the limit speed: A + C w + B w^2 is smallest at an end, or
      // inside when it is convex and falling (the dampers unload a closing valve)
      const ContactLoad& c = loads_[static_cast<std::size_t>(r.item)];
      const double w = *l.min_separation_speed_rpm / to_rpm;
      const Grad3 ends = c.at(w);
      Grad3 least = ends.v < c.statics.v ? ends : c.statics;
      if (c.inertia.v > 0 && c.damping.v < 0 && -c.damping.v / (2 * c.inertia.v) < w)
        least = c.statics - c.damping * c.damping / (c.inertia * 4.0);
      out.g = -least / reference_[static_cast<std::size_t>(r.item)];
      out.physical = std::min(first_zero(c.statics.v, c.inertia.v, c.damping.v) * to_rpm, kNoSeparationRpm);
      return out;
    }
    case ConstraintKind::contact_force: {
      const Grad3 f = cam_force();
      const double scale = std::max(*l.min_contact_force_N, reference_[0]);
      out.g = (*l.min_contact_force_N - ratio * f) / scale;
      out.physical = ratio.v * f.v;
      out.d_ratio = -f.v / scale;
      return out;
    }
    case ConstraintKind::spring_margin: {
      const std::size_t ns = springs_.size(), k = static_cast<std::size_t>(r.item) / ns, s = static_cast<std::size_t>(r.item) % ns;
      const ContactLoad& c = loads_[k];
      const Grad3 f = c.at(omega_);
      out.g = (c.spring[s] * *l.min_spring_margin - f) / reference_[k];
      out.physical = c.spring[s].v > 0 ? std::min(f.v / c.spring[s].v, kNoSeparationRpm) : kNoSeparationRpm;
      return out;
    }
    case ConstraintKind::cam_torque: {
      // by virtual work T omega = F L' omega [N mm]
      Grad3 l1(lift_[1]);
      l1.d = {0.0, 1.0, 0.0};
      const Grad3 t = cam_force() * l1 * (r.item == 0 ? 1e-3 : -1e-3);
      out.g = (t - *l.max_cam_torque_Nm) / *l.max_cam_torque_Nm;
      out.physical = std::abs(t.v);
      return out;
    }
    case ConstraintKind::film_thickness:
    case ConstraintKind::lambda: {
      // (h / h_lim)^(1/0.7) = |u| (...)^(1/0.7): smooth but for |u|, finite where u passes 0
      const OilSetSpec& oil = oil_;
      const double sigma = oil.composite_roughness_um.value_or(0.0);
      const double h_lim_um = r.kind == ConstraintKind::lambda ? *l.min_lambda * sigma : *l.min_film_thickness_um;
      const double e_prime = 2.0 * e_star_MPa_ * 1e6, eta = oil.viscosity_mPa_s * 1e-3, alpha = oil.pressure_viscosity_per_GPa * 1e-9;
      const double p = 1.0 / kFilmSpeed;
      const Grad3 u = magnitude(cq->entrainment) * (omega_ * 1e-3);           // [m/s]
      const Grad3 radius = at_least((1.0 / cq->inverse_radius_sum) * 1e-3, 1e-6);  // [m]
      const Grad3 w = at_least(ratio * cam_force() / (width_mm_ * 1e-3), 1.0);  // [N/m]
      const double k = std::pow(kFilmCoefficient * std::pow(alpha, kFilmMaterial) *
                                    std::pow(e_prime, -kFilmSpeed + kFilmMaterial - kFilmLoad) / (h_lim_um * 1e-6), p);
      const Grad3 q = u * (eta * k) * power(radius, (1.0 + kFilmLoad - kFilmSpeed) * p) * power(w, kFilmLoad * p);
      out.g = 1.0 - q;
      const double h_um = h_lim_um * std::pow(std::max(q.v, 0.0), kFilmSpeed);
      out.physical = r.kind == ConstraintKind::lambda ? h_um / sigma : h_um;
      return out;
    }
    default: CAMOPT_ASSERT(false);
  }
  return out;
}

}  // namespace camopt::opt::detail
