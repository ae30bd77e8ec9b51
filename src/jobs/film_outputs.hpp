#pragma once
// the EHL film thickness outputs of `dynamics --model rigid` for a design with [oil]
// (docs/dynamics.md, "EHL film thickness"): per contact with Hertz data (materials and
// width_mm), the Dowson-Higginson minimum film and its lambda ratio at every point
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/dynamics/rigid.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::jobs {

// contacts that get film columns: every contact with Hertz data, when the design has [oil]
bool has_film(const dynamics::Model& model, const std::optional<OilSpec>& oil, std::size_t connection);

// the minimum film [um] of contact c at a point of the sweep at cam speed w [rad/s], from its
// rigid force, the kinematic curvatures and entrainment; nullopt for an open or tensile
// contact (force <= 0) or conforming surfaces (1/R <= 0). An entrainment below round-off
// (1e-9 x the mechanism size per rad, as for sliding: a follower at rest on the base circle)
// is none, and so is the film.
std::optional<double> film_um(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model,
                              const OilSpec& oil, std::size_t point, int c, double w);

// the summary fields of contact c at one speed and control position: min_film_thickness_um,
// min_film_thickness_at_cam_deg, and with a composite roughness min_lambda and
// min_lambda_at_cam_deg; an empty object when the contact carries no film there
nlohmann::json film_fields(const kin::Mechanism& mech, const dynamics::RigidSweep& s, const dynamics::Model& model,
                           const OilSpec& oil, int c, double w);

// summary.json "film": per control position and contact with a film, the thinnest film and
// the lowest lambda over every rpm and cam angle, with where (rpm, cam deg); null when the
// contact never carries a film
nlohmann::json film_summary(const kin::Mechanism& mech, const dynamics::Model& model, const OilSpec& oil,
                            const std::vector<dynamics::RigidSweep>& sweeps, const std::vector<double>& rpms,
                            const std::vector<double>& control_values, const std::string& control_key);

}  // namespace camopt::jobs
