// a figure's frame and axes: the data ranges with nice ticks, the plot area (a profile at one
// scale on both axes), the grid, tick labels and "label [unit]" axis titles, and the colours
#include <algorithm>
#include <charconv>
#include <cmath>

#include "camopt/core/units.hpp"
#include "figure_detail.hpp"

namespace camopt::report::detail {

namespace {

// margins around the plot area [px]
constexpr double kLeft = 74, kRight = 24, kTop = 44, kBottom = 58, kColorBar = 96;
constexpr int kXTicks = 9, kYTicks = 7;  // about this many ticks on each axis

// a value range that grows to hold values
struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
  // an empty range becomes [0, 1]; a single value is widened by 10 % of itself (or 1)
  void settle() {
    if (empty()) {
      lo = 0;
      hi = 1;
    } else if (lo == hi) {
      const double d = lo != 0 ? 0.1 * std::abs(lo) : 1.0;
      lo -= d;
      hi += d;
    }
  }
};

// 1, 2 or 5 x 10^k nearest above x
double nice_step(double x) {
  const double e = std::floor(std::log10(x)), f = x / std::pow(10.0, e);
  const double n = f <= 1.0 ? 1.0 : f <= 2.0 ? 2.0 : f <= 5.0 ? 5.0 : 10.0;
  return n * std::pow(10.0, e);
}

// the x and y data ranges of a plot
void data_ranges(const Plot& plot, Range& x, Range& y) {
  if (plot.kind == PlotKind::heatmap) {
    for (double v : plot.x_values) x.add(v);
    for (double v : plot.y_values) y.add(v);
    // the cells reach half a spacing beyond the first and last centres
    auto pad = [](const std::vector<double>& v, Range& r) {
      if (v.size() < 2) return;
      r.lo -= 0.5 * std::abs(v[1] - v[0]);
      r.hi += 0.5 * std::abs(v[v.size() - 1] - v[v.size() - 2]);
    };
    pad(plot.x_values, x);
    pad(plot.y_values, y);
    return;
  }
  for (const Series& s : plot.series) {
    const std::vector<double>& xs = s.x.empty() ? plot.x_values : s.x;
    const std::size_t n = std::min(xs.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(xs[i]) || !std::isfinite(s.y[i])) continue;
      x.add(xs[i]);
      y.add(s.y[i]);
    }
  }
  for (const LimitLine& l : plot.limits) y.add(l.y);
}

// the profile's ranges widened about their centres to one scale [mm per px] on both axes
void equal_aspect(FigureFrame& f) {
  const double sx = (f.x_max - f.x_min) / f.width, sy = (f.y_max - f.y_min) / f.height;
  const double s = std::max(sx, sy);
  const double cx = 0.5 * (f.x_min + f.x_max), cy = 0.5 * (f.y_min + f.y_max);
  f.x_min = cx - 0.5 * s * f.width;
  f.x_max = cx + 0.5 * s * f.width;
  f.y_min = cy - 0.5 * s * f.height;
  f.y_max = cy + 0.5 * s * f.height;
}

std::string axis_title(const Axis& a) { return a.label + " [" + a.unit + "]"; }

}  // namespace

Rgb palette(int index) {
  static const Rgb colors[] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                               {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                               {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}, {0.737, 0.741, 0.133},
                               {0.090, 0.745, 0.812}};
  return colors[static_cast<std::size_t>(index) % 10];
}

Rgb colormap(double t) {
  // viridis at t = 0, 1/8, ..., 1, interpolated linearly
  static const Rgb anchors[] = {{0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530},
                                {0.207, 0.372, 0.553}, {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551},
                                {0.135, 0.659, 0.518}, {0.267, 0.749, 0.441}, {0.478, 0.821, 0.318},
                                {0.741, 0.873, 0.150}, {0.993, 0.906, 0.144}};
  constexpr int n = 10;  // intervals
  const double u = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * n;
  const int i = std::min(static_cast<int>(u), n - 1);
  const double w = u - i;
  Rgb c;
  for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = (1 - w) * anchors[i][static_cast<std::size_t>(k)] +
                                                                w * anchors[i + 1][static_cast<std::size_t>(k)];
  return c;
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  std::vector<double> ticks;
  if (!(hi > lo)) return ticks;
  const double step = nice_step((hi - lo) / std::max(count - 1, 1));
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

std::string tick_label(double value, double step) {
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 12);
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  return std::string(buf, r.ptr);
}

std::array<double, 2> color_range(const Plot& plot) {
  Range r;
  if (plot.kind == PlotKind::heatmap)
    for (double v : plot.z) r.add(v);
  else
    for (const Series& s : plot.series)
      for (double v : s.color) r.add(v);
  r.settle();
  return {r.lo, r.hi};
}

bool has_color_bar(const Plot& plot) {
  if (plot.kind == PlotKind::heatmap) return true;
  return std::any_of(plot.series.begin(), plot.series.end(), [](const Series& s) { return !s.color.empty(); });
}

void set_color(cairo_t* cr, const Rgb& c, double alpha) { cairo_set_source_rgba(cr, c[0], c[1], c[2], alpha); }

