#include "profile_exports.hpp"

#include <utility>

#include "camopt/io/csv.hpp"
#include "camopt/io/design_rewrite.hpp"
#include "camopt/io/dxf.hpp"

namespace camopt::jobs {

ProfileExports profile_exports(const std::string& out_dir, const std::string& design_path,
                               const std::vector<io::Override>& overrides, const DesignSpec& spec,
                               const synthesis::SynthesisResult& res, std::optional<double> master_radius_mm,
                               double grinding_step_deg, nlohmann::json& report, bool grinding_optional) {
  std::vector<double> excess(res.radius_mm.size());
  for (std::size_t i = 0; i < excess.size(); ++i) excess[i] = res.radius_mm[i] - res.base_radius_mm;
  report["profile"] = {{"name", res.profile.name},
                       {"points", res.angle_deg.size()},
                       {"base_circle_radius_mm", res.base_radius_mm},
                       {"max_radius_mm", res.max_radius_mm},
                       {"max_excess_radius_mm", res.max_radius_mm - res.base_radius_mm}};

  // grinding table for a master roller: by default the follower's own roller
  double master = master_radius_mm.value_or(0.0);
  if (!master_radius_mm)
    for (const auto& c : spec.connections)
      if (c.name == res.connection) {
        const auto& fs = c.surface_a.node == res.follower_node ? c.surface_a : c.surface_b;
        if (fs.shape == SurfaceShape::circle) master = fs.radius_mm;
      }
  std::vector<double> grind_deg, grind_lift;
  Status st = synthesis::grinding_table(res.profile, master, grinding_step_deg, grind_deg, grind_lift);
  if (!st.ok()) {
    st.message = "grinding table with a " + std::to_string(master) + " mm master: " + st.message;
    if (!grinding_optional) throw NumericalError(st);
  }
  report["exports"] = {{"dxf", "profile.dxf"},
                       {"grinding_table", st.ok() ? std::string("grinding.csv") : "not computed: " + st.str()},
                       {"grinding_master_radius_mm", master},
                       {"grinding_master", master > 0 ? "roller" : "flat"}};

  ProfileExports files;
  files.dxf = io::dxf_closed_polyline(res.x_mm, res.y_mm, "CAM_" + res.profile.name);
  if (st.ok()) files.grinding = {{"cam_deg", "master_lift_mm"}, {std::move(grind_deg), std::move(grind_lift)}, {}};
  files.profile = {{"angle_deg", "radius_mm", "excess_radius_mm", "x_mm", "y_mm", "radius_of_curvature_mm"},
                   {res.angle_deg, res.radius_mm, excess, res.x_mm, res.y_mm, res.radius_of_curvature_mm},
                   {}};
  // design.toml names profile.csv beside it, so the folder can be moved or handed on
  files.design_toml = io::design_with_profile_file(design_path, res.profile.name, "profile.csv", out_dir, overrides);
  return files;
}

std::vector<std::pair<std::string, std::string>> export_files(const ProfileExports& exports) {
  std::vector<std::pair<std::string, std::string>> files = {{"profile.dxf", exports.dxf}};
  if (!exports.grinding.header.empty()) files.emplace_back("grinding.csv", io::format_csv(exports.grinding));
  files.emplace_back("profile.csv", io::format_csv(exports.profile));
  files.emplace_back("design.toml", exports.design_toml);
  return files;
}

}  // namespace camopt::jobs
