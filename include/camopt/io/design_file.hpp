#pragma once
// design files (TOML) -> DesignSpec. Strict: unknown keys, wrong types, missing required
// values and out-of-range values throw InputError "file:line:column: key.path: value ...: rule".
#include <string>
#include <string_view>

#include "camopt/core/design_spec.hpp"

namespace camopt::io {

DesignSpec load_design(const std::string& path);
// `directory` resolves relative `file = ...` references
DesignSpec parse_design(std::string_view text, const std::string& file_name, const std::string& directory);

}  // namespace camopt::io
