// the main plots as static figures: each drawn once on a cairo surface (SVG or PNG, the same
// drawing code) into memory, then written atomically
#include "camopt/report/figures.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <memory>
#include <new>

#include "camopt/core/error.hpp"
#include "camopt/io/atomic_file.hpp"
#include "figure_detail.hpp"

namespace camopt::report {

namespace {

// cairo's stream callback: appends to a std::string (no exception crosses into cairo)
cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  try {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  } catch (...) {
    return CAIRO_STATUS_WRITE_ERROR;
  }
}

// a plot id names a file: letters, digits, '-', '_', '.', not starting with '.'
void check_id(const Plot& plot) {
  const bool ok = !plot.id.empty() && plot.id[0] != '.' &&
                  std::all_of(plot.id.begin(), plot.id.end(), [](char c) {
                    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                           c == '_' || c == '.';
                  });
  CAMOPT_THROW_UNLESS(ok, "figure plot id '" + plot.id +
                              "' cannot name a file (letters, digits, '-', '_' and '.' only, not starting with '.')");
}

// the whole figure on one cairo context
void draw_plot(cairo_t* cr, const Plot& plot, const ReportData& data) {
  const FigureFrame frame = figure_frame(plot);
  const detail::Mapper m{frame};
  // the paper
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  // the data, clipped to the plot area: grid and bands beneath, limits above
  cairo_save(cr);
  cairo_rectangle(cr, frame.left, frame.top, frame.width, frame.height);
  cairo_clip(cr);
  if (plot.kind != PlotKind::heatmap) detail::draw_grid(cr, frame);  // cells cover a heatmap's area
  detail::draw_bands(cr, plot, m);
  if (plot.kind == PlotKind::heatmap)
    detail::draw_heatmap(cr, plot, m);
  else
    detail::draw_series(cr, plot, data, m);
  detail::draw_limits(cr, plot, m);
  cairo_restore(cr);
  // the axes, the legend and the colour bar
  detail::draw_axes(cr, plot, frame);
  detail::draw_legend(cr, plot, data, frame);
  if (detail::has_color_bar(plot)) detail::draw_color_bar(cr, plot, frame);
}

// the characters XML text must escape
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// cairo draws text as glyph outlines: the title and the axis titles as text for readers and
// search, in <title> and <desc> at the top of the document
std::string with_titles(std::string svg, const Plot& plot) {
  const std::size_t open = svg.find("<svg");
  const std::size_t end = open == std::string::npos ? open : svg.find('>', open);
  CAMOPT_ASSERT(end != std::string::npos);
  auto title = [](const Axis& a) { return a.label + " [" + a.unit + "]"; };
  std::string desc = "x: " + title(plot.x) + "; y: " + title(plot.y);
  if (plot.kind != PlotKind::line && !plot.color.label.empty()) desc += "; color: " + title(plot.color);
  svg.insert(end + 1, "\n<title>" + xml_escape(plot.title) + "</title>\n<desc>" + xml_escape(desc) + "</desc>");
  return svg;
}

std::string render(const Plot& plot, const ReportData& data, FigureFormat format) {
  std::string bytes;
  using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
  using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;
  Surface surface(format == FigureFormat::svg
                      ? cairo_svg_surface_create_for_stream(append_bytes, &bytes, kFigureWidth, kFigureHeight)
                      : cairo_image_surface_create(CAIRO_FORMAT_RGB24, kFigureWidth, kFigureHeight),
                  cairo_surface_destroy);
  {
    Context cr(cairo_create(surface.get()), cairo_destroy);
    draw_plot(cr.get(), plot, data);
    CAMOPT_ASSERT(cairo_status(cr.get()) == CAIRO_STATUS_SUCCESS);
  }
  if (format == FigureFormat::png) {
    const cairo_status_t st = cairo_surface_write_to_png_stream(surface.get(), append_bytes, &bytes);
    if (st != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();  // append_bytes fails only when out of memory
    return bytes;
  }
  cairo_surface_finish(surface.get());
  CAMOPT_ASSERT(cairo_surface_status(surface.get()) == CAIRO_STATUS_SUCCESS);
  return with_titles(std::move(bytes), plot);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> render_figures(const ReportData& data, FigureFormat format) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Plot& plot : data.plots) {
    if (!plot.main) continue;
    check_id(plot);
    out.emplace_back(plot.id + (format == FigureFormat::svg ? ".svg" : ".png"), render(plot, data, format));
  }
  return out;
}

void write_figures(const ReportData& data, const std::filesystem::path& dir, FigureFormat format) {
  // every figure rendered before the first is written
  const std::vector<std::pair<std::string, std::string>> figures = render_figures(data, format);
  if (figures.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  CAMOPT_THROW_UNLESS(!ec && std::filesystem::is_directory(dir),
                      "figures directory '" + dir.string() + "' cannot be made: " + ec.message());
  for (const auto& [name, content] : figures) io::write_text_atomic((dir / name).string(), content);
}

}  // namespace camopt::report
