#pragma once
// the designed cam contact of a mechanism and the two halves around it: the upstream
// part (driver -> cam node) and the downstream part (follower -> target node, driven by
// the target node). used by envelope synthesis and by the optimiser, which both invert
// the target motion through the downstream part (SAE 2010-01-1193, "cam lobe solution").
#include <string>

#include "camopt/core/design_spec.hpp"

namespace camopt::synthesis {

struct MechanismCut {
  int connection = -1;                        // index of the designed contact in spec.connections
  std::string cam_node, follower_node, profile;
  bool profile_on_a = true;                   // the profile is surface a of the contact
  DesignSpec upstream;                        // driver -> cam node (output: the cam node)
  DesignSpec downstream;                      // driven by target_node (output: the follower)
};

// cam_kind "rotational": the profile on the driver; "swing": a profile on another
// rotational node or on a floating lever (its pose solved upstream with its other contacts). InputError when no contact or several qualify, when the follower is a
// concave circle, or when the contact does not separate the driver from target_node.
MechanismCut cut_mechanism(const DesignSpec& spec, const std::string& cam_kind, const std::string& target_node);

}  // namespace camopt::synthesis
