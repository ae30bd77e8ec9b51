// camopt dynamics --model modes: the flexible model linearised about its static equilibrium
// at chosen cam angles (dynamics::flexible_modes), written as modes.csv and summary.json.
#include "modes_command.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "camopt/dynamics/model.hpp"
#include "camopt/io/atomic_file.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/kinematics/drawing_check.hpp"
#include "camopt/kinematics/sweep.hpp"
#include "cli_common.hpp"
#include "range_option.hpp"

namespace camopt::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
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
                              double start, double stop, double step) {
  kin::SweepSpec spec;
  spec.start = start;
  spec.stop = stop;
  spec.step = step;
  spec.control_positions = positions;
  spec.request.derivative_order = 0;
  spec.threads = thread_count();
  return kin::sweep(mech, spec);
}

double lift_from_rest(const kin::Mechanism& mech, const kin::PositionResult& p, std::size_t point) {
  const int out = mech.nodes[mech.output_node].first_variable;
  const double rest = mech.variables[out].is_angle ? mech.nodes[mech.output_node].rest / kDeg
                                                   : mech.nodes[mech.output_node].rest;
  return p.at(point, mech.variables.size(), out, 0) - rest;
}

std::string number_text(double v) { return format_value(v, 12); }

}  // namespace

void add_modes_options(CLI::App& cmd, ModesOptions& options) {
  cmd.add_option("--cam-deg", options.cam_deg,
                 "modes: cam angles [cam deg] at which to linearise: a value, a list a,b,c or START:STOP:COUNT "
                 "(default: the driver's start angle and the angle of peak kinematic lift)");
  cmd.add_flag("--release-cam", options.release_cam,
               "modes: the contacts on the driver carry no stiffness (the cam force is the input)");
}

