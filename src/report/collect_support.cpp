// the collectors' shared pieces: axes from unit suffixes, row groups and family labels,
// plot, series and table builders.
#include "collect_support.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace camopt::report::detail {
namespace {

// the unit words of camopt's column names and keys
bool is_unit_word(std::string_view w) {
  static const char* const words[] = {"mm", "m", "um", "deg", "rad", "s", "N", "Nm", "MPa", "Pa",
                                      "Hz", "rpm", "W", "kg", "J", "in"};
  while (!w.empty() && (w.back() == '2' || w.back() == '3')) w.remove_suffix(1);
  return std::any_of(std::begin(words), std::end(words), [&](const char* u) { return w == u; });
}

// "deg2" -> "deg^2"
std::string power_of(std::string_view w) {
  if (!w.empty() && (w.back() == '2' || w.back() == '3'))
    return std::string(w.substr(0, w.size() - 1)) + "^" + w.back();
  return std::string(w);
}

// the words from `first` on read as a unit: factors, optionally "per" and more factors
bool parse_unit(const std::vector<std::string_view>& words, std::size_t first, std::string& unit) {
  std::string numerator, denominator;
  bool per = false;
  for (std::size_t i = first; i < words.size();) {
    if (words[i] == "per" && !per && !numerator.empty()) {
      per = true;
      ++i;
      continue;
    }
    std::string factor;
    if (words[i] == "sqrt" && i + 1 < words.size() && is_unit_word(words[i + 1])) {
      factor = "sqrt(" + power_of(words[i + 1]) + ")";
      i += 2;
    } else if (is_unit_word(words[i])) {
      factor = power_of(words[i]);
      ++i;
    } else {
      return false;
    }
    std::string& side = per ? denominator : numerator;
    side += (side.empty() ? "" : " ") + factor;
  }
  if (numerator.empty() || (per && denominator.empty())) return false;
  unit = per ? numerator + "/" + denominator : numerator;
  return true;
}

// words of a quantity for a reader: "vel" -> "velocity", "acc" -> "acceleration"
std::string readable(const std::vector<std::string_view>& words, std::size_t count) {
  std::string out;
  for (std::size_t i = 0; i < count; ++i) {
    std::string_view w = words[i];
    if (w == "vel") w = "velocity";
    if (w == "acc") w = "acceleration";
    out += (out.empty() ? "" : " ") + std::string(w);
  }
  if (out == "cam" || out == "crank") out += " angle";
  if (out.empty()) out = "engine speed";  // "rpm"
  return out;
}

std::string dotted(const std::string& prefix, const std::string& key) { return prefix.empty() ? key : prefix + "." + key; }

// the scalar members of `j`, nested objects flattened, as (key, text) rows
void flatten(const nlohmann::json& j, const std::string& prefix, std::vector<std::vector<std::string>>& rows) {
  for (const auto& [key, value] : j.items()) {
    if (value.is_object()) {
      flatten(value, dotted(prefix, key), rows);
      continue;
    }
    std::string text;
    if (value.is_array()) {
      if (std::any_of(value.begin(), value.end(), [](const auto& e) { return e.is_structured(); })) continue;
      for (const auto& e : value) text += (text.empty() ? "" : ", ") + format_scalar(e);
      if (text.empty()) text = "none";
    } else {
      text = format_scalar(value);
    }
    const Axis a = axis_of(key);
    rows.push_back({dotted(prefix, a.unit == "-" ? key : heading(a)), text});
  }
}

}  // namespace

Axis axis_of(std::string_view name) {
  std::vector<std::string_view> words;
  for (std::string_view rest = name;;) {
    const std::size_t cut = rest.find('_');
    words.push_back(rest.substr(0, cut));
    if (cut == std::string_view::npos) break;
    rest.remove_prefix(cut + 1);
  }
  // the first word from which the rest reads as a unit
  for (std::size_t first = 0; first < words.size(); ++first) {
    std::string unit;
    if (parse_unit(words, first, unit)) return {readable(words, first), unit};
  }
  return {readable(words, words.size()), "-"};
}

std::string heading(const Axis& axis) { return axis.label + " [" + axis.unit + "]"; }

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string format_scalar(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "yes" : "no";
  if (value.is_null()) return "none";
  if (value.is_number_integer()) return std::to_string(value.get<long long>());
  if (value.is_number()) return format_number(value.get<double>());
  return value.dump();
}

std::vector<Group> group_rows(const CsvData& csv, const std::vector<std::string>& key_columns) {
  std::vector<const std::vector<double>*> keys;
  for (const auto& k : key_columns)
    if (const auto* column = csv.find(k)) keys.push_back(column);
  std::vector<Group> groups;
  for (std::size_t row = 0; row < csv.rows(); ++row) {
    std::vector<double> values;
    for (const auto* k : keys) values.push_back((*k)[row]);
    if (groups.empty() || groups.back().keys != values) groups.push_back({row, row, values});
    groups.back().end = row + 1;
  }
  return groups;
}

std::vector<double> slice(const std::vector<double>& column, const Group& group) {
  return {column.begin() + static_cast<std::ptrdiff_t>(group.begin),
          column.begin() + static_cast<std::ptrdiff_t>(group.end)};
}

