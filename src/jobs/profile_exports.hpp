#pragma once
// the files a synthesized or optimised profile is delivered in (shared by the synthesize and
// optimize jobs): profile.csv, profile.dxf, grinding.csv and design.toml, with their
// description in the report.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "camopt/core/design_spec.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/jobs/synthesize.hpp"
#include "camopt/synthesis/envelope.hpp"

namespace camopt::jobs {

// master_radius_mm: grinding master roller (nullopt: the follower's own roller, else a
// flat master). throws NumericalError when the grinding table cannot be computed, unless
// grinding_optional: then the report says why and grinding.csv is not written. design.toml
// is the file at design_path with `overrides` edited in.
ProfileExports profile_exports(const std::string& out_dir, const std::string& design_path,
                               const std::vector<io::Override>& overrides, const DesignSpec& spec,
                               const synthesis::SynthesisResult& res, std::optional<double> master_radius_mm,
                               double grinding_step_deg, nlohmann::json& report, bool grinding_optional = false);

}  // namespace camopt::jobs
