// the mechanism animation of a report: the design the run used, its control positions and
// driver sweep, and build_scene(). A design that cannot be read from where the report is
// made leaves the animation out with a note; the rest of the report stands.
#include <algorithm>
#include <cmath>
#include <system_error>

#include "camopt/core/error.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/mechanism.hpp"
#include "camopt/report/scene.hpp"
#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

// every how many of the run's points the animation keeps a frame: at least 1 deg apart
std::size_t frame_stride(double run_step) {
  if (!(run_step > 0.0) || run_step >= 1.0) return 1;
  return static_cast<std::size_t>(std::ceil(1.0 / run_step - 1e-9));
}

// every `stride`-th frame of each position kept (the first included)
void keep_every(Scene& scene, std::size_t stride) {
  if (stride <= 1) return;
  const auto thin = [stride](std::vector<double>& v, std::size_t width) {
    std::size_t out = 0;
    for (std::size_t f = 0; f * width < v.size(); f += stride, ++out)
      for (std::size_t j = 0; j < width; ++j) v[out * width + j] = v[f * width + j];
    v.resize(out * width);
  };
  for (ScenePosition& p : scene.positions) {
    thin(p.cam_deg, 1);
    thin(p.lift_mm, 1);
    for (auto& pose : p.pose) thin(pose, 3);
    for (auto& contact : p.contact) thin(contact, 4);
  }
}

// the distinct values of a JSON array's members under `key` ("control_deg"), in order
std::vector<double> distinct_members(const nlohmann::json& rows, const std::string& key) {
  std::vector<double> out;
  if (!rows.is_array()) return out;
  for (const auto& row : rows) {
    const auto it = row.find(key);
    if (it == row.end() || !it->is_number()) continue;
    const double v = it->get<double>();
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  }
  return out;
}

}  // namespace

SceneSource scene_source_of_summary(const nlohmann::json& summary, const nlohmann::json& rows, double run_step,
                                    double start, double stop) {
  SceneSource s;
  if (const auto it = summary.find("design_file"); it != summary.end() && it->is_string())
    s.design = it->get<std::string>();
  for (const char* key : {"control_deg", "control_mm"}) {
    s.request.controls = distinct_members(rows, key);
    if (!s.request.controls.empty()) break;
  }
  s.request.start_deg = start;
  s.request.stop_deg = stop;
  s.request.step_deg = run_step;
  s.stride = frame_stride(run_step);
  return s;
}

std::shared_ptr<const CompiledDesign> compile_design_file(const fs::path& path) {
  std::error_code ec;
  if (path.empty() || !fs::exists(path, ec)) return nullptr;
  DesignSpec spec = io::load_design(path.string());
  kin::Mechanism mech = kin::compile(spec);
  return std::make_shared<const CompiledDesign>(CompiledDesign{std::move(spec), std::move(mech)});
}

void add_scene(ReportData& data, const SceneSource& source) {
  // the design as the run read it, compiled once
  const std::shared_ptr<const CompiledDesign> compiled = source.compiled ? source.compiled : compile_design_file(source.design);
  if (!compiled) {
    data.notes.push_back("no mechanism animation: the design file '" + source.design.string() +
                         "' is not readable from here (make the report from the folder the run was made in)");
    return;
  }
  const DesignSpec& spec = compiled->spec;
  const kin::Mechanism& mech = compiled->mech;
  SceneRequest request = source.request;
  if (mech.controls.empty()) request.controls.clear();
  if (std::isnan(request.start_deg)) request.start_deg = mech.driver.start;
  if (std::isnan(request.stop_deg)) request.stop_deg = mech.driver.stop;
  // solved at the run's own points (the same continuation, so the run's lift bit for bit),
  // drawn at every stride-th
  data.scene = build_scene(spec, mech, request);
  keep_every(*data.scene, source.stride);
  // the animation after the run's first section (the valve's motion), before the details
  const auto at = data.sections.begin() + std::min<std::ptrdiff_t>(1, std::ssize(data.sections));
  data.sections.insert(at, {"mechanism", "Mechanism"});
}

}  // namespace camopt::report::detail
