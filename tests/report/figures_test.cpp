// write_figures on hand-made report data: the files of the main plots and nothing else, PNG
// and SVG that readers accept, one stroked path per series (plus its legend sample), the axis
// titles in the SVG text, and the pixels: a point of a thick line, a profile and a heatmap
// cell land where figure_frame maps them, in their colour, and the space beside them stays
// paper-white (a wrong data-to-pixel map fails these).
#include <catch2/catch.hpp>

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/report/figures.hpp"
#include "cli/cli_support.hpp"
#include "support/compare.hpp"

using namespace camopt;
using namespace camopt::report;
namespace fs = std::filesystem;

namespace {

using Rgb = std::array<double, 3>;

// the series palette's first colours and viridis at 0.5 (figure_axes.cpp), as the test expects them
constexpr Rgb kBlue{0.122, 0.467, 0.706}, kOrange{1.000, 0.498, 0.055}, kRed{0.839, 0.153, 0.157},
    kReferenceGray{0.35, 0.35, 0.35};
constexpr double kColorTol = 2.5 / 255;  // 8-bit quantisation of the surface

// a main plot with its axes
Plot main_plot(const char* id, const char* title, PlotKind kind, Axis x, Axis y, Axis color = {}) {
  Plot p;
  p.id = id;
  p.title = title;
  p.kind = kind;
  p.x = std::move(x);
  p.y = std::move(y);
  p.color = std::move(color);
  p.main = true;
  return p;
}

ReportData sample_data() {
  ReportData d;
  d.command = "kinematics";
  d.title = "figure test";
  // a line plot: two series, a dashed reference, an upright line, a band and a limit
  Plot line = main_plot("svaj-lift", "Valve lift", PlotKind::line, {"cam angle", "deg"}, {"valve lift", "mm"});
  line.x_values = {0, 2, 4, 6, 8, 10};
  Series a{"lift", {}, {2, 2, 2, NAN, 8, 8}, {}, -1, false};
  Series b{"lift 2", {0, 10}, {5, 5}, {}, -1, false};
  Series ref{"kinematic lift", {0, 10}, {0.5, 0.5}, {}, -1, true};
  Series upright{"cursor", {6, 6}, {0, 10}, {}, -1, false};
  line.series = {a, b, ref, upright};
  line.bands = {{4.5, 5.5, "open"}};
  line.limits = {{9.0, "limit"}};
  // a profile: a circle of radius 10 about (1, 2) with one color value all round
  Plot profile = main_plot("cam-profile", "Cam profile", PlotKind::profile, {"x", "mm"}, {"y", "mm"},
                           {"radius of curvature", "mm"});
  Series circle;
  circle.name = "cam";
  for (int i = 0; i <= 720; ++i) {
    const double t = 2 * M_PI * i / 720;
    circle.x.push_back(1 + 10 * std::cos(t));
    circle.y.push_back(2 + 10 * std::sin(t));
    circle.color.push_back(10.0);
  }
  profile.series = {circle};
  // a heatmap: 2 x 3 cells, one of them a hole
  Plot heat = main_plot("speed-map", "Separation speed", PlotKind::heatmap, {"engine speed", "rpm"},
                        {"control", "deg"}, {"margin", "rpm"});
  heat.x_values = {1000, 2000, 3000};
  heat.y_values = {0, 8};
  heat.z = {0, 50, 100, NAN, 25, 75};
  // not a main plot: no figure
  Plot extra = line;
  extra.id = "not-main";
  extra.main = false;
  d.plots = {line, profile, heat, extra};
  return d;
}

// the pixel figure_frame maps a data point to (the one that contains it)
std::array<int, 2> pixel_of(const Plot& plot, double x, double y) {
  const FigureFrame f = figure_frame(plot);
  const double px = f.left + (x - f.x_min) / (f.x_max - f.x_min) * f.width;
  const double py = f.top + (f.y_max - y) / (f.y_max - f.y_min) * f.height;
  return {static_cast<int>(std::floor(px)), static_cast<int>(std::floor(py))};
}

// a decoded PNG (cairo reads it from memory)
struct Image {
  cairo_surface_t* s = nullptr;
  explicit Image(const std::string& png) {
    struct Reader {
      const std::string* bytes;
      std::size_t at = 0;
    } reader{&png};
    s = cairo_image_surface_create_from_png_stream(
        [](void* closure, unsigned char* data, unsigned int length) {
          auto* r = static_cast<Reader*>(closure);
          if (r->at + length > r->bytes->size()) return CAIRO_STATUS_READ_ERROR;
          std::memcpy(data, r->bytes->data() + r->at, length);
          r->at += length;
          return CAIRO_STATUS_SUCCESS;
        },
        &reader);
  }
  ~Image() { cairo_surface_destroy(s); }
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;
  Rgb at(std::array<int, 2> p) const {
    cairo_surface_flush(s);
    const unsigned char* row = cairo_image_surface_get_data(s) + p[1] * cairo_image_surface_get_stride(s);
    std::uint32_t v;
    std::memcpy(&v, row + 4 * p[0], 4);  // native-endian xRGB
    return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0};
  }
};

