// render_html(): ReportData as the page's JSON (docs/report.md, "Data format": numeric arrays
// as base64 little-endian float32, scalars shortest round-trip, "</" written "<\/"), inlined
// with the assets into the page template.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "assets.hpp"
#include "camopt/core/error.hpp"
#include "camopt/report/report.hpp"

namespace camopt::report {
namespace {

// a JSON text built piece by piece
class JsonWriter {
 public:
  explicit JsonWriter(std::size_t expected_size) { out_.reserve(expected_size); }
  std::string& text() { return out_; }

  void string(std::string_view s) {
    out_ += '"';
    for (std::size_t i = 0; i < s.size(); ++i) {
      const char c = s[i];
      switch (c) {
        case '"': out_ += "\\\""; break;
        case '\\': out_ += "\\\\"; break;
        case '\n': out_ += "\\n"; break;
        case '\r': out_ += "\\r"; break;
        case '\t': out_ += "\\t"; break;
        case '/':  // "</" would end the page's <script> element
          out_ += i > 0 && s[i - 1] == '<' ? "\\/" : "/";
          break;
        case '<':  // "<!--" would open a comment inside it
          out_ += i + 1 < s.size() && s[i + 1] == '!' ? "\\u003c" : "<";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            out_ += buffer;
          } else {
            out_ += c;
          }
      }
    }
    out_ += '"';
    fresh_ = false;
  }
  void number(double v) {
    if (!std::isfinite(v)) return null();
    fresh_ = false;
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    out_.append(buffer, result.ptr);
  }
  void null() {
    out_ += "null";
    fresh_ = false;
  }
  void boolean(bool b) {
    out_ += b ? "true" : "false";
    fresh_ = false;
  }
  void key(std::string_view k) {
    comma();
    string(k);
    out_ += ':';
    fresh_ = true;
  }
  void begin(char bracket) {
    comma();
    out_ += bracket;
    fresh_ = true;
  }
  void end(char bracket) {
    out_ += bracket;
    fresh_ = false;
  }
  // an array element or a member follows: a comma unless it is the first
  void comma() {
    if (!fresh_) out_ += ',';
    fresh_ = false;
  }
  void member(std::string_view k, std::string_view v) { key(k), string(v); }
  void member_number(std::string_view k, double v) { key(k), number(v); }
  void member_bool(std::string_view k, bool v) { key(k), boolean(v); }
  void member_array(std::string_view k, const std::vector<double>& v) { key(k), string(base64_float32(v)); }
  // an array of strings as a value
  void strings(const std::vector<std::string>& v) {
    begin('[');
    for (const auto& s : v) comma(), string(s);
    end(']');
  }
  void member_strings(std::string_view k, const std::vector<std::string>& v) { key(k), strings(v); }

 private:
  std::string out_;
  bool fresh_ = true;
};

const char* kind_name(PlotKind k) {
  switch (k) {
    case PlotKind::line: return "line";
    case PlotKind::profile: return "profile";
    case PlotKind::heatmap: return "heatmap";
  }
  return "line";
}

const char* shape_kind_name(SceneShape::Kind k) {
  switch (k) {
    case SceneShape::Kind::polyline: return "polyline";
    case SceneShape::Kind::polygon: return "polygon";
    case SceneShape::Kind::circle: return "circle";
    case SceneShape::Kind::spring: return "spring";
  }
  return "polyline";
}

void write_axis(JsonWriter& w, std::string_view name, const Axis& a) {
  w.key(name);
  w.begin('{');
  w.member("label", a.label);
  w.member("unit", a.unit);
  w.end('}');
}

void write_series(JsonWriter& w, const Series& s) {
  w.begin('{');
  w.member("name", s.name);
  w.member_array("x", s.x);
  w.member_array("y", s.y);
  w.member_array("color", s.color);
  w.key("family_member"), w.number(s.family_member);
  w.member_bool("dashed", s.dashed);
  w.end('}');
}

void write_plot(JsonWriter& w, const Plot& p) {
  w.begin('{');
  w.member("id", p.id);
  w.member("title", p.title);
  w.member("section", p.section);
  w.member("kind", kind_name(p.kind));
  write_axis(w, "x", p.x);
  write_axis(w, "y", p.y);
  write_axis(w, "color", p.color);
  w.member("link_group", p.link_group);
  w.member_array("x_values", p.x_values);
  w.member_array("y_values", p.y_values);
  w.member_array("z", p.z);
  w.key("series");
  w.begin('[');
  for (const auto& s : p.series) write_series(w, s);
  w.end(']');
  w.key("bands");
  w.begin('[');
  for (const auto& b : p.bands) {
    w.begin('{');
    w.member_number("from", b.from), w.member_number("to", b.to), w.member("label", b.label);
    w.end('}');
  }
  w.end(']');
  w.key("limits");
  w.begin('[');
  for (const auto& l : p.limits) {
    w.begin('{');
    w.member_number("y", l.y), w.member("label", l.label);
    w.end('}');
  }
  w.end(']');
  w.member_bool("main", p.main);
  w.end('}');
}

void write_table(JsonWriter& w, const Table& t) {
  w.begin('{');
  w.member("id", t.id);
  w.member("title", t.title);
  w.member("section", t.section);
  w.member_strings("columns", t.columns);
  w.key("rows");
  w.begin('[');
  for (const auto& row : t.rows) w.strings(row);
  w.end(']');
  w.key("failed_rows");
  w.begin('[');
  for (int r : t.failed_rows) w.comma(), w.number(r);
  w.end(']');
  w.end('}');
}

void write_shape(JsonWriter& w, const SceneShape& s) {
  w.begin('{');
  w.member("kind", shape_kind_name(s.kind));
  w.key("body"), w.number(s.body);
  w.key("body_b"), w.number(s.body_b);
  w.member_array("xy", s.xy);
  w.member_number("radius", s.radius);
  w.member("role", s.role);
  w.end('}');
}

void write_position(JsonWriter& w, const ScenePosition& p) {
  w.begin('{');
  w.member_number("control", p.control);
  w.member_array("cam_deg", p.cam_deg);
  w.key("pose");
  w.begin('[');
  for (const auto& b : p.pose) w.comma(), w.string(base64_float32(b));
  w.end(']');
  w.key("contact");
  w.begin('[');
  for (const auto& c : p.contact) w.comma(), w.string(base64_float32(c));
  w.end(']');
  w.member_array("lift_mm", p.lift_mm);
  w.end('}');
}

void write_scene(JsonWriter& w, const Scene& s) {
  w.begin('{');
  w.member_strings("bodies", s.bodies);
  w.member_strings("contacts", s.contacts);
  w.key("shapes");
  w.begin('[');
  for (const auto& shape : s.shapes) write_shape(w, shape);
  w.end(']');
  w.member("control_name", s.control_name);
  w.member("control_unit", s.control_unit);
  w.member("output_body", s.output_body);
  w.key("bbox");
  w.begin('[');
  for (double v : s.bbox) w.comma(), w.number(v);
  w.end(']');
  w.key("positions");
  w.begin('[');
  for (const auto& p : s.positions) write_position(w, p);
  w.end(']');
  w.end('}');
}

// the HTML text of a title: & < > " ' escaped
std::string html_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string base64_float32(const std::vector<double>& values) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  // the float32 bytes, little-endian
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto bits = std::bit_cast<std::uint32_t>(static_cast<float>(values[i]));
    for (int b = 0; b < 4; ++b) bytes[4 * i + static_cast<std::size_t>(b)] = static_cast<char>((bits >> (8 * b)) & 0xFF);
  }
  // three bytes to four digits, '=' padding
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = 0;
    for (std::size_t k = 0; k < 3; ++k)
      chunk = (chunk << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(chunk >> (18 - 6 * k)) & 0x3F] : '=';
  }
  return out;
}