void run_modes(const ModesRequest& rq) {
  const std::vector<double> angles =
      rq.modes.cam_deg.empty() ? std::vector<double>{} : parse_range("--cam-deg", rq.modes.cam_deg);
  const DesignSpec spec = io::load_design(rq.design);
  const kin::Mechanism mech = kin::compile(spec);
  for (const auto& note : kin::check_drawing(mech)) info(rq.design + ": warning: " + note);
  const dynamics::Model model = dynamics::compile_dynamics(mech);
  if (!rq.rpm.empty()) info("dynamics (modes): note: --rpm is not used (the modes are at no speed)");

  // control positions: the first control at each value, the others at their defaults
  std::vector<double> control_values;
  if (!rq.control.empty()) {
    if (mech.controls.empty()) throw InputError("--control: design '" + rq.design + "' has no [[control]]");
    const auto& c0 = mech.controls[0];
    control_values = parse_range("--control", rq.control);
    for (double v : control_values)
      if (v < c0.min - 1e-12 || v > c0.max + 1e-12)
        throw InputError("--control: value " + number_text(v) + " is outside control '" + c0.name + "' range [" +
                         number_text(c0.min) + ", " + number_text(c0.max) + "]");
  } else {
    control_values.push_back(mech.controls.empty() ? 0.0 : mech.controls[0].default_value);
  }
  std::vector<std::vector<double>> positions;
  for (double v : control_values) {
    auto pos = mech.default_controls();
    if (!pos.empty()) pos[0] = v;
    positions.push_back(pos);
  }
  const std::string control_key =
      "control_" + std::string(mech.controls.empty() || mech.controls[0].is_angle ? "deg" : "mm");
  const bool angle_out = mech.nodes[mech.output_node].kind != NodeKind::translational;
  const std::string lift_unit = angle_out ? "deg" : "mm";
  // a failure named with the control position and the cam angle (NaN: none, the sweep names it)
  auto fail = [&](Status st, std::size_t p, double cam_deg) {
    if (!std::isnan(cam_deg))
      st.where += std::string(st.where.empty() ? "" : ", ") + "modes at cam " + number_text(cam_deg) + " deg";
    if (!mech.controls.empty()) st.where += ", control " + mech.controls[0].name + " = " + number_text(control_values[p]);
    throw NumericalError(st);
  };

  // the cam angles: --cam-deg at every control position, or the driver's start (the valve
  // on its seat) and the grid angle of the largest kinematic lift at each position
  std::vector<Point> points;
  if (!angles.empty()) {
    for (std::size_t p = 0; p < positions.size(); ++p)
      for (double a : angles) points.push_back({p, a, "--cam-deg", 0.0, {}});
  } else {
    const auto& d = spec.driver;
    const kin::SweepResult grid = output_sweep(mech, positions, d.start_deg, d.stop_deg, d.step_deg);
    for (std::size_t p = 0; p < positions.size(); ++p) {
      const kin::PositionResult& r = grid.positions[p];
      if (!r.status.ok()) fail(r.status, p, std::nan(""));
      std::size_t peak = 0;
      for (std::size_t i = 1; i < grid.driver.size(); ++i)
        if (lift_from_rest(mech, r, i) > lift_from_rest(mech, r, peak)) peak = i;
      points.push_back({p, d.start_deg, "driver start", 0.0, {}});
      if (grid.driver[peak] != d.start_deg) points.push_back({p, grid.driver[peak], "peak lift", 0.0, {}});
    }
  }

  // the modes and the kinematic lift at every point
  Progress progress("modes", static_cast<long>(points.size()));
  for (Point& pt : points) {
    const kin::SweepResult one = output_sweep(mech, {positions[pt.position]}, pt.cam_deg, pt.cam_deg, 1.0);
    if (!one.positions[0].status.ok()) fail(one.positions[0].status, pt.position, pt.cam_deg);
    pt.lift = lift_from_rest(mech, one.positions[0], 0);
    const Status st = dynamics::flexible_modes(mech, model, positions[pt.position], pt.cam_deg, rq.flexible,
                                               rq.modes.release_cam, pt.modes);
    if (!st.ok()) fail(st, pt.position, pt.cam_deg);
    // the coordinates follow from the design alone: the same at every point
    if (pt.modes.coordinates != points.front().modes.coordinates || pt.modes.units != points.front().modes.units)
      throw std::logic_error("dynamics (modes): the coordinates differ between cam angles");
    progress.advance();
  }
  const std::vector<std::string>& coordinates = points.front().modes.coordinates;
  const std::vector<std::string>& units = points.front().modes.units;
  const std::size_t n = coordinates.size();

  // ---- modes.csv: one row per (control, cam angle, mode) ----
  std::vector<std::string> header = {control_key, "cam_deg", "mode", "frequency_Hz"};
  // mass-normalised shapes (x^T M x = 1, M in kg and kg mm^2): [mm or rad] per sqrt(kg)
  for (std::size_t i = 0; i < n; ++i) header.push_back(coordinates[i] + "_" + units[i] + "_per_sqrt_kg");
  std::vector<std::vector<double>> cols(header.size());
  for (const Point& pt : points)
    for (std::size_t k = 0; k < pt.modes.frequencies_hz.size(); ++k) {
      cols[0].push_back(control_values[pt.position]);
      cols[1].push_back(pt.cam_deg);
      cols[2].push_back(static_cast<double>(k + 1));
      cols[3].push_back(pt.modes.frequencies_hz[k]);
      for (std::size_t i = 0; i < n; ++i) cols[4 + i].push_back(pt.modes.shapes[k * n + i] * kShapeToKg);
    }

  // ---- summary.json ----
  nlohmann::json summary;
  summary["design"] = spec.name;
  summary["design_file"] = rq.design;
  summary["model"] = "modes";
  summary["linearisation"] =
      "flexible model at its static equilibrium at each cam angle, no speed: K x = w^2 M x with the spring "
      "coil masses, the seat and the contacts at their tangent stiffness";
  summary["driver_contacts"] = rq.modes.release_cam ? "released" : "held";
  summary["mode_shape_normalisation"] =
      "x^T M x = 1 with M in kg for mm coordinates and kg mm^2 for rad coordinates";
  nlohmann::json coords = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i) coords.push_back({{"name", coordinates[i]}, {"unit", units[i]}});
  nlohmann::json results = nlohmann::json::array();
  for (const Point& pt : points) {
    nlohmann::json j;
    j[control_key] = control_values[pt.position];
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
  // every compression spring with a mass alone, both ends held: a fixed-fixed chain of its
  // N = surge_masses masses m_i = m/(N+1) joined by N+1 segments of stiffness K = (N+1) k:
  // w_j = 2 sqrt(K/m_i) sin(j pi / (2 (N+1))), j = 1..N; the continuous coil f_j = (j/2) sqrt(k/m)
  nlohmann::json springs = nlohmann::json::object();
  for (const SpringSpec& ss : spec.springs) {
    if (ss.kind != SpringKind::compression || !ss.mass_kg) continue;
    double rate = 0.0;  // [N/mm], tangent at the installed length (a table law: at 0 travel)
    for (const dynamics::Spring& sp : model.springs)
      if (sp.name == ss.name) rate = sp.stiffness(0.0);
    const int masses = ss.surge_masses;
    const double m = *ss.mass_kg, k = rate * 1e3;  // [kg], [N/m]
    const double m_i = m / (masses + 1), k_seg = (masses + 1) * k;
    std::vector<double> chain, continuum;
    for (int j = 1; j <= masses; ++j)
      chain.push_back(std::sqrt(k_seg / m_i) / kPi * std::sin(j * kPi / (2.0 * (masses + 1))));
    for (int j = 1; j <= std::min(masses, 5); ++j) continuum.push_back(0.5 * j * std::sqrt(k / m));
    springs[ss.name] = {{"mass_kg", m},
                        {"rate_N_per_mm", rate},
                        {"surge_masses", masses},
                        {"coil_mass_kg", m_i},
                        {"segment_stiffness_N_per_mm", k_seg * 1e-3},
                        {"surge_frequencies_Hz", chain},
                        {"continuum_frequencies_Hz", continuum}};
  }
  summary["springs_alone"] = springs;

  io::OutputTransaction out = open_outputs(rq.out_dir, kDynamicsOutputs);
  out.stage("modes.csv", io::format_csv(header, cols));
  out.stage("summary.json", summary.dump(2) + "\n");
  out.commit();
  info("dynamics (modes): " + std::to_string(points.size()) + " linearisation(s), " + std::to_string(n) +
       " coordinates -> " + rq.out_dir + "/modes.csv, summary.json");
}

}  // namespace camopt::cli
