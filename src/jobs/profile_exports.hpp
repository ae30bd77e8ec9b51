#pragma once
// the files a synthesized or optimised profile is delivered in (shared by `synthesize` and
// `optimize`): profile.csv, profile.dxf, grinding.csv and design.toml, staged into one
// output transaction, with their description in the report.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "camopt/core/design_spec.hpp"
#include "camopt/io/atomic_file.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::cli {

// master_radius_mm: grinding master roller (nullopt: the follower's own roller, else a
// flat master). throws NumericalError when the grinding table cannot be computed, unless
// grinding_optional: then the report says why and grinding.csv is not written.
void stage_profile_exports(io::OutputTransaction& out, const std::string& out_dir, const std::string& design_path,
                           const DesignSpec& spec, const synthesis::SynthesisResult& res,
                           std::optional<double> master_radius_mm, double grinding_step_deg, nlohmann::json& report,
                           bool grinding_optional = false);

}  // namespace camopt::cli
