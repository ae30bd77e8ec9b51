#pragma once
// contacts that touch at rest (`touch_at_rest = true`, docs/design-format.md): side b's circle
// centre or line point is placed on the contact normal so the two shapes touch in the
// drawing (every node at zero displacement, the controls at their defaults). Side a stays.
// The drawing pose of every node is fixed by the design, so each contact is solved on its own.
#include "camopt/core/design_spec.hpp"
#include "camopt/kinematics/mechanism.hpp"

namespace camopt::kin {

// every contact of the spec that touches at rest and is not solved yet, solved: its
// surface_b.origin_mm replaced by the touching position (drawn_b_mm keeps the written one).
// InputError naming the connection, the key and the gap when a contact cannot close
// (a centre inside the other shape, a face behind it, a circle that does not fit)
void assemble_contacts(DesignSpec& spec);

namespace detail {
// compile's step: the touching positions of the mechanism's contacts that touch at rest
// (surface_b moved, Mechanism::assembled recorded); those the spec has solved are recorded
void assemble_mechanism_contacts(const DesignSpec& spec, Mechanism& m);
bool has_unsolved_contacts(const DesignSpec& spec);
// kin::compile without solving the contacts first (their touching positions are the
// mechanism's; the spec keeps the written ones)
Mechanism compile_as_drawn(const DesignSpec& spec);
}  // namespace detail

}  // namespace camopt::kin
