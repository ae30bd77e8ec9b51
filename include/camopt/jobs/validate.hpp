#pragma once
// the validate job (camopt validate): what a design compiles to, as the command prints it.
#include <string>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::jobs {

// a compiled design described: the mechanism (nodes, connections, solve order), the flexible
// model's laws, stiffnesses and damping (each marked when it is a default), the oil; and the
// drawing check's warnings
struct DesignFindings {
  std::string description;            // the lines `camopt validate` prints after "<file>: ok"
  std::vector<std::string> warnings;  // one per drawing problem, without the "<file>: warning: "
};

// InputError for bad flexible-model data (the dynamics data of a design that has masses)
DesignFindings validate_design(const DesignSpec& spec, const kin::Mechanism& mech);

}  // namespace camopt::jobs
