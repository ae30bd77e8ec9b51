#pragma once
// a design file rewritten to use a new profile table (synthesize and optimize write
// DIR/design.toml)
#include <string>
#include <vector>

#include "camopt/io/design_document.hpp"

namespace camopt::io {

// TOML text of the design at `design_path` in which the [[profile]] named `profile_name`
// reads its polar table from `profile_file`, a path relative to `out_dir`, the folder the
// text is written into (form = "polar", its inline arrays dropped). Every other relative
// `file = ...` reference is rewritten relative to `out_dir`. The original text is edited in
// place: its comments, layout and numbers stay as written (only the profile's data lines go,
// with any comment on those lines); a header comment says where the text came from.
// `overrides` (`--set`) are edited into the text first, and listed in the header comment.
std::string design_with_profile_file(const std::string& design_path, const std::string& profile_name,
                                     const std::string& profile_file, const std::string& out_dir,
                                     const std::vector<Override>& overrides = {});

}  // namespace camopt::io
