#pragma once
// the steps of a static figure (figures.hpp): the frame and its axes (figure_axes.cpp), the
// data drawn into it and the legends (figure_series.cpp), on one cairo context of either
// surface (SVG or PNG: the same drawing code)
#include <cairo.h>

#include <array>
#include <string>
#include <vector>

#include "camopt/report/figures.hpp"

namespace camopt::report::detail {

using Rgb = std::array<double, 3>;

// the series palette (Tableau 10), by series index
Rgb palette(int index);
// the sequential colour map (viridis) at t in [0, 1]: family members and color values
Rgb colormap(double t);

// nice tick values over [lo, hi] (1, 2, 5 x 10^k steps), about `count` of them
std::vector<double> nice_ticks(double lo, double hi, int count);
// a number for a tick label: the shortest that tells the ticks apart
std::string tick_label(double value, double step);

// the value range of the plot's color axis (profile color values, heatmap z) [lo, hi]
std::array<double, 2> color_range(const Plot& plot);
// whether the plot draws a colour bar for its color axis (color values, heatmap)
bool has_color_bar(const Plot& plot);

// drawing in data coordinates through the frame
struct Mapper {
  FigureFrame f;
  double x(double v) const { return f.left + (v - f.x_min) / (f.x_max - f.x_min) * f.width; }
  double y(double v) const { return f.top + (f.y_max - v) / (f.y_max - f.y_min) * f.height; }
};

void set_color(cairo_t* cr, const Rgb& c, double alpha = 1.0);
void draw_text(cairo_t* cr, const std::string& text, double x, double y, double align_x, double align_y,
               double size, bool bold = false, double angle = 0.0);

// the grid beneath the data, and above it the frame, ticks, tick labels, axis titles and title
void draw_grid(cairo_t* cr, const FigureFrame& frame);
void draw_axes(cairo_t* cr, const Plot& plot, const FigureFrame& frame);
// bands and limit lines (line plots), beneath and above the series
void draw_bands(cairo_t* cr, const Plot& plot, const Mapper& m);
void draw_limits(cairo_t* cr, const Plot& plot, const Mapper& m);
// the data: line or profile series, or heatmap cells
void draw_series(cairo_t* cr, const Plot& plot, const ReportData& data, const Mapper& m);
void draw_heatmap(cairo_t* cr, const Plot& plot, const Mapper& m);
// the legend (series names; a family too large to list as a gradient from its first to its
// last member) and the colour bar of the color axis
void draw_legend(cairo_t* cr, const Plot& plot, const ReportData& data, const FigureFrame& frame);
void draw_color_bar(cairo_t* cr, const Plot& plot, const FigureFrame& frame);

// the colour a series is drawn in
Rgb series_color(const Series& s, std::size_t index, const ReportData& data);

}  // namespace camopt::report::detail
