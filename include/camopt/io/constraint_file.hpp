#pragma once
// constraint sets for `camopt optimize` (TOML, docs/optimisation.md) -> opt::OptimizationSpec.
// every key is checked where it is read (type, range, unknown keys) and reported with its
// file, line and key path; the set's consistency is checked by opt::validate.
#include <string>
#include <string_view>
#include <vector>

#include "camopt/io/design_document.hpp"

#include "camopt/opt/optimization_spec.hpp"

namespace camopt::io {

opt::OptimizationSpec parse_constraints(std::string_view text, const std::string& file_name,
                                        const std::string& directory);
opt::OptimizationSpec load_constraints(const std::string& path);
// the set at `path` with `--set-constraint key.path=value` overrides applied (key paths as in
// a design file, docs/design-format.md "Key paths"); a value an override gave is reported at it
opt::OptimizationSpec load_constraints(const std::string& path, const std::vector<Override>& overrides);

}  // namespace camopt::io
