// the modes job (camopt dynamics --model modes): the flexible model linearised about its static
// equilibrium at chosen cam angles (dynamics::flexible_modes), as modes.csv's columns and summary.json.
#include "camopt/jobs/modes.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "camopt/core/units.hpp"
#include "camopt/dynamics/model.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/jobs/range_option.hpp"
#include "camopt/kinematics/sweep.hpp"

namespace camopt::jobs {

namespace {

// flexible_modes normalises the shapes with M in t (N s^2/mm) and t mm^2; the files use
// the design file's kg and kg mm^2: shape_kg = shape_t / sqrt(1000)
const double kShapeToKg = 1.0 / std::sqrt(1000.0);

// one linearisation: a control position and a cam angle
struct Point {
  std::size_t position = 0;
  double cam_deg = 0.0;
  std::string at;  // why this angle: "driver start", "peak lift", "--cam-deg"
  double lift = 0.0;  // kinematic lift of the output node there [mm or deg]
  dynamics::FlexibleModes modes;
};

// kinematic displacement of the output node from its rest position at every driver grid
// point, or at one angle (start == stop) [mm or deg]
kin::SweepResult output_sweep(const kin::Mechanism& mech, const std::vector<std::vector<double>>& positions,
                              double start, double stop, double step, int threads) {
  kin::SweepSpec spec;
  spec.start = start;
  spec.stop = stop;
  spec.step = step;
  spec.control_positions = positions;
  spec.request.derivative_order = 0;
  spec.threads = threads;
  return kin::sweep(mech, spec);
}

double lift_from_rest(const kin::Mechanism& mech, const kin::PositionResult& p, std::size_t point) {
  const int out = mech.nodes[mech.output_node].first_variable;
  const double rest = mech.variables[out].is_angle ? mech.nodes[mech.output_node].rest / rad_per_deg
                                                   : mech.nodes[mech.output_node].rest;
  return p.value(point, out, 0) - rest;
}

std::string number_text(double v) { return format_value(v, 12); }

// a failure at a control position and cam angle (NaN: none, the sweep names it)
[[noreturn]] void fail_at(const kin::Mechanism& mech, const ControlPositions& controls, Status st, std::size_t p,
                          double cam_deg) {
  if (!std::isnan(cam_deg))
    st.where += std::string(st.where.empty() ? "" : ", ") + "modes at cam " + number_text(cam_deg) + " deg";
  fail_at_position(mech, controls, st, p);
}

// the cam angles: --cam-deg at every control position, or the driver's start (the valve on
// its seat) and the grid angle of the largest kinematic lift at each position
std::vector<Point> linearisation_points(const kin::Mechanism& mech, const ControlPositions& controls,
                                        const std::vector<double>& angles, int threads) {
  std::vector<Point> points;
  const std::vector<std::vector<double>>& positions = controls.positions;
  if (!angles.empty()) {
    for (std::size_t p = 0; p < positions.size(); ++p)
      for (double a : angles) points.push_back({p, a, "--cam-deg", 0.0, {}});
    return points;
  }
  const kin::DriverDefaults& d = mech.driver;
  const kin::SweepResult grid = output_sweep(mech, positions, d.start, d.stop, d.step, threads);
  for (std::size_t p = 0; p < positions.size(); ++p) {
    const kin::PositionResult& r = grid.positions[p];
    if (!r.status.ok()) fail_at(mech, controls, r.status, p, std::nan(""));
    std::size_t peak = 0;
    for (std::size_t i = 1; i < grid.driver.size(); ++i)
      if (lift_from_rest(mech, r, i) > lift_from_rest(mech, r, peak)) peak = i;
    points.push_back({p, d.start, "driver start", 0.0, {}});
    if (grid.driver[peak] != d.start) points.push_back({p, grid.driver[peak], "peak lift", 0.0, {}});
  }
  return points;
}

// the modes and the kinematic lift at every point; the coordinates follow from the design
// alone, the same at every point
void compute_modes(const kin::Mechanism& mech, const dynamics::Model& model, const ControlPositions& controls,
                   const ModesOptions& o, std::vector<Point>& points, Observer& observer) {
  StepCounter steps(observer);
  for (Point& pt : points) {
    const std::vector<double>& position = controls.positions[pt.position];
    const kin::SweepResult one = output_sweep(mech, {position}, pt.cam_deg, pt.cam_deg, 1.0, 1);
    if (!one.positions[0].status.ok()) fail_at(mech, controls, one.positions[0].status, pt.position, pt.cam_deg);
    pt.lift = lift_from_rest(mech, one.positions[0], 0);
    const Status st =
        dynamics::flexible_modes(mech, model, position, pt.cam_deg, o.flexible, o.release_cam, pt.modes);
    if (!st.ok()) fail_at(mech, controls, st, pt.position, pt.cam_deg);
    if (pt.modes.coordinates != points.front().modes.coordinates || pt.modes.units != points.front().modes.units)
      throw std::logic_error("dynamics (modes): the coordinates differ between cam angles");
    steps.step_done();
  }
}

// modes.csv: one row per (control, cam angle, mode); mass-normalised shapes (x^T M x = 1, M in
// kg and kg mm^2): [mm or rad] per sqrt(kg)
io::Columns modes_columns(const std::vector<Point>& points, const ControlPositions& controls,
                      const std::string& control_key) {
  const std::vector<std::string>& coordinates = points.front().modes.coordinates;
  const std::vector<std::string>& units = points.front().modes.units;
  const std::size_t n = coordinates.size();
  std::vector<std::string> header = {control_key, "cam_deg", "mode", "frequency_Hz"};
  for (std::size_t i = 0; i < n; ++i) header.push_back(coordinates[i] + "_" + units[i] + "_per_sqrt_kg");
  std::vector<std::vector<double>> cols(header.size());
  for (const Point& pt : points)
    for (std::size_t k = 0; k < pt.modes.frequencies_hz.size(); ++k) {
      cols[0].push_back(controls.values[pt.position]);
      cols[1].push_back(pt.cam_deg);
      cols[2].push_back(static_cast<double>(k + 1));
      cols[3].push_back(pt.modes.frequencies_hz[k]);
      for (std::size_t i = 0; i < n; ++i) cols[4 + i].push_back(pt.modes.shapes[k * n + i] * kShapeToKg);
    }
  return {std::move(header), std::move(cols), {}};
}

// every compression spring with a mass alone, both ends held: a fixed-fixed chain of its
// N = surge_masses masses m_i = m/(N+1) joined by N+1 segments of stiffness K = (N+1) k:
// w_j = 2 sqrt(K/m_i) sin(j pi / (2 (N+1))), j = 1..N; the continuous coil f_j = (j/2) sqrt(k/m)
nlohmann::json springs_alone(const dynamics::Model& model) {
  nlohmann::json springs = nlohmann::json::object();
  for (const dynamics::Spring& sp : model.springs) {
    if (sp.kind != SpringKind::compression || !(sp.mass > 0)) continue;
    const double rate = sp.stiffness(0.0);  // [N/mm], tangent at the installed length (a table law: at 0 travel)
    const int masses = sp.surge_masses;
    const double m = sp.mass, k = rate * 1e3;  // [kg], [N/m]
    const double m_i = m / (masses + 1), k_seg = (masses + 1) * k;
    std::vector<double> chain, continuum;
    for (int j = 1; j <= masses; ++j)
      chain.push_back(std::sqrt(k_seg / m_i) / pi * std::sin(j * pi / (2.0 * (masses + 1))));
    for (int j = 1; j <= std::min(masses, 5); ++j) continuum.push_back(0.5 * j * std::sqrt(k / m));
    springs[sp.name] = {{"mass_kg", m},
                        {"rate_N_per_mm", rate},
                        {"surge_masses", masses},
                        {"coil_mass_kg", m_i},
                        {"segment_stiffness_N_per_mm", k_seg * 1e-3},
                        {"surge_frequencies_Hz", chain},
                        {"continuum_frequencies_Hz", continuum}};
  }
  return springs;
}

// summary.json: the linearisation, per point the frequencies, and the springs alone
nlohmann::json modes_summary(const kin::Mechanism& mech, const dynamics::Model& model, const ModesOptions& o,
                             const std::vector<Point>& points, const ControlPositions& controls,
                             const std::string& control_key) {
  const std::vector<std::string>& coordinates = points.front().modes.coordinates;
  const std::vector<std::string>& units = points.front().modes.units;
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";
  nlohmann::json summary;
  summary["design"] = mech.name;
  summary["design_file"] = o.design_file;
  summary["model"] = "modes";
  summary["linearisation"] =
      "flexible model at its static equilibrium at each cam angle, no speed: K x = w^2 M x with the spring "
      "coil masses, the seat and the contacts at their tangent stiffness";
  summary["driver_contacts"] = o.release_cam ? "released" : "held";
  summary["mode_shape_normalisation"] =
      "x^T M x = 1 with M in kg for mm coordinates and kg mm^2 for rad coordinates";
  nlohmann::json coords = nlohmann::json::array();
  for (std::size_t i = 0; i < coordinates.size(); ++i) coords.push_back({{"name", coordinates[i]}, {"unit", units[i]}});
  nlohmann::json results = nlohmann::json::array();
  for (const Point& pt : points) {
    nlohmann::json j;
    j[control_key] = controls.values[pt.position];
    j["cam_deg"] = pt.cam_deg;
    j["cam_angle_from"] = pt.at;
    j["lift_kinematic_" + lift_unit] = pt.lift + 0.0;  // no negative zero
    j["first_frequency_Hz"] = pt.modes.frequencies_hz.empty() ? nlohmann::json(nullptr)
                                                               : nlohmann::json(pt.modes.frequencies_hz.front());
    j["frequencies_Hz"] = pt.modes.frequencies_hz;
    j["coordinates"] = coords;
    results.push_back(j);
  }
  summary["results"] = results;
  summary["springs_alone"] = springs_alone(model);
  return summary;
}

}  // namespace

ModesResult run_modes(const LoadedDesign& design, const ModesOptions& o, Observer& observer) {
  // the cam angles of --cam-deg, and the design's dynamics model
  const std::vector<double> angles = o.cam_deg.empty() ? std::vector<double>{} : parse_range("--cam-deg", o.cam_deg);
  const kin::Mechanism& mech = design.mech;
  const dynamics::Model model = dynamics::compile_dynamics(design.spec, mech);
  // the control positions and the cam angles at each
  const ControlPositions controls = resolve_controls(mech, o.design_file, o.control);
  const std::string control_key = "control_" + controls.unit;
  std::vector<Point> points = linearisation_points(mech, controls, angles, o.threads);
  // the modes at every point
  observer.begin("modes", static_cast<long>(points.size()));
  compute_modes(mech, model, controls, o, points, observer);
  observer.end();
  // modes.csv and summary.json
  ModesResult result;
  result.columns = modes_columns(points, controls, control_key);
  result.summary = modes_summary(mech, model, o, points, controls, control_key);
  record_overrides(result.summary, design.overrides);
  result.linearisations = points.size();
  result.coordinates = points.front().modes.coordinates.size();
  return result;
}

}  // namespace camopt::jobs