namespace {

// the numbers of the report's arrays: for the JSON's size, reserved once
std::size_t array_values(const ReportData& d) {
  std::size_t n = 0;
  for (const auto& p : d.plots) {
    n += p.x_values.size() + p.y_values.size() + p.z.size();
    for (const auto& s : p.series) n += s.x.size() + s.y.size() + s.color.size();
  }
  if (d.scene)
    for (const auto& pos : d.scene->positions) {
      n += pos.cam_deg.size() + pos.lift_mm.size();
      for (const auto& v : pos.pose) n += v.size();
      for (const auto& v : pos.contact) n += v.size();
    }
  return n;
}

}  // namespace

std::string to_json(const ReportData& d) {
  JsonWriter w(array_values(d) * 16 / 3 + (1 << 16));
  w.begin('{');
  w.member("format", "camopt-report");
  w.member_number("version", 1);
  w.member("generator", "camopt " CAMOPT_VERSION);
  w.member("command", d.command);
  w.member("title", d.title);
  w.member("source_dir", d.source_dir);
  w.key("facts");
  w.begin('[');
  for (const auto& f : d.facts) {
    w.begin('{');
    w.member("key", f.key), w.member("value", f.value);
    w.end('}');
  }
  w.end(']');
  w.member_strings("notes", d.notes);
  w.member_strings("family", d.family);
  w.key("sections");
  w.begin('[');
  for (const auto& s : d.sections) {
    w.begin('{');
    w.member("id", s.id), w.member("title", s.title);
    w.end('}');
  }
  w.end(']');
  w.key("plots");
  w.begin('[');
  for (const auto& p : d.plots) write_plot(w, p);
  w.end(']');
  w.key("tables");
  w.begin('[');
  for (const auto& t : d.tables) write_table(w, t);
  w.end(']');
  w.key("scene");
  if (d.scene)
    write_scene(w, *d.scene);
  else
    w.null();
  w.key("passed");
  if (d.passed)
    w.boolean(*d.passed);
  else
    w.null();
  w.end('}');
  return std::move(w.text());
}

std::string render_html(const ReportData& data) {
  // each placeholder of the template once, replaced in one pass over the template (the
  // inlined texts are never searched)
  const std::pair<std::string_view, std::string> fills[] = {
      {"{{camopt:title}}", html_escape(data.title)},
      {"{{camopt:uplot.css}}", std::string(assets::uplot_css)},
      {"{{camopt:report.css}}", std::string(assets::report_css)},
      {"{{camopt:uplot.js}}", std::string(assets::uplot_js)},
      {"{{camopt:report.js}}", std::string(assets::report_js)},
      {"{{camopt:data}}", to_json(data)},
  };
  const std::string_view page = assets::template_html;
  std::string out;
  std::size_t size = page.size();
  for (const auto& fill : fills) size += fill.second.size();
  out.reserve(size);
  std::size_t at = 0;
  int filled[6] = {0, 0, 0, 0, 0, 0};
  for (;;) {
    const std::size_t open = page.find("{{camopt:", at);
    if (open == std::string_view::npos) break;
    std::size_t which = 0;
    while (which < 6 && page.compare(open, fills[which].first.size(), fills[which].first) != 0) ++which;
    CAMOPT_ASSERT_MSG(which < 6, "report template: an unknown {{camopt:...}} placeholder");
    out.append(page.substr(at, open - at));
    out += fills[which].second;
    ++filled[which];
    at = open + fills[which].first.size();
  }
  out.append(page.substr(at));
  for (int n : filled) CAMOPT_ASSERT_MSG(n == 1, "report template: a placeholder missing or repeated");
  return out;
}

}  // namespace camopt::report
