#pragma once
#include "camopt/io/input_file.hpp"
// the checking layer shared by the TOML readers (design files, constraint sets): typed,
// range-checked values that know their file, line and key path, and tables that reject
// keys they do not know. internal to camopt_io.
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "camopt/core/design_spec.hpp"
#include "camopt/core/error.hpp"
#include "camopt/core/printable.hpp"
#include "camopt/io/csv.hpp"

namespace camopt::io::toml_detail {

namespace fs = std::filesystem;
using Keys = std::vector<std::string_view>;

// ---- message text

// shortest text that reads back to the same double
inline std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

inline std::string quote(std::string_view s) { return "\"" + printable(s) + "\""; }

inline std::string join(const Keys& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i > 0 ? ", " : "") + std::string(items[i]);
  return out;
}

inline Keys concat(Keys a, const Keys& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

inline bool contains(const Keys& keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// a TOML value as the user wrote it: string "a", integer 3, array of 2 elements, ...
inline std::string describe(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "string " + quote(node.as_string()->get());
    case toml::node_type::integer: return "integer " + std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point: return "float " + format_number(node.as_floating_point()->get());
    case toml::node_type::boolean: return node.as_boolean()->get() ? "boolean true" : "boolean false";
    case toml::node_type::array: return "array of " + std::to_string(node.as_array()->size()) + " elements";
    case toml::node_type::table: return "table";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

inline std::string indexed(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// ---- numeric rules: "value -2 must be > 0"

struct Bound {
  double value = 0.0;
  bool strict = false;
  std::string label;  // names a bound taken from another key, e.g. "start_deg"

  std::string str() const { return label.empty() ? format_number(value) : label + " (" + format_number(value) + ")"; }
};

struct Rule {
  std::optional<Bound> lo, hi;
  bool nonzero = false;

  // "" when `v` satisfies the rule, else the rule ("must be > 0"); non-finite always fails
  std::string violation(double v) const {
    if (!std::isfinite(v)) return "must be finite";
    const bool ok = (!lo || (lo->strict ? v > lo->value : v >= lo->value)) &&
                    (!hi || (hi->strict ? v < hi->value : v <= hi->value)) && (!nonzero || v != 0.0);
    if (ok) return {};
    std::string text = "must be ";
    if (lo && hi && lo->label.empty() && hi->label.empty()) {
      text += std::string("in ") + (lo->strict ? "(" : "[") + lo->str() + ", " + hi->str() + (hi->strict ? ")" : "]");
    } else {
      if (lo) text += std::string(lo->strict ? "> " : ">= ") + lo->str();
      if (lo && hi) text += " and ";
      if (hi) text += std::string(hi->strict ? "< " : "<= ") + hi->str();
    }
    if (nonzero) text += (lo || hi) ? " and non-zero" : "non-zero";
    return text;
  }
};

inline Rule gt(double v, std::string label = {}) { return {Bound{v, true, std::move(label)}, {}, false}; }
inline Rule ge(double v, std::string label = {}) { return {Bound{v, false, std::move(label)}, {}, false}; }
inline Rule lt(double v, std::string label = {}) { return {{}, Bound{v, true, std::move(label)}, false}; }
inline Rule le(double v, std::string label = {}) { return {{}, Bound{v, false, std::move(label)}, false}; }
inline Rule nonzero() { return {{}, {}, true}; }
inline Rule operator&(Rule a, const Rule& b) {
  if (b.lo) a.lo = b.lo;
  if (b.hi) a.hi = b.hi;
  a.nonzero = a.nonzero || b.nonzero;
  return a;
}

// ---- one value, typed

// the text of a value given by an override (`--set key.path=value`): a value written there
// is reported at the override, not at the line it was edited into
struct OverrideSpan {
  toml::source_position begin, end;  // [begin, end] in the edited text
  std::string label;                 // "--set key.path=value"
};

struct Context {
  std::string file;
  std::string directory;
  std::vector<OverrideSpan> overrides;  // empty unless the text carries overrides

  SourceRef ref(const toml::source_region& source, std::string key_path) const {
    if (!overrides.empty())
      if (const OverrideSpan* span = override_at(source.begin)) return {span->label, 0, 0, std::move(key_path)};
    return {file, static_cast<int>(source.begin.line), static_cast<int>(source.begin.column), std::move(key_path)};
  }
  const OverrideSpan* override_at(const toml::source_position& p) const {
    const auto before = [](const toml::source_position& a, const toml::source_position& b) {
      return a.line < b.line || (a.line == b.line && a.column <= b.column);
    };
    for (const OverrideSpan& span : overrides)
      if (before(span.begin, p) && before(p, span.end)) return &span;
    return nullptr;
  }
  // relative references are resolved against the design file's directory
  fs::path resolve(const std::string& name) const {
    fs::path path(name);
    if (path.is_relative() && !directory.empty()) path = fs::path(directory) / path;
    return path.lexically_normal();
  }
};

inline double to_number(const toml::node& node, const SourceRef& at, const Rule& rule) {
  double value = 0.0;
  if (const auto* i = node.as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    value = f->get();
  } else {
    throw InputError(at, "expected a number, got " + describe(node));
  }
  if (const std::string why = rule.violation(value); !why.empty())
    throw InputError(at, "value " + format_number(value) + " " + why);
  return value;
}

inline std::string to_string_value(const toml::node& node, const SourceRef& at, bool allow_empty = false) {
  const auto* s = node.as_string();
  if (!s) throw InputError(at, "expected a string, got " + describe(node));
  if (s->get().empty() && !allow_empty) throw InputError(at, "value \"\" must be non-empty");
  return s->get();
}

// ---- a numeric series with the origin of every value

struct Column {
  std::string name;             // key or CSV column name, for messages
  std::vector<double> values;
  std::vector<SourceRef> refs;  // where each value was written (an inline array)
  SourceRef where;              // the whole array / CSV column
  std::optional<SourceRef> via; // the `file = ...` key that brought a CSV column
  std::vector<int> lines;       // a CSV column: the file line of each value (refs stays empty)

  // where value i was written; a CSV cell's location is built only when asked (for an error)
  SourceRef ref(std::size_t i) const {
    if (i < refs.size()) return refs[i];
    return SourceRef{where.file, i < lines.size() ? lines[i] : 0, 0, where.key_path};
  }
  [[noreturn]] void fail(const SourceRef& at, const std::string& message) const {
    if (!via) throw InputError(at, message);
    throw InputError(*via, InputError(at, message).what());
  }
  void check_each(const Rule& rule) const {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (const std::string why = rule.violation(values[i]); !why.empty())
        fail(ref(i), "value " + format_number(values[i]) + " " + why);
  }
  void check_increasing() const {
    for (std::size_t i = 1; i < values.size(); ++i)
      if (!(std::isfinite(values[i]) && values[i] > values[i - 1])) {
        const std::string why = gt(values[i - 1], "previous value").violation(values[i]);
        fail(ref(i), "value " + format_number(values[i]) + " " + why + "; values must be strictly increasing");
      }
  }
  void check_min_points(std::size_t count) const {
    if (values.size() < count)
      fail(where, "expected at least " + std::to_string(count) + " points, got " + std::to_string(values.size()));
  }
  // angles of one revolution: last - first < 360 (the first point is not repeated)
  void check_span_below_turn() const {
    const double span = values.back() - values.front();
    if (span >= 360.0)
      fail(where, "angles span " + format_number(span) + " deg (" + format_number(values.front()) + " to " +
                      format_number(values.back()) + "); the span must be < 360 (do not repeat the first point)");
  }
};

inline void check_same_size(const Column& x, const Column& y) {
  if (x.values.size() != y.values.size())
    y.fail(y.where, std::to_string(y.values.size()) + " values, but " + x.name + " has " +
                        std::to_string(x.values.size()) + " (must be the same length)");
}

// ---- a TOML table that knows its key path

class Table {
 public:
  Table(const Context& context, const toml::table& table, std::string path)
      : context_(&context), table_(&table), path_(std::move(path)) {}

  const Context& context() const { return *context_; }
  std::string path_of(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }
  bool has(std::string_view key) const { return table_->contains(key); }

  // the table itself; the value of `key` (the table when the key is absent)
  SourceRef where() const { return context_->ref(table_->source(), path_); }
  SourceRef where(std::string_view key) const {
    const toml::node* node = table_->get(key);
    return context_->ref(node ? node->source() : table_->source(), path_of(key));
  }

  [[noreturn]] void fail(const std::string& message) const { throw InputError(where(), message); }
  [[noreturn]] void fail(std::string_view key, const std::string& message) const {
    throw InputError(where(key), message);
  }

  // every key must be in `allowed`; keys in `elsewhere` are valid only in another variant
  // (`variant` says which one this is, e.g. type = "floating")
  void allow(const Keys& allowed, const Keys& elsewhere = {}, std::string_view variant = {}) const {
    const toml::key* first = nullptr;
    for (auto&& [key, node] : *table_) {
      if (contains(allowed, key.str())) continue;
      const auto& a = key.source().begin;
      if (!first || a.line < first->source().begin.line ||
          (a.line == first->source().begin.line && a.column < first->source().begin.column))
        first = &key;
    }
    if (!first) return;
    const SourceRef at = context_->ref(first->source(), path_);
    const std::string name(first->str());
    if (contains(elsewhere, name))
      throw InputError(at, "key '" + name + "' is not allowed for " + std::string(variant) + " (allowed: " +
                               join(allowed) + ")");
    throw InputError(at, "unknown key '" + name + "' (allowed: " + join(allowed) + ")");
  }

  const toml::node& require(std::string_view key) const {
    const toml::node* node = table_->get(key);
    if (!node) fail("missing required key '" + std::string(key) + "'");
    return *node;
  }

  // strings
  std::string string(std::string_view key) const { return to_string_value(require(key), where(key)); }
  // free text, may be empty
  std::string text_or(std::string_view key, std::string fallback) const {
    return has(key) ? to_string_value(require(key), where(key), true) : fallback;
  }
  std::string identifier(std::string_view key) const {
    std::string value = string(key);
    const auto head = [](char c) { return c == '_' || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
    const auto tail = [&](char c) { return head(c) || (c >= '0' && c <= '9'); };
    if (!head(value.front()) || !std::all_of(value.begin() + 1, value.end(), tail))
      fail(key, "value " + quote(value) + " must be an identifier ([A-Za-z_][A-Za-z0-9_]*)");
    return value;
  }
  template <class E>
  E choice(std::string_view key, std::initializer_list<std::pair<std::string_view, E>> options) const {
    const std::string value = string(key);
    Keys names;
    for (const auto& [name, option] : options) {
      if (name == value) return option;
      names.push_back(name);
    }
    fail(key, "value " + quote(value) + " must be one of: " + join(names));
  }
  // two distinct strings, e.g. nodes = ["cam", "rocker"]; `where` gets each one's origin
  std::array<std::string, 2> string_pair(std::string_view key, std::array<SourceRef, 2>& where_each) const {
    const toml::node& node = require(key);
    const auto* array = node.as_array();
    if (!array || array->size() != 2) fail(key, "expected an array of 2 strings, got " + describe(node));
    std::array<std::string, 2> out;
    for (std::size_t i = 0; i < 2; ++i) {
      where_each[i] = context_->ref((*array)[i].source(), indexed(path_of(key), i));
      out[i] = to_string_value((*array)[i], where_each[i]);
    }
    return out;
  }

  // numbers (integers are accepted)
  double number(std::string_view key, const Rule& rule = {}) const {
    return to_number(require(key), where(key), rule);
  }
  std::optional<double> optional_number(std::string_view key, const Rule& rule = {}) const {
    if (!has(key)) return std::nullopt;
    return number(key, rule);
  }
  double number_or(std::string_view key, double fallback, const Rule& rule = {}) const {
    return has(key) ? number(key, rule) : fallback;
  }
  long long integer(std::string_view key, const Rule& rule = {}) const {
    const toml::node& node = require(key);
    if (!node.is_integer()) fail(key, "expected an integer, got " + describe(node));
    to_number(node, where(key), rule);
    return node.as_integer()->get();
  }
  long long integer_or(std::string_view key, long long fallback, const Rule& rule = {}) const {
    return has(key) ? integer(key, rule) : fallback;
  }
  bool boolean_or(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    const toml::node& node = require(key);
    if (!node.is_boolean()) fail(key, "expected a boolean, got " + describe(node));
    return node.as_boolean()->get();
  }

  // points and directions [x, y]
  Vec2 vec2(std::string_view key) const {
    const toml::node& node = require(key);
    const auto* array = node.as_array();
    if (!array || array->size() != 2) fail(key, "expected an array of 2 numbers, got " + describe(node));
    Vec2 out{};
    for (std::size_t i = 0; i < 2; ++i) {
      const toml::node& element = (*array)[i];
      if (!element.is_number())
        throw InputError(context_->ref(element.source(), path_of(key)),
                         "expected an array of 2 numbers, got " + describe(element) + " at index " +
                             std::to_string(i));
      out[i] = to_number(element, context_->ref(element.source(), indexed(path_of(key), i)), {});
    }
    return out;
  }
  std::optional<Vec2> optional_vec2(std::string_view key) const {
    if (!has(key)) return std::nullopt;
    return vec2(key);
  }
  // a direction: any non-zero length
  Vec2 direction(std::string_view key) const {
    const Vec2 v = vec2(key);
    if (v[0] == 0.0 && v[1] == 0.0) fail(key, "value [0, 0] must have non-zero length");
    return v;
  }
  Vec2 direction_or(std::string_view key, Vec2 fallback) const { return has(key) ? direction(key) : fallback; }

  // an inline array of numbers
  Column numbers(std::string_view key) const {
    const toml::node& node = require(key);
    const auto* array = node.as_array();
    if (!array) fail(key, "expected an array of numbers, got " + describe(node));
    Column column{std::string(key), {}, {}, where(key), std::nullopt, {}};
    for (std::size_t i = 0; i < array->size(); ++i) {
      column.refs.push_back(context_->ref((*array)[i].source(), indexed(path_of(key), i)));
      column.values.push_back(to_number((*array)[i], column.refs.back(), {}));
    }
    return column;
  }

  // sub-tables
  Table table(std::string_view key) const {
    const toml::node& node = require(key);
    if (!node.is_table()) fail(key, "expected a table, got " + describe(node));
    return Table(*context_, *node.as_table(), path_of(key));
  }
  std::optional<Table> optional_table(std::string_view key) const {
    if (!has(key)) return std::nullopt;
    return table(key);
  }
  // [[key]] entries; empty when absent
  std::vector<Table> array_of_tables(std::string_view key) const {
    std::vector<Table> out;
    if (!has(key)) return out;
    const toml::node& node = require(key);
    const auto* array = node.as_array();
    if (!array) fail(key, "expected an array of tables ([[" + std::string(key) + "]]), got " + describe(node));
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& element = (*array)[i];
      const std::string path = indexed(path_of(key), i);
      if (!element.is_table())
        throw InputError(context_->ref(element.source(), path), "expected a table, got " + describe(element));
      out.emplace_back(*context_, *element.as_table(), path);
    }
    return out;
  }

 private:
  const Context* context_;
  const toml::table* table_;
  std::string path_;
};


// the document of a TOML text; a syntax error is an InputError at its line and column
inline toml::table parse_document(std::string_view text, const Context& context) {
  try {
    return toml::parse(text, std::string_view(context.file));
  } catch (const toml::parse_error& e) {
    throw InputError(context.ref(e.source(), ""), "TOML syntax error: " + std::string(e.description()));
  }
}

// the whole file (io::read_input_file's checks) and its directory ("." for a bare name)
inline std::string read_text_file(const std::string& path, const char* what, std::string& directory) {
  std::string text = read_input_file(path, what);
  directory = fs::path(path).parent_path().string();
  if (directory.empty()) directory = ".";
  return text;
}

}  // namespace camopt::io::toml_detail
