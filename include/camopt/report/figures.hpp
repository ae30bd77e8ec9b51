#pragma once
// the run's main plots as static figures for a document (`--figures svg|png`), drawn with
// cairo from the same Plot definitions as the page: axes with nice ticks and "label [unit]"
// titles, the series (a family's members coloured along the family), dashed reference
// series, shaded bands and limit lines, profiles to scale coloured by their color values,
// heatmaps, colour bars and a legend. One file per Plot with main == true, named
// "<plot id>.svg" or "<plot id>.png", kFigureWidth x kFigureHeight.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "camopt/report/report_data.hpp"

namespace camopt::report {

enum class FigureFormat { svg, png };

inline constexpr int kFigureWidth = 800;   // [px] (SVG: pt)
inline constexpr int kFigureHeight = 500;  // [px]

// where a plot's data lands in its figure: the plot area [px from the top left] and the axis
// ranges it spans (nice tick values; a profile's ranges widened to one scale on both axes).
// pixel x = left + (x - x_min) / (x_max - x_min) * width, y = top + (y_max - y) / (y_max - y_min) * height
struct FigureFrame {
  double left = 0, top = 0, width = 0, height = 0;  // [px]
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
};
FigureFrame figure_frame(const Plot& plot);

// every main plot rendered: (file name, content) in ReportData::plots order, for a caller that
// stages its outputs itself. InputError when a plot id cannot name a file (letters, digits,
// '-', '_', '.' only, not starting with '.').
std::vector<std::pair<std::string, std::string>> render_figures(const ReportData& data, FigureFormat format);

// every main plot written into dir (made if missing) as "<plot id>.svg|png", each file written
// atomically (temp file + rename). All figures are rendered before the first is written; no
// main plot: nothing is written. InputError for a bad plot id (render_figures) or a path that
// is not a regular file (io::write_text_atomic).
void write_figures(const ReportData& data, const std::filesystem::path& dir, FigureFormat format);

}  // namespace camopt::report
