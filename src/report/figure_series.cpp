// the data of a figure: line and profile series (a profile coloured along its color values),
// heatmap cells, shaded bands and limit lines, and the legend
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "figure_detail.hpp"

namespace camopt::report::detail {

namespace {

constexpr double kLineWidth = 2.0;                 // a series [px]
const Rgb kReference{0.35, 0.35, 0.35};            // a dashed reference series without a family
const Rgb kInk{0.15, 0.15, 0.15};
constexpr int kMaxLegendEntries = 10;              // more: "+ n more"
constexpr std::size_t kFamilyGradientFrom = 7;     // family members listed one by one below this

void set_dash(cairo_t* cr, bool dashed) {
  const double dash[] = {6.0, 4.0};
  cairo_set_dash(cr, dash, dashed ? 2 : 0, 0.0);
}

// the family's size: ReportData::family, or the largest member index + 1
std::size_t family_size(const Plot& plot, const ReportData& data) {
  std::size_t n = data.family.size();
  for (const Series& s : plot.series)
    if (s.family_member >= 0) n = std::max(n, static_cast<std::size_t>(s.family_member) + 1);
  return n;
}

// the series as polylines through its finite points (a non-finite value breaks the line)
void trace(cairo_t* cr, const std::vector<double>& xs, const Series& s, const Mapper& m) {
  const std::size_t n = std::min(xs.size(), s.y.size());
  bool open = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(s.y[i])) {
      open = false;
      continue;
    }
    if (open)
      cairo_line_to(cr, m.x(xs[i]), m.y(s.y[i]));
    else
      cairo_move_to(cr, m.x(xs[i]), m.y(s.y[i]));
    open = true;
  }
}

// a profile coloured along its color values: each segment in the colour of its mean value
void trace_colored(cairo_t* cr, const std::vector<double>& xs, const Series& s, const std::array<double, 2>& range,
                   const Mapper& m) {
  const std::size_t n = std::min({xs.size(), s.y.size(), s.color.size()});
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double v[] = {xs[i], s.y[i], xs[i + 1], s.y[i + 1]};
    if (!std::all_of(std::begin(v), std::end(v), [](double q) { return std::isfinite(q); })) continue;
    set_color(cr, colormap((0.5 * (s.color[i] + s.color[i + 1]) - range[0]) / (range[1] - range[0])));
    cairo_move_to(cr, m.x(v[0]), m.y(v[1]));
    cairo_line_to(cr, m.x(v[2]), m.y(v[3]));
    cairo_stroke(cr);
  }
}

// one legend entry: a line sample in the series' style and its name
void legend_entry(cairo_t* cr, const Rgb& color, bool dashed, const std::string& name, double x, double y) {
  set_color(cr, color);
  cairo_set_line_width(cr, kLineWidth);
  set_dash(cr, dashed);
  cairo_move_to(cr, x, y);
  cairo_line_to(cr, x + 24, y);
  cairo_stroke(cr);
  set_dash(cr, false);
  set_color(cr, kInk);
  draw_text(cr, name, x + 30, y, 0.0, 0.5, 11);
}

// the family's members as a gradient from the first member's label to the last's
void legend_gradient(cairo_t* cr, const ReportData& data, std::size_t members, double x, double y) {
  constexpr int steps = 32;
  for (int i = 0; i < steps; ++i) {
    set_color(cr, colormap((i + 0.5) / steps));
    cairo_rectangle(cr, x + 80.0 * i / steps, y - 5, 80.0 / steps + 0.3, 10);
    cairo_fill(cr);
  }
  set_color(cr, kInk);
  const std::string first = data.family.empty() ? "member 0" : data.family.front();
  const std::string last = data.family.size() < members ? "member " + std::to_string(members - 1) : data.family[members - 1];
  draw_text(cr, first + " .. " + last, x + 86, y, 0.0, 0.5, 11);
}

// the top left of a w x h legend box in the corner of the plot area (top right, top left,
// bottom right, bottom left, in this order of preference) that covers the fewest data points
std::array<double, 2> legend_corner(const Plot& plot, const FigureFrame& f, double w, double h) {
  const Mapper m{f};
  const double right = f.left + f.width - w - 8, bottom = f.top + f.height - h - 8;
  const std::array<double, 2> corners[] = {{right, f.top + 8}, {f.left + 8, f.top + 8}, {right, bottom}, {f.left + 8, bottom}};
  std::size_t best = 0, fewest = SIZE_MAX;
  for (std::size_t k = 0; k < 4; ++k) {
    std::size_t covered = 0;
    for (const Series& s : plot.series) {
      const std::vector<double>& xs = s.x.empty() ? plot.x_values : s.x;
      for (std::size_t i = 0; i < std::min(xs.size(), s.y.size()); ++i) {
        const double px = m.x(xs[i]), py = m.y(s.y[i]);
        covered += px >= corners[k][0] - 4 && px <= corners[k][0] + w + 4 && py >= corners[k][1] - 4 &&
                   py <= corners[k][1] + h + 4;
      }
    }
    if (covered < fewest) {
      fewest = covered;
      best = k;
    }
  }
  return corners[best];
}

}  // namespace

Rgb series_color(const Series& s, std::size_t index, const ReportData& data) {
  if (s.family_member >= 0) {
    const std::size_t n = std::max<std::size_t>(data.family.size(), static_cast<std::size_t>(s.family_member) + 1);
    return colormap(n > 1 ? static_cast<double>(s.family_member) / static_cast<double>(n - 1) : 0.0);
  }
  return s.dashed ? kReference : palette(static_cast<int>(index));
}

