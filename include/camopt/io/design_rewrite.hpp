#pragma once
// a design file rewritten to use a new profile table (camopt synthesize writes DIR/design.toml)
#include <string>

namespace camopt::io {

// TOML text of the design at `design_path` in which the [[profile]] named `profile_name`
// reads its polar table from `profile_file` (form = "polar"); every other relative
// `file = ...` reference is made absolute so the text can live in another directory.
// Comments of the original are not kept; a header comment says where the text came from.
std::string design_with_profile_file(const std::string& design_path, const std::string& profile_name,
                                     const std::string& profile_file);

}  // namespace camopt::io
