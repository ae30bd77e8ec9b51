// the synthesized cam at work: the kinematic solver run on the design synthesize wrote
// (design.toml), giving the pressure angle and the cam's radius of curvature at the contact
// against cam angle, and the lift it makes against the target (the round-trip error).
#include <cmath>
#include <system_error>

#include "camopt/core/units.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

// the made cam's lift per target point: the target's angles in cam degrees (a crank-angle
// table divided by the design's crank ratio) and its lift, when the target file is readable
struct Target {
  std::vector<double> cam_deg, lift_mm;
};

Target read_target(const nlohmann::json& report, const kin::Mechanism& mech) {
  Target t;
  const auto it = report.find("target_file");
  std::error_code ec;
  if (it == report.end() || !it->is_string() || !fs::exists(it->get<std::string>(), ec)) return t;
  // the target as synthesize read it: '#' comments, cam or crank angles
  const io::AngleTable table =
      io::read_angle_table(io::read_csv(it->get<std::string>()), {"lift_mm", "valve_lift_mm"});
  t.lift_mm = table.value;
  t.cam_deg = table.angle_deg;
  if (table.basis == io::AngleBasis::crank)
    for (double& a : t.cam_deg) a /= mech.driver.crank_per_cam;
  return t;
}

}  // namespace

void add_made_cam_plots(ReportData& data, const CompiledDesign& design, const nlohmann::json& report) {
  const auto connection = report.find("connection");
  if (connection == report.end() || !connection->is_string()) return;
  const kin::Mechanism& mech = design.mech;
  int c = -1;
  for (std::size_t i = 0; i < mech.connections.size(); ++i)
    if (mech.connections[i].name == connection->get<std::string>()) c = static_cast<int>(i);
  if (c < 0) return;
  // one revolution at 0.5 deg with the contact quantities
  kin::SweepSpec sweep{0.0, 360.0, 0.5, {mech.default_controls()}, kin::Request{1, true}, 1, {}};
  const kin::SweepResult r = kin::sweep(mech, sweep);
  const kin::PositionResult& p = r.positions.front();
  if (!p.status.ok()) {
    data.notes.push_back("the kinematic check of design.toml stopped: " + p.status.str());
    return;
  }
  // the pressure angle and the cam's radius of curvature where it touches (+ convex,
  // - concave, none where the flank is straight)
  const auto cam_node = report.find("cam_node");
  const bool cam_is_a = cam_node == report.end() || !cam_node->is_string() ||
                        mech.nodes[mech.connections[c].node_a].name == cam_node->get<std::string>();
  Plot pa = line_plot("made-pressure-angle", "Pressure angle of " + connection->get<std::string>(), "made-cam", "cam_deg",
                      "pressure_angle_deg", "made-cam");
  Plot rho = line_plot("made-radius", "Cam radius of curvature at the contact", "made-cam", "cam_deg",
                       "radius_of_curvature_mm", "made-cam");
  pa.x_values = r.driver;
  rho.x_values = r.driver;
  Series pa_s{"pressure angle", {}, {}, {}, -1, false}, rho_s{"radius of curvature", {}, {}, {}, -1, false};
  for (std::size_t i = 0; i < r.driver.size(); ++i) {
    const kin::ContactState& s = p.contacts[i * mech.connections.size() + static_cast<std::size_t>(c)];
    pa_s.y.push_back(s.pressure_angle * deg_per_rad);
    const double k = cam_is_a ? s.curvature_a : s.curvature_b;
    rho_s.y.push_back(std::abs(k) > 1e-9 ? 1.0 / k : std::numeric_limits<double>::quiet_NaN());
  }
  pa.series.push_back(std::move(pa_s));
  rho.series.push_back(std::move(rho_s));
  add_section(data, "made-cam", "The synthesized cam in the kinematic solver");
  data.plots.push_back(std::move(pa));
  data.plots.push_back(std::move(rho));
  // the lift the cam makes minus the target, at the target's points on the 0.5 deg grid
  const Target t = read_target(report, mech);
  Plot err = line_plot("made-round-trip", "Round trip: the made cam's lift minus the target", "made-cam", "cam_deg",
                       "lift_error_mm", "made-cam");
  Series e{"lift error", {}, {}, {}, -1, false};
  for (std::size_t j = 0; j < t.cam_deg.size(); ++j) {
    const double at = t.cam_deg[j] / 0.5;
    if (std::abs(at - std::round(at)) > 1e-9 || at < 0 || at >= static_cast<double>(r.driver.size())) continue;
    e.x.push_back(t.cam_deg[j]);
    e.y.push_back(kin::output_lift(mech, p, static_cast<std::size_t>(std::lround(at))) - t.lift_mm[j]);
  }
  if (e.y.empty()) {
    data.notes.push_back("no round-trip plot: the target file is not readable from here or not on a 0.5 deg grid");
    return;
  }
  err.series.push_back(std::move(e));
  data.plots.push_back(std::move(err));
}

}  // namespace camopt::report::detail