void draw_bands(cairo_t* cr, const Plot& plot, const Mapper& m) {
  for (const Band& b : plot.bands) {
    const double x0 = m.x(std::min(b.from, b.to)), x1 = m.x(std::max(b.from, b.to));
    cairo_set_source_rgba(cr, 1.0, 0.80, 0.25, 0.25);
    cairo_rectangle(cr, x0, m.f.top, x1 - x0, m.f.height);
    cairo_fill(cr);
    set_color(cr, {0.55, 0.40, 0.05});
    draw_text(cr, b.label, 0.5 * (x0 + x1), m.f.top + 4, 0.5, 0.0, 10);
  }
}

void draw_limits(cairo_t* cr, const Plot& plot, const Mapper& m) {
  for (const LimitLine& l : plot.limits) {
    set_color(cr, {0.80, 0.10, 0.10});
    cairo_set_line_width(cr, 1.5);
    set_dash(cr, true);
    cairo_move_to(cr, m.f.left, m.y(l.y));
    cairo_line_to(cr, m.f.left + m.f.width, m.y(l.y));
    cairo_stroke(cr);
    set_dash(cr, false);
    draw_text(cr, l.label, m.f.left + 4, m.y(l.y) - 3, 0.0, 1.0, 10);
  }
}

void draw_series(cairo_t* cr, const Plot& plot, const ReportData& data, const Mapper& m) {
  const std::array<double, 2> range = color_range(plot);
  cairo_set_line_width(cr, kLineWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    const std::vector<double>& xs = s.x.empty() ? plot.x_values : s.x;
    set_dash(cr, s.dashed);
    if (plot.kind == PlotKind::profile && !s.color.empty() && !s.dashed) {
      trace_colored(cr, xs, s, range, m);
      continue;
    }
    set_color(cr, series_color(s, i, data));
    trace(cr, xs, s, m);
    cairo_stroke(cr);
  }
  set_dash(cr, false);
}

void draw_heatmap(cairo_t* cr, const Plot& plot, const Mapper& m) {
  const std::size_t nx = plot.x_values.size(), ny = plot.y_values.size();
  if (plot.z.size() != nx * ny || nx == 0 || ny == 0) return;
  const std::array<double, 2> range = color_range(plot);
  // a cell reaches halfway to its neighbours (half its one spacing at the ends)
  auto edges = [](const std::vector<double>& v) {
    std::vector<double> e(v.size() + 1);
    for (std::size_t i = 1; i < v.size(); ++i) e[i] = 0.5 * (v[i - 1] + v[i]);
    const double first = v.size() > 1 ? v[1] - v[0] : 1.0, last = v.size() > 1 ? v[v.size() - 1] - v[v.size() - 2] : 1.0;
    e.front() = v.front() - 0.5 * first;
    e.back() = v.back() + 0.5 * last;
    return e;
  };
  const std::vector<double> ex = edges(plot.x_values), ey = edges(plot.y_values);
  for (std::size_t r = 0; r < ny; ++r)
    for (std::size_t c = 0; c < nx; ++c) {
      const double z = plot.z[r * nx + c];
      if (!std::isfinite(z)) continue;  // a hole: the background shows
      set_color(cr, colormap((z - range[0]) / (range[1] - range[0])));
      const double x0 = m.x(ex[c]), x1 = m.x(ex[c + 1]), y0 = m.y(ey[r]), y1 = m.y(ey[r + 1]);
      // a hair wider than the cell, so that no seam shows between neighbours
      cairo_rectangle(cr, std::min(x0, x1) - 0.25, std::min(y0, y1) - 0.25, std::abs(x1 - x0) + 0.5, std::abs(y1 - y0) + 0.5);
      cairo_fill(cr);
    }
}

void draw_legend(cairo_t* cr, const Plot& plot, const ReportData& data, const FigureFrame& f) {
  // the entries: each named series, or the family as one gradient when it is too large to list
  const std::size_t members = family_size(plot, data);
  const bool gradient = members >= kFamilyGradientFrom;
  std::vector<std::size_t> listed;
  bool family_shown = false;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    if (s.name.empty() || (plot.kind == PlotKind::profile && !s.color.empty() && !s.dashed)) continue;
    if (gradient && s.family_member >= 0) {
      family_shown = true;
      continue;
    }
    listed.push_back(i);
  }
  const std::size_t shown = std::min<std::size_t>(listed.size(), kMaxLegendEntries);
  const std::size_t rows = shown + (listed.size() > shown ? 1 : 0) + (family_shown ? 1 : 0);
  if (rows == 0) return;
  // a box in the corner of the plot area that hides the fewest data points
  const double w = 220, row = 17, h = rows * row + 8;
  const std::array<double, 2> corner = legend_corner(plot, f, w, h);
  const double x = corner[0], y = corner[1];
  cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
  cairo_rectangle(cr, x, y, w, h);
  cairo_fill_preserve(cr);
  set_color(cr, {0.75, 0.75, 0.75});
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  double cy = y + 4 + 0.5 * row;
  if (family_shown) {
    legend_gradient(cr, data, members, x + 8, cy);
    cy += row;
  }
  for (std::size_t k = 0; k < shown; ++k, cy += row) {
    const Series& s = plot.series[listed[k]];
    legend_entry(cr, series_color(s, listed[k], data), s.dashed, s.name, x + 8, cy);
  }
  if (listed.size() > shown) {
    set_color(cr, kInk);
    draw_text(cr, "+ " + std::to_string(listed.size() - shown) + " more", x + 38, cy, 0.0, 0.5, 11);
  }
}

}  // namespace camopt::report::detail
