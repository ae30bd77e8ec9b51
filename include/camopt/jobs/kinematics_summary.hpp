#pragma once
// the kinematics summary as summary.json and as a short line on the terminal, per control
// position, and the heights of --duration-at.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/kinematics/sweep.hpp"

namespace camopt::jobs {

// a height of --duration-at: in the output's unit (mm, or deg for a rotating output) and
// as written in the keys ("1mm", "0.04in")
struct DurationHeight {
  double value = 0.0;
  std::string label;
};

// --duration-at: a comma list of positive heights, each a number with an optional unit: mm
// (the default) or in for a translating output, deg (the default) for a rotating one.
// InputError naming the option and the item otherwise, or when a height is given twice.
std::vector<DurationHeight> parse_duration_heights(const std::string& text, bool output_is_angle);

// the units of a run's summary keys
struct SummaryUnits {
  std::string lift;    // "mm" or "deg"
  std::string driver;  // "deg" or "mm"
  int order = 0;       // highest lift derivative written
  double cam_deg_per_s = 0.0;  // > 0: also rpm and m/s
};

// a duration's key: duration_at_<height><unit>_cam_deg (driver_mm for a translating driver)
std::string duration_key(const DurationHeight& h, const std::string& driver_unit);

// InputError naming --duration-at when a height is at or above the maximum lift at every
// control position (a unit slip, e.g. thou for mm); at some positions only, the duration
// there is 0 and the position's notes say why
void check_duration_heights(const std::vector<DurationHeight>& heights, const std::vector<kin::PositionSummary>& summaries,
                            const std::string& lift_unit);

// one control position's entry of summary.json (without the control and status keys)
nlohmann::json position_summary_json(const kin::PositionSummary& s, const std::vector<DurationHeight>& heights,
                                     const SummaryUnits& u);

// one line for the terminal: max lift, durations, the sharpest cam radii and their surfaces
std::string position_summary_line(const kin::PositionSummary& s, const std::vector<DurationHeight>& heights,
                                  const SummaryUnits& u);

}  // namespace camopt::jobs
