#include "camopt/kinematics/drawing_check.hpp"

#include <cmath>
#include <sstream>

#include "camopt/core/units.hpp"
#include "camopt/kinematics/solver.hpp"

namespace camopt::kin {

std::vector<std::string> check_drawing(const Mechanism& mech) {
  std::vector<std::string> notes;
  Workspace ws(mech);
  const Status st = solve(mech, ws, 0.0, {0, false});
  if (!st.ok()) {
    notes.push_back("the drawing does not assemble at driver 0: " + st.str());
    return notes;
  }
  std::vector<bool> at_rest(mech.nodes.size(), false);
  for (std::size_t si = 0; si < mech.plan.size(); ++si)
    if (ws.lash_open()[si]) at_rest[mech.plan[si].output_node] = true;
  for (std::size_t v = 0; v < mech.variables.size(); ++v) {
    const int n = mech.variables[v].node;
    if (n < 0 || n == mech.driver_node || at_rest[n]) continue;
    const bool angle = mech.variables[v].is_angle;
    const double tol = angle ? 1e-3 * pi / 180.0 : 1e-3;  // 0.001 deg or 0.001 mm
    const double x = ws.values()[v];
    if (std::abs(x) > tol) {
      std::ostringstream os;
      os.precision(6);
      os << "drawing not assembled: '" << mech.variables[v].name << "' solves to "
         << (angle ? x * 180.0 / pi : x) << (angle ? " deg" : " mm")
         << " at driver 0 instead of 0 (its drawing position); check the drawing coordinates or length_mm";
      notes.push_back(os.str());
    }
  }
  return notes;
}

}  // namespace camopt::kin