std::vector<std::string> family_labels(const std::vector<std::string>& key_columns, const std::vector<Group>& groups) {
  std::vector<std::string> labels(groups.size());
  if (groups.size() < 2) return labels;
  const std::size_t n = groups.front().keys.size();
  for (std::size_t k = 0; k < n && k < key_columns.size(); ++k) {
    // a key that is the same in every group names nothing
    const bool varies = std::any_of(groups.begin(), groups.end(), [&](const Group& g) {
      return g.keys[k] != groups.front().keys[k];
    });
    if (!varies) continue;
    const Axis a = axis_of(key_columns[k]);
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const std::string value = format_number(groups[g].keys[k]);
      const std::string text = a.unit == "rpm" ? value + " rpm"
                               : a.unit == "-"  ? a.label + " " + value
                                                : a.label + " " + value + " " + a.unit;
      labels[g] += (labels[g].empty() ? "" : ", ") + text;
    }
  }
  return labels;
}

Plot line_plot(std::string id, std::string title, std::string section, const std::string& x_column,
               const std::string& y_column, std::string link_group) {
  Plot p;
  p.id = std::move(id);
  p.title = std::move(title);
  p.section = std::move(section);
  p.kind = PlotKind::line;
  p.x = axis_of(x_column);
  p.y = axis_of(y_column);
  p.link_group = std::move(link_group);
  return p;
}

bool add_group_series(Plot& plot, const CsvData& csv, const std::vector<Group>& groups,
                      const std::vector<std::string>& labels, const std::string& x_column,
                      const std::string& y_column, const std::string& name, bool dashed) {
  const std::vector<double>& x = csv.at(x_column);
  const std::vector<double>& y = csv.at(y_column);
  if (std::all_of(y.begin(), y.end(), [](double v) { return v == 0.0 || std::isnan(v); })) return false;
  if (groups.empty()) return false;
  // the series share the plot's x when every group has its angles
  const auto has_x = [&](const Group& g, const std::vector<double>& ref) {
    return g.end - g.begin == ref.size() &&
           std::equal(ref.begin(), ref.end(), x.begin() + static_cast<std::ptrdiff_t>(g.begin));
  };
  if (plot.series.empty()) plot.x_values = slice(x, groups.front());
  const bool shared = std::all_of(groups.begin(), groups.end(), [&](const Group& g) { return has_x(g, plot.x_values); });
  if (plot.series.empty() && !shared) plot.x_values.clear();
  // a second quantity on a family's plot is named with the member's label
  const bool qualify = groups.size() > 1 && !plot.series.empty();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    Series s;
    s.name = groups.size() > 1 && !labels[g].empty() ? labels[g] : name;
    if (qualify) s.name += ", " + name;
    s.family_member = groups.size() > 1 ? static_cast<int>(g) : -1;
    if (!shared) s.x = slice(x, groups[g]);
    s.y = slice(y, groups[g]);
    s.dashed = dashed;
    plot.series.push_back(std::move(s));
  }
  return true;
}

Table key_value_table(std::string id, std::string title, std::string section, const nlohmann::json& object) {
  Table t;
  t.id = std::move(id);
  t.title = std::move(title);
  t.section = std::move(section);
  t.columns = {"quantity [unit]", "value"};
  flatten(object, "", t.rows);
  return t;
}

Table rows_table(std::string id, std::string title, std::string section, const nlohmann::json& array,
                 const std::vector<std::string>& first_columns) {
  Table t;
  t.id = std::move(id);
  t.title = std::move(title);
  t.section = std::move(section);
  if (!array.is_array() || array.empty() || !array.front().is_object()) return t;
  // the columns: the named ones first, then every scalar member of the first row with a unit
  std::vector<std::string> keys;
  for (const auto& k : first_columns)
    if (array.front().contains(k)) keys.push_back(k);
  for (const auto& [key, value] : array.front().items())
    if (value.is_primitive() && std::find(keys.begin(), keys.end(), key) == keys.end() &&
        (axis_of(key).unit != "-" || value.is_boolean() || value.is_string()))
      keys.push_back(key);
  for (const auto& k : keys)
    t.columns.push_back(array.front()[k].is_string() || axis_of(k).unit == "-" ? k : heading(axis_of(k)));
  for (const auto& entry : array) {
    std::vector<std::string> row;
    for (const auto& k : keys) row.push_back(entry.contains(k) ? format_scalar(entry[k]) : "");
    t.rows.push_back(std::move(row));
  }
  return t;
}

void add_facts(ReportData& data, const nlohmann::json& j, const std::vector<std::string>& fact_keys) {
  for (const auto& key : fact_keys) {
    const auto it = j.find(key);
    if (it == j.end() || it->is_structured()) continue;
    const Axis a = axis_of(key);
    data.facts.push_back({a.unit == "-" || it->is_string() ? key : heading(a), format_scalar(*it)});
  }
}

void add_section(ReportData& data, std::string id, std::string title) {
  for (const auto& s : data.sections)
    if (s.id == id) return;
  data.sections.push_back({std::move(id), std::move(title)});
}

}  // namespace camopt::report::detail
