// the cam's motion for envelope synthesis (envelope.hpp): it depends on the driver alone
// (not on the target), so it is solved upstream every `stride` samples (and at 2 pi) with
// its jets, and septic hermite in the driver angle in between; across a dwell (the cam at
// rest) only every kRestStride strides. A cam that is the lone upstream body turns with the
// driver and needs no solve; a floating cam moved through one roller follows its lever path
// (lever_path.hpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "camopt/core/trig_cache.hpp"
#include "camopt/core/units.hpp"
#include "camopt/synthesis/detail/envelope_steps.hpp"
#include "camopt/synthesis/lever_path.hpp"

namespace camopt::synthesis::detail {

namespace {

// [rad] spacing of the upstream solves for a cam that is not the driver (a swing cam, a
// floating lever); septic hermite in the driver angle between them. 1.5 deg would leave the
// bundled designs' round trips at their drawing controls unchanged, but at the
// Valvetronic's part-lift controls it raises them up to 12 times (7.6e-8 mm at 55 deg) and
// at 60 deg the interpolated lever motion folds the traced stretch (cam 91 deg)
constexpr double kUpstreamSpacing = 1.0 * pi / 180;
// where the cam rests at a solve (its taylor terms of order 1 to 3 over the stretch move it
// by less than kRestMotion rad or mm: the implicit derivatives on a dwell are round-off,
// ~1e-13, 1e-11 and 1e-9 for a floating lever), the next solve is tried kRestStride spacings
// on; a stretch that rests at both ends at the same pose (within kRestMotion) is taken as a
// dwell, else it is solved at every spacing. A motion shorter than the stretch and at rest
// to third order at both of its ends would be missed: no cam lobe or lever stroke is that short.
constexpr int kRestStride = 6;
constexpr double kRestMotion = 1e-12;

// the upstream solves at sample indices of a revolution of n samples, each appending the
// cam node's variables with their jets to out.values
struct UpstreamSolver {
  const kin::Mechanism& up;
  kin::Workspace& ws;
  const kin::Node& cam;
  int n;
  CamMotion& out;
  // a floating cam that the driver moves through one roller: its motion from the lever
  // path instead of a solve of its whole contact cluster at every node; the first node is
  // solved whole (the path's start, and the workspace's state). contact < 0: solved whole
  LeverPath lever_path;
  LeverState path_state;  // where the lever path last found the lever

  Status solve_at(int sample) {
    const double at = 2 * pi * sample / n;
    if (lever_path.contact >= 0 && !out.node_at.empty()) {
      Jet3 lever[3];
      if (lever_at(lever_path, up, ws, at, path_state, lever).ok()) {
        out.node_at.push_back(sample);
        for (const Jet3& v : lever)
          for (int d = 0; d < 4; ++d) out.values.push_back(v.derivative(d));
        return Status::success();
      }
      lever_path = {};  // from here on solved whole
    }
    const Status st = kin::solve(up, ws, at, {3, false});
    if (!st.ok()) return {st.code, st.message, "cam " + fmt(at * 180 / pi) + " deg"};
    out.node_at.push_back(sample);
    for (int k = 0; k < cam.dof; ++k)
      for (int d = 0; d < 4; ++d) out.values.push_back(ws.vars[cam.first_variable + k].derivative(d));
    if (lever_path.contact >= 0) lever_path_state(lever_path, up, ws, at, path_state);
    return Status::success();
  }

  // the cam at node j moves by less than kRestMotion over rest_span [rad] of driver
  bool at_rest(std::size_t j, double rest_span) const {
    for (int k = 0; k < cam.dof; ++k) {
      const double* d = &out.values[(j * cam.dof + k) * 4];
      const double h = rest_span;
      if (!(std::abs(d[1]) * h + std::abs(d[2]) * h * h / 2 + std::abs(d[3]) * h * h * h / 6 <= kRestMotion))
        return false;
    }
    return true;
  }