void draw_text(cairo_t* cr, const std::string& text, double x, double y, double align_x, double align_y, double size,
               bool bold, double angle) {
  cairo_save(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  // align_x 0: left, 0.5: centre, 1: right; align_y likewise from the top
  cairo_move_to(cr, -e.x_bearing - align_x * e.width, -e.y_bearing - align_y * e.height);
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

void draw_grid(cairo_t* cr, const FigureFrame& f) {
  const Mapper m{f};
  set_color(cr, {0.88, 0.88, 0.88});
  cairo_set_line_width(cr, 1.0);
  for (double t : nice_ticks(f.x_min, f.x_max, kXTicks)) {
    cairo_move_to(cr, m.x(t), f.top);
    cairo_line_to(cr, m.x(t), f.top + f.height);
  }
  for (double t : nice_ticks(f.y_min, f.y_max, kYTicks)) {
    cairo_move_to(cr, f.left, m.y(t));
    cairo_line_to(cr, f.left + f.width, m.y(t));
  }
  cairo_stroke(cr);
}

void draw_axes(cairo_t* cr, const Plot& plot, const FigureFrame& f) {
  const Mapper m{f};
  const Rgb ink{0.15, 0.15, 0.15};
  const std::vector<double> xt = nice_ticks(f.x_min, f.x_max, kXTicks), yt = nice_ticks(f.y_min, f.y_max, kYTicks);
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ys = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  set_color(cr, ink);
  cairo_set_line_width(cr, 1.0);
  // the frame, the ticks and their labels
  cairo_rectangle(cr, f.left, f.top, f.width, f.height);
  for (double t : xt) {
    cairo_move_to(cr, m.x(t), f.top + f.height);
    cairo_line_to(cr, m.x(t), f.top + f.height + 4);
  }
  for (double t : yt) {
    cairo_move_to(cr, f.left - 4, m.y(t));
    cairo_line_to(cr, f.left, m.y(t));
  }
  cairo_stroke(cr);
  for (double t : xt) draw_text(cr, tick_label(t, xs), m.x(t), f.top + f.height + 7, 0.5, 0.0, 11);
  for (double t : yt) draw_text(cr, tick_label(t, ys), f.left - 7, m.y(t), 1.0, 0.5, 11);
  // the axis titles and the plot's title
  draw_text(cr, axis_title(plot.x), f.left + 0.5 * f.width, kFigureHeight - 8, 0.5, 1.0, 13);
  draw_text(cr, axis_title(plot.y), 16, f.top + 0.5 * f.height, 0.5, 0.0, 13, false, -0.5 * pi);
  draw_text(cr, plot.title, f.left, 14, 0.0, 0.0, 15, true);
}

void draw_color_bar(cairo_t* cr, const Plot& plot, const FigureFrame& f) {
  const std::array<double, 2> r = color_range(plot);
  const double x0 = f.left + f.width + 18, w = 16;
  // the gradient, bottom (lo) to top (hi), in thin bands
  constexpr int bands = 64;
  for (int i = 0; i < bands; ++i) {
    set_color(cr, colormap((i + 0.5) / bands));
    const double y = f.top + f.height * (1.0 - static_cast<double>(i + 1) / bands);
    cairo_rectangle(cr, x0, y, w, f.height / bands + 0.5);
    cairo_fill(cr);
  }
  const Rgb ink{0.15, 0.15, 0.15};
  set_color(cr, ink);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, x0, f.top, w, f.height);
  cairo_stroke(cr);
  const std::vector<double> t = nice_ticks(r[0], r[1], 6);
  const double step = t.size() > 1 ? t[1] - t[0] : 1.0;
  for (double v : t) {
    const double y = f.top + f.height * (r[1] - v) / (r[1] - r[0]);
    draw_text(cr, tick_label(v, step), x0 + w + 4, y, 0.0, 0.5, 10);
  }
  draw_text(cr, axis_title(plot.color), kFigureWidth - 8, f.top + 0.5 * f.height, 0.5, 1.0, 12, false, -0.5 * pi);
}

}  // namespace camopt::report::detail

namespace camopt::report {

FigureFrame figure_frame(const Plot& plot) {
  using namespace detail;
  FigureFrame f;
  f.left = kLeft;
  f.top = kTop;
  f.width = kFigureWidth - kLeft - kRight - (has_color_bar(plot) ? kColorBar : 0.0);
  f.height = kFigureHeight - kTop - kBottom;
  Range x, y;
  data_ranges(plot, x, y);
  x.settle();
  y.settle();
  f.x_min = x.lo;
  f.x_max = x.hi;
  f.y_min = y.lo;
  f.y_max = y.hi;
  if (plot.kind == PlotKind::line) {
    // y out to the ticks beyond the data
    const std::vector<double> t = nice_ticks(y.lo, y.hi, 6);
    const double step = t.size() > 1 ? t[1] - t[0] : y.hi - y.lo;
    f.y_min = std::floor(y.lo / step + 1e-9) * step;
    f.y_max = std::ceil(y.hi / step - 1e-9) * step;
  } else if (plot.kind == PlotKind::profile) {
    const double pad = 0.04 * std::max(x.hi - x.lo, y.hi - y.lo);
    f.x_min -= pad;
    f.x_max += pad;
    f.y_min -= pad;
    f.y_max += pad;
    equal_aspect(f);
  }
  return f;
}

}  // namespace camopt::report