bool same_color(const Rgb& a, const Rgb& b) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(a[static_cast<std::size_t>(k)] - b[static_cast<std::size_t>(k)]) > kColorTol) return false;
  return true;
}

std::string figure(const std::vector<std::pair<std::string, std::string>>& figures, const std::string& name) {
  for (const auto& [n, content] : figures)
    if (n == name) return content;
  FAIL("no figure " << name);
  return {};
}

// the stroke colours of the SVG's paths, with how many paths use each
std::vector<std::pair<Rgb, int>> stroke_colors(const std::string& svg) {
  std::vector<std::pair<Rgb, int>> out;
  const std::regex path("<path[^>]*stroke:rgb\\(([-0-9.e]+)%,([-0-9.e]+)%,([-0-9.e]+)%\\)");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path); it != std::sregex_iterator(); ++it) {
    const Rgb c{std::stod((*it)[1]) / 100, std::stod((*it)[2]) / 100, std::stod((*it)[3]) / 100};
    auto found = std::find_if(out.begin(), out.end(), [&](const auto& e) { return same_color(e.first, c); });
    if (found == out.end())
      out.push_back({c, 1});
    else
      ++found->second;
  }
  return out;
}

int paths_in(const std::string& svg, const Rgb& c) {
  for (const auto& [color, n] : stroke_colors(svg))
    if (same_color(color, c)) return n;
  return 0;
}

// every element opened is closed in order (enough XML to trust a reader with it)
bool balanced_tags(const std::string& xml) {
  std::vector<std::string> open;
  const std::regex tag("<(/?)([A-Za-z_][-A-Za-z0-9_:.]*)[^>]*?(/?)>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::string closing = (*it)[1], name = (*it)[2], self = (*it)[3];
    if (!self.empty()) continue;
    if (closing.empty()) {
      open.push_back(name);
    } else {
      if (open.empty() || open.back() != name) return false;
      open.pop_back();
    }
  }
  return open.empty();
}

}  // namespace

TEST_CASE("figures: every main plot is written as an svg with its titles and one path per series",
          "[report][figures]") {
  const ReportData d = sample_data();
  test::TempDir dir;
  write_figures(d, dir.path() / "figures", FigureFormat::svg);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path() / "figures")) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"cam-profile.svg", "speed-map.svg", "svaj-lift.svg"});
  const std::string svg = test::read_file(dir.path() / "figures" / "svaj-lift.svg");
  CHECK(svg.rfind("<?xml", 0) == 0);
  CHECK(balanced_tags(svg));
  CHECK(svg.find("<title>Valve lift</title>") != std::string::npos);
  CHECK(svg.find("x: cam angle [deg]; y: valve lift [mm]") != std::string::npos);
  // each series: its curve and its legend sample, in its own colour
  CHECK(paths_in(svg, kBlue) == 2);
  CHECK(paths_in(svg, kOrange) == 2);
  CHECK(paths_in(svg, kReferenceGray) == 2);
  CHECK(paths_in(svg, kRed) == 2);
  const std::string heat = test::read_file(dir.path() / "figures" / "speed-map.svg");
  CHECK(balanced_tags(heat));
  CHECK(heat.find("x: engine speed [rpm]; y: control [deg]; color: margin [rpm]") != std::string::npos);
}

TEST_CASE("figures: a png of 800 x 500 pixels per main plot", "[report][figures]") {
  const auto figures = render_figures(sample_data(), FigureFormat::png);
  REQUIRE(figures.size() == 3);
  for (const auto& figure : figures) {
    // named, not a structured binding: clang 14 cannot capture one in the lambda below
    const std::string& name = figure.first;
    const std::string& png = figure.second;
    INFO(name);
    CHECK(name.size() > 4);
    CHECK(name.substr(name.size() - 4) == ".png");
    REQUIRE(png.size() > 24);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    CHECK(png.compare(12, 4, "IHDR") == 0);
    auto be32 = [&](std::size_t at) {
      return (static_cast<unsigned>(static_cast<unsigned char>(png[at])) << 24) |
             (static_cast<unsigned>(static_cast<unsigned char>(png[at + 1])) << 16) |
             (static_cast<unsigned>(static_cast<unsigned char>(png[at + 2])) << 8) |
             static_cast<unsigned>(static_cast<unsigned char>(png[at + 3]));
    };
    CHECK(be32(16) == 800u);
    CHECK(be32(20) == 500u);
  }
}

