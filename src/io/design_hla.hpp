#pragma once
// the design file's [[hla]] tables (docs/hla.md, "Keys"); internal to camopt_io
#include "camopt/core/design_spec.hpp"
#include "toml_table.hpp"

namespace camopt::io {

// every [[hla]] of the root table into spec.hlas (the nodes already read): unknown keys, wrong
// types and missing keys are InputErrors at file:line:column: key; each HLA is then compiled
// (dynamics::compile_hla) so every rule of the element is reported while reading the file
void parse_hlas(const toml_detail::Table& root, DesignSpec& spec);

}  // namespace camopt::io