  // nodes j and j + 1 hold the same pose (within kRestMotion)
  bool same_pose(std::size_t j) const {
    bool same = true;
    for (int k = 0; k < cam.dof && same; ++k)
      same = std::abs(out.values[((j + 1) * cam.dof + k) * 4] - out.values[(j * cam.dof + k) * 4]) <= kRestMotion;
    return same;
  }
};

// the solves from sample 0 to sample n, stride by stride; where the cam rests, one solve
// kRestStride strides on is tried first and kept when the cam rests there at the same pose
// (a dwell), else dropped and the stretch solved stride by stride
Status solve_nodes(UpstreamSolver& solver, int stride) {
  const int n = solver.n;
  std::vector<int>& node_at = solver.out.node_at;
  const double rest_span = kRestStride * stride * 2 * pi / n;  // [rad] of driver
  if (Status st = solver.solve_at(0); !st.ok()) return st;
  // the state a refused dwell try returns to: the workspace where the upstream is solved
  // whole (assigned, not reallocated, after the first), the lever path's state where it
  // follows the path (which reads the workspace's pivots only)
  std::optional<kin::Workspace> before;
  while (node_at.back() < n) {
    const std::size_t j = node_at.size() - 1;
    const int next = std::min(n, node_at.back() + stride);
    if (solver.at_rest(j, rest_span) && next < n) {
      const bool whole = solver.lever_path.contact < 0;
      if (whole && before) *before = solver.ws;
      if (whole && !before) before.emplace(solver.ws);
      const LeverState state_before = solver.path_state;
      const int far = std::min(n, node_at.back() + kRestStride * stride);
      if (Status st = solver.solve_at(far); !st.ok()) return st;
      if (solver.at_rest(j + 1, rest_span) && solver.same_pose(j)) continue;
      node_at.pop_back();
      solver.out.values.resize(solver.out.values.size() - static_cast<std::size_t>(solver.cam.dof) * 4);
      if (whole) solver.ws = *before;  // (a path that fell back to whole solves goes on from far)
      solver.path_state = state_before;
    }
    if (Status st = solver.solve_at(next); !st.ok()) return st;
  }
  return Status::success();
}

}  // namespace

Jet3 CamMotion::at(int i, int k) {
  while (node_at[interval + 1] <= i) ++interval;
  const int a = node_at[interval], b = node_at[interval + 1];
  double d[4];
  pieces.eval(interval, k, static_cast<double>(i - a) / (b - a), d);
  return jet_from_derivatives<3>(d);
}

Status solve_cam_motion(Halves& halves, int n, CamMotion& out) {
  const kin::Mechanism& up = halves.up;
  const kin::Node& cn = up.nodes[halves.cam];
  out = {};
  out.dof = cn.dof;
  out.first_variable = cn.first_variable;
  // a rotational cam that is the only body upstream turns with the driver: no solve needed
  out.lone_driver = up.variables.size() == 1 && halves.cam == up.driver_node && up.driver_variable() == 0;
  if (out.lone_driver) {
    revolution_sin_cos(n, out.driver_sin, out.driver_cos);
    // one solve fills the workspace's pivot positions for node_pose
    const Status st = kin::solve(up, halves.up_ws, 0.0, {3, false});
    if (!st.ok()) return {st.code, st.message, "cam 0 deg"};
    return Status::success();
  }
  const int stride = std::max(1, static_cast<int>(std::lround(kUpstreamSpacing * n / (2 * pi))));
  UpstreamSolver solver{up, halves.up_ws, cn, n, out, {}, {}};
  if (cn.kind == NodeKind::floating)
    if (!build_lever_path(halves.cut.upstream, up, halves.cam, halves.controls, solver.lever_path).ok())
      solver.lever_path = {};  // solved whole
  if (Status st = solve_nodes(solver, stride); !st.ok()) return st;
  // the cam's variables between solves
  out.pieces = SepticPieces(cn.dof);
  for (std::size_t j = 0; j + 1 < out.node_at.size(); ++j)
    out.pieces.add_interval(&out.values[j * cn.dof * 4], &out.values[(j + 1) * cn.dof * 4],
                            (out.node_at[j + 1] - out.node_at[j]) * 2 * pi / n);
  return Status::success();
}

void swing_angle_at_samples(const Halves& halves, int n, CamMotion& cam, std::vector<double>& cam_rate,
                            std::vector<char>& needed) {
  const int angle_dof = halves.cam_angle_variable - cam.first_variable;
  double max_rate = 0.0;
  cam.angle_at.resize(n);
  for (int i = 0; i < n; ++i) {
    cam.angle_at[i] = cam.at(i, angle_dof);
    cam_rate[i] = cam.angle_at[i].derivative(1);
    max_rate = std::max(max_rate, std::abs(cam_rate[i]));
  }
  // swing_profile traces the envelope where the rate exceeds 1e-3 of the peak; the rest is its dwell
  for (int i = 0; i < n; ++i) needed[i] = std::abs(cam_rate[i]) > 1e-4 * max_rate;
  cam.interval = 0;
}

}  // namespace camopt::synthesis::detail