TEST_CASE("figures: data points land on the pixels the frame maps them to in their colour", "[report][figures]") {
  const ReportData d = sample_data();
  const auto figures = render_figures(d, FigureFormat::png);
  const Rgb white{1, 1, 1};
  SECTION("line plot: on the thick line its colour, beside it paper") {
    const Plot& line = d.plots[0];
    const FigureFrame f = figure_frame(line);
    CHECK(f.x_min == 0.0);
    CHECK(f.x_max == 10.0);
    CHECK((f.y_min <= 0.5 && f.y_max >= 9.0));
    const Image img(figure(figures, "svaj-lift.png"));
    REQUIRE(cairo_surface_status(img.s) == CAIRO_STATUS_SUCCESS);
    CHECK(same_color(img.at(pixel_of(line, 3, 2)), kBlue));   // on the first segment
    CHECK(same_color(img.at(pixel_of(line, 9, 8)), kBlue));   // on the second
    CHECK(!same_color(img.at(pixel_of(line, 3, 8)), kBlue));  // where a mirrored map would put them
    CHECK(!same_color(img.at(pixel_of(line, 9, 2)), kBlue));
    CHECK(!same_color(img.at(pixel_of(line, 7, 8)), kBlue));  // the gap: no line across it
    CHECK(!same_color(img.at(pixel_of(line, 7, 6.5)), kBlue));
    CHECK(same_color(img.at(pixel_of(line, 6, 3)), kRed));  // on the upright line
    CHECK(!same_color(img.at(pixel_of(line, 6.2, 3)), kRed));
    CHECK(same_color(img.at(pixel_of(line, 3, 7)), white));   // paper, off the grid
    CHECK(same_color(img.at(pixel_of(line, 5, 7)), Rgb{1.0, 0.95, 0.8125}));  // the band, no line across the gap
    CHECK(same_color(img.at(pixel_of(line, 3, 5)), kOrange));
  }
  SECTION("profile: to scale, the curve in the colour of its value") {
    const Plot& profile = d.plots[1];
    const FigureFrame f = figure_frame(profile);
    CHECK_REL((f.x_max - f.x_min) / f.width, (f.y_max - f.y_min) / f.height, 1e-12);
    CHECK((f.x_min <= -9 && f.x_max >= 11 && f.y_min <= -8 && f.y_max >= 12));
    const Image img(figure(figures, "cam-profile.png"));
    // viridis at the middle of the colour range (one value, widened by 10 % each way)
    const Rgb middle{0.128, 0.567, 0.551};
    for (const auto& p : {std::array<double, 2>{11, 2}, {1, 12}, {-9, 2}, {1, -8}}) {
      INFO(p[0] << ", " << p[1]);
      CHECK(same_color(img.at(pixel_of(profile, p[0], p[1])), middle));
    }
    CHECK(same_color(img.at(pixel_of(profile, 3.3, 4.7)), white));  // inside the circle, off the grid
  }
  SECTION("heatmap: each cell's centre in the colour of its value, a hole left blank") {
    const Plot& heat = d.plots[2];
    const Image img(figure(figures, "speed-map.png"));
    // viridis at 0, 0.5 (z 50 of 0..100) and 1
    CHECK(same_color(img.at(pixel_of(heat, 1000, 0)), Rgb{0.267, 0.005, 0.329}));
    CHECK(same_color(img.at(pixel_of(heat, 2000, 0)), Rgb{0.128, 0.567, 0.551}));
    CHECK(same_color(img.at(pixel_of(heat, 3000, 0)), Rgb{0.993, 0.906, 0.144}));
    CHECK(same_color(img.at(pixel_of(heat, 1000, 8)), white));
  }
}

TEST_CASE("figures: no main plot writes nothing and a bad plot id or path is an input error", "[report][figures]") {
  test::TempDir dir;
  ReportData d = sample_data();
  for (Plot& p : d.plots) p.main = false;
  write_figures(d, dir.path() / "none", FigureFormat::png);
  CHECK(!fs::exists(dir.path() / "none"));
  write_figures(ReportData{}, dir.path() / "none", FigureFormat::svg);
  CHECK(!fs::exists(dir.path() / "none"));
  d = sample_data();
  d.plots[1].id = "../escape";
  CHECK_THROWS_AS(render_figures(d, FigureFormat::svg), InputError);
  CHECK_THROWS_WITH(write_figures(d, dir.path(), FigureFormat::svg), Catch::Contains("'../escape' cannot name a file"));
  CHECK(!fs::exists(dir.path() / "svaj-lift.svg"));  // nothing written before the bad id was found
  // a directory where a figure would go is never replaced
  d = sample_data();
  fs::create_directory(dir.path() / "cam-profile.png");
  CHECK_THROWS_AS(write_figures(d, dir.path(), FigureFormat::png), InputError);
  CHECK(fs::is_directory(dir.path() / "cam-profile.png"));
}
