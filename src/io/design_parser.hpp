#pragma once
// the design-file parser on a parsed document (design_file.cpp), for the readers of a design
// text: io::parse_design and the design document. internal to camopt_io.
#include <toml++/toml.h>

#include "camopt/core/design_spec.hpp"
#include "toml_table.hpp"

namespace camopt::io {

// the document checked and read into a DesignSpec, with the contacts that touch at rest
// solved (kin::assemble_contacts)
DesignSpec parse_design_document(const toml::table& document, const toml_detail::Context& context);

}  // namespace camopt::io
