#pragma once
// the drawing is the assembled mechanism at driver 0 and default controls: it gives the
// initial guess, the assembly branch of every link and the rest positions. A drawing that
// does not close is not an error (the solver finds the true assembly) but is reported.
#include <string>
#include <vector>

#include "camopt/kinematics/mechanism.hpp"

namespace camopt::kin {

// one message per node whose solved displacement at driver 0 differs from the drawing by
// more than 0.001 mm or 0.001 deg; or the solve failure itself
std::vector<std::string> check_drawing(const Mechanism& mech);

}  // namespace camopt::kin
