#include "profile_exports.hpp"

#include "camopt/io/csv.hpp"
#include "camopt/io/design_rewrite.hpp"
#include "camopt/io/dxf.hpp"
#include "cli_common.hpp"

namespace camopt::cli {

void stage_profile_exports(io::OutputTransaction& out, const std::string& out_dir, const std::string& design_path,
                           const DesignSpec& spec, const synthesis::SynthesisResult& res,
                           std::optional<double> master_radius_mm, double grinding_step_deg, nlohmann::json& report,
                           bool grinding_optional) {
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

  out.stage("profile.dxf", io::dxf_closed_polyline(res.x_mm, res.y_mm, "CAM_" + res.profile.name));
  if (st.ok()) out.stage("grinding.csv", io::format_csv({"cam_deg", "master_lift_mm"}, {grind_deg, grind_lift}));
  out.stage("profile.csv",
            io::format_csv({"angle_deg", "radius_mm", "excess_radius_mm", "x_mm", "y_mm", "radius_of_curvature_mm"},
                           {res.angle_deg, res.radius_mm, excess, res.x_mm, res.y_mm, res.radius_of_curvature_mm}));
  // design.toml names profile.csv beside it, so the folder can be moved or handed on
  out.stage("design.toml", io::design_with_profile_file(design_path, res.profile.name, "profile.csv", out_dir,
                                                                design_overrides()));
}

}  // namespace camopt::cli
