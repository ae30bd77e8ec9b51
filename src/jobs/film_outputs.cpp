#include "film_outputs.hpp"

#include <cmath>
#include <limits>

#include "camopt/dynamics/ehl.hpp"

namespace camopt::jobs {

namespace {

// the thinnest film over the points of one sweep at one speed [um], and where [cam deg]
struct Thinnest {
  double film = std::numeric_limits<double>::infinity();
  double at_cam_deg = 0.0;
  bool any() const { return film < std::numeric_limits<double>::infinity(); }
};

// an entrainment below this times the mechanism size [mm per rad] is round-off (the rigid
// model's rule for sliding)
constexpr double kStillEntrainment = 1e-9;

Thinnest thinnest(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model,
                  const OilSpec& oil, int c, double w) {
  Thinnest t;
  for (std::size_t i = 0; i < s.points(); ++i) {
    const auto h = film_um(mech, s, model, oil, i, c, w);
    if (h && *h < t.film) t = {*h, s.cam_deg[i]};
  }
  return t;
}

}  // namespace

bool has_film(const dynamics::Model& model, const std::optional<OilSpec>& oil, std::size_t connection) {
  return oil && model.contacts[connection].is_contact && model.contacts[connection].has_hertz;
}

std::optional<double> film_um(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model,
                              const OilSpec& oil, std::size_t point, int c, double w) {
  const auto& cs = s.contact[point * static_cast<std::size_t>(s.connections) + static_cast<std::size_t>(c)];
  const auto& cd = model.contacts[static_cast<std::size_t>(c)];
  if (cs.open) return std::nullopt;
  const double entrainment = std::abs(cs.entrainment) > kStillEntrainment * mech.length_scale ? cs.entrainment : 0.0;
  return dynamics::line_contact_film_um(s.force_at(point, c, w), cd.width, cd.e_star, cs.curvature_a + cs.curvature_b,
                                        entrainment, w, oil);
}

nlohmann::json film_fields(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model,
                           const OilSpec& oil, int c, double w) {
  nlohmann::json j = nlohmann::json::object();
  const Thinnest t = thinnest(mech, s, model, oil, c, w);
  if (!t.any()) return j;
  j["min_film_thickness_um"] = t.film;
  j["min_film_thickness_at_cam_deg"] = t.at_cam_deg;
  // lambda is the film over a constant: its minimum is where the film's is
  if (oil.composite_roughness_um) {
    j["min_lambda"] = dynamics::film_lambda(t.film, *oil.composite_roughness_um);
    j["min_lambda_at_cam_deg"] = t.at_cam_deg;
  }
  return j;
}

nlohmann::json film_summary(const kin::Mechanism& mech, const dynamics::Model& model, const OilSpec& oil,
                            const std::vector<dynamics::RigidSweep>& sweeps, const std::vector<double>& rpms,
                            const std::vector<double>& control_values, const std::string& control_key) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t p = 0; p < sweeps.size(); ++p) {
    nlohmann::json j;
    j[control_key] = control_values[p];
    j["contacts"] = nlohmann::json::object();
    for (std::size_t c = 0; c < mech.connections.size(); ++c) {
      if (!has_film(model, oil, c)) continue;
      Thinnest best;
      double best_rpm = 0.0;
      for (double rpm : rpms) {
        const double w = dynamics::cam_speed_rad_per_s(rpm, model.crank_per_cam);
        const Thinnest t = thinnest(mech, sweeps[p], model, oil, static_cast<int>(c), w);
        if (t.any() && t.film < best.film) best = t, best_rpm = rpm;
      }
      nlohmann::json cj = nullptr;
      if (best.any()) {
        cj = {{"min_film_thickness_um", best.film}, {"at_rpm", best_rpm}, {"at_cam_deg", best.at_cam_deg}};
        if (oil.composite_roughness_um)
          cj["min_lambda"] = dynamics::film_lambda(best.film, *oil.composite_roughness_um);
      }
      j["contacts"][mech.connections[c].name] = cj;
    }
    out.push_back(j);
  }
  return out;
}

}  // namespace camopt::jobs
