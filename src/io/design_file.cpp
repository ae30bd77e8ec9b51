// design files (TOML) -> DesignSpec (docs/design-format.md).
//
// one small helper layer does the checking: `Table` knows its key path and gives typed,
// range-checked values ("allowed keys" included); `Column` is a numeric series (inline
// array or CSV column) that remembers where every value was written. The section parsers
// below only say what the schema is. Cross references are collected while parsing and
// resolved at the end, each reported at the key that names it.
#include "camopt/io/design_file.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <system_error>
#include <utility>

#include "camopt/core/error.hpp"
#include "camopt/io/csv.hpp"

namespace camopt::io {
namespace {

namespace fs = std::filesystem;
using Keys = std::vector<std::string_view>;

// ---- message text

// shortest text that reads back to the same double
std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string quote(std::string_view s) { return "\"" + std::string(s) + "\""; }

std::string join(const Keys& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i > 0 ? ", " : "") + std::string(items[i]);
  return out;
}

Keys concat(Keys a, const Keys& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

bool contains(const Keys& keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// a TOML value as the user wrote it: string "a", integer 3, array of 2 elements, ...
std::string describe(const toml::node& node) {
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

std::string indexed(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

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

Rule gt(double v, std::string label = {}) { return {Bound{v, true, std::move(label)}, {}, false}; }
Rule ge(double v, std::string label = {}) { return {Bound{v, false, std::move(label)}, {}, false}; }
Rule lt(double v, std::string label = {}) { return {{}, Bound{v, true, std::move(label)}, false}; }
Rule le(double v, std::string label = {}) { return {{}, Bound{v, false, std::move(label)}, false}; }
Rule nonzero() { return {{}, {}, true}; }
Rule operator&(Rule a, const Rule& b) {
  if (b.lo) a.lo = b.lo;
  if (b.hi) a.hi = b.hi;
  a.nonzero = a.nonzero || b.nonzero;
  return a;
}

// ---- one value, typed

struct Context {
  std::string file;
  std::string directory;

  SourceRef ref(const toml::source_region& source, std::string key_path) const {
    return {file, static_cast<int>(source.begin.line), static_cast<int>(source.begin.column), std::move(key_path)};
  }
  // relative references are resolved against the design file's directory
  fs::path resolve(const std::string& name) const {
    fs::path path(name);
    if (path.is_relative() && !directory.empty()) path = fs::path(directory) / path;
    return path.lexically_normal();
  }
};

double to_number(const toml::node& node, const SourceRef& at, const Rule& rule) {
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

std::string to_string_value(const toml::node& node, const SourceRef& at, bool allow_empty = false) {
  const auto* s = node.as_string();
  if (!s) throw InputError(at, "expected a string, got " + describe(node));
  if (s->get().empty() && !allow_empty) throw InputError(at, "value \"\" must be non-empty");
  return s->get();
}

// ---- a numeric series with the origin of every value

struct Column {
  std::string name;             // key or CSV column name, for messages
  std::vector<double> values;
  std::vector<SourceRef> refs;  // where each value was written
  SourceRef where;              // the whole array / CSV column
  std::optional<SourceRef> via; // the `file = ...` key that brought a CSV column

  [[noreturn]] void fail(const SourceRef& at, const std::string& message) const {
    if (!via) throw InputError(at, message);
    throw InputError(*via, InputError(at, message).what());
  }
  void check_each(const Rule& rule) const {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (const std::string why = rule.violation(values[i]); !why.empty())
        fail(refs[i], "value " + format_number(values[i]) + " " + why);
  }
  void check_increasing() const {
    for (std::size_t i = 1; i < values.size(); ++i)
      if (const std::string why = gt(values[i - 1], "previous value").violation(values[i]); !why.empty())
        fail(refs[i], "value " + format_number(values[i]) + " " + why + "; values must be strictly increasing");
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

void check_same_size(const Column& x, const Column& y) {
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
    Column column{std::string(key), {}, {}, where(key), std::nullopt};
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

// ---- "file or inline arrays": two columns from a CSV file or from two inline arrays

struct Series {
  Column x, y;
  std::string source_file;  // resolved CSV path, "" when inline
};

// x_csv: accepted CSV names of the x column; x_key / y_key: inline keys (y_key is also the
// CSV name of the y column)
Series read_series(const Table& t, const std::vector<std::string>& x_csv, std::string_view x_key,
                   std::string_view y_key) {
  if (!t.has("file")) {
    if (!t.has(x_key) && !t.has(y_key))
      t.fail("missing table: give 'file' or inline '" + std::string(x_key) + "' and '" + std::string(y_key) + "'");
    Series s{t.numbers(x_key), t.numbers(y_key), {}};
    check_same_size(s.x, s.y);
    return s;
  }
  if (t.has(x_key) || t.has(y_key))
    t.fail(t.has(x_key) ? x_key : y_key, "give either 'file' or inline arrays, not both");

  const std::string name = t.string("file");
  const SourceRef via = t.where("file");
  const fs::path path = t.context().resolve(name);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    t.fail("file", "file " + quote(name) + " not found (resolved to " + quote(path.string()) + ")");
  try {
    const CsvTable csv = read_csv(path.string());
    const std::size_t xi = csv.require_one_of(x_csv, x_key);
    const std::size_t yi = csv.require_one_of({std::string(y_key)}, y_key);
    const auto column = [&](std::size_t c) {
      Column out{csv.columns[c], csv.values[c], {}, SourceRef{csv.file, 0, 0, csv.columns[c]}, via};
      for (const int line : csv.lines) out.refs.push_back(SourceRef{csv.file, line, 0, csv.columns[c]});
      return out;
    };
    return Series{column(xi), column(yi), path.string()};
  } catch (const InputError& e) {
    throw InputError(via, e.what());
  }
}

// ---- the design file

struct Reference {
  enum class To { node, control, profile, material } to;
  std::string name;
  SourceRef where;                 // the key naming it
  std::optional<NodeKind> kind;    // a node of this kind is required ...
  std::string role;                // ... by this role ("a compression spring")
  bool free_node = false;          // the node must not be set by a control
};

template <class Spec>
const Spec* find_named(const std::vector<Spec>& specs, const std::string& name) {
  for (const auto& spec : specs)
    if (spec.name == name) return &spec;
  return nullptr;
}

template <class Spec>
std::string names_of(const std::vector<Spec>& specs) {
  if (specs.empty()) return "none defined";
  std::string out = "defined: ";
  for (std::size_t i = 0; i < specs.size(); ++i) out += (i > 0 ? ", " : "") + specs[i].name;
  return out;
}

// names are unique within a section
template <class Spec>
void check_unique(const std::vector<Spec>& specs, const Spec& spec, const Table& t) {
  for (const auto& other : specs)
    if (other.name == spec.name)
      t.fail("name", "duplicate name " + quote(spec.name) + " (already used by " + other.where.key_path +
                         " at line " + std::to_string(other.where.line) + ")");
}

const Keys kRootKeys = {"schema", "design", "driver", "control", "node", "profile",
                        "connection", "material", "spring", "gas_force"};

class Parser {
 public:
  explicit Parser(const Context& context) : context_(context) {}

  DesignSpec run(const toml::table& document) {
    const Table root(context_, document, "");
    root.allow(kRootKeys);
    if (const long long schema = root.integer("schema"); schema != 1)
      root.fail("schema", "value " + std::to_string(schema) + " is not a supported schema version (must be 1)");

    DesignSpec spec;
    spec.file = context_.file;
    spec.directory = context_.directory;
    parse_header(root.table("design"), spec);
    spec.driver = parse_driver(root.table("driver"));
    for (const Table& t : root.array_of_tables("control")) add(spec.controls, parse_control(t), t);
    for (const Table& t : root.array_of_tables("node")) add(spec.nodes, parse_node(t), t);
    for (const Table& t : root.array_of_tables("profile")) add(spec.profiles, parse_profile(t), t);
    for (const Table& t : root.array_of_tables("material")) add(spec.materials, parse_material(t), t);
    for (const Table& t : root.array_of_tables("connection")) add(spec.connections, parse_connection(t), t);
    for (const Table& t : root.array_of_tables("spring")) add(spec.springs, parse_spring(t), t);
    for (const Table& t : root.array_of_tables("gas_force")) spec.gas_forces.push_back(parse_gas_force(t));
    resolve(spec);
    return spec;
  }

 private:
  template <class Spec>
  void add(std::vector<Spec>& specs, Spec spec, const Table& t) {
    check_unique(specs, spec, t);
    specs.push_back(std::move(spec));
  }

  void refer(Reference::To to, const Table& t, std::string_view key, std::optional<NodeKind> kind = {},
             std::string role = {}) {
    refer(to, t.string(key), t.where(key), kind, std::move(role));
  }
  void refer(Reference::To to, std::string name, SourceRef where, std::optional<NodeKind> kind = {},
             std::string role = {}) {
    references_.push_back({to, std::move(name), std::move(where), kind, std::move(role), false});
  }

  void parse_header(const Table& t, DesignSpec& spec) {
    t.allow({"name", "description", "output_node"});
    spec.name = t.string("name");
    spec.description = t.text_or("description", "");
    spec.output_node = t.string("output_node");
    refer(Reference::To::node, t, "output_node");
  }

  DriverSpec parse_driver(const Table& t) {
    t.allow({"node", "start_deg", "stop_deg", "step_deg", "crank_per_cam"});
    DriverSpec d;
    d.node = t.string("node");
    refer(Reference::To::node, t, "node");
    references_.back().free_node = true;
    d.start_deg = t.number_or("start_deg", 0.0);
    d.stop_deg = t.number_or("stop_deg", d.start_deg + 360.0, gt(d.start_deg, "start_deg"));
    d.step_deg = t.number_or("step_deg", 1.0, gt(0.0) & le(d.stop_deg - d.start_deg, "stop_deg - start_deg"));
    d.crank_per_cam = t.number_or("crank_per_cam", 2.0, gt(0.0));
    d.where = t.where();
    return d;
  }

  ControlSpec parse_control(const Table& t) {
    t.allow({"name", "unit", "min", "max", "default"});
    ControlSpec c;
    c.name = t.string("name");
    c.unit = t.has("unit") ? t.choice<std::string>("unit", {{"deg", "deg"}, {"mm", "mm"}}) : "deg";
    c.min = t.number("min");
    c.max = t.number("max", ge(c.min, "min"));
    c.default_value = t.number_or("default", c.min, ge(c.min, "min") & le(c.max, "max"));
    c.where = t.where();
    return c;
  }

  NodeSpec parse_node(const Table& t) {
    NodeSpec n;
    n.name = t.identifier("name");
    n.kind = t.choice<NodeKind>("type", {{"rotational", NodeKind::rotational},
                                         {"translational", NodeKind::translational},
                                         {"floating", NodeKind::floating}});
    const Keys common = {"name", "type", "mass_kg", "inertia_kg_mm2", "cg_mm", "damping_ratio"};
    const Keys rotational = {"pivot_mm", "pivot_motion", "control", "rest_deg", "torsional_stiffness_Nm_per_rad"};
    const Keys translational = {"origin_mm", "direction", "control", "rest_mm", "axial_stiffness_N_per_mm"};
    const Keys floating = {"torsional_stiffness_Nm_per_rad"};
    const Keys& own = n.kind == NodeKind::rotational      ? rotational
                      : n.kind == NodeKind::translational ? translational
                                                          : floating;
    t.allow(concat(common, own), concat(rotational, translational),
            std::string("type = ") + quote(to_string(n.kind)));

    if (n.kind == NodeKind::rotational) {
      n.pivot_mm = t.vec2("pivot_mm");
      if (const auto m = t.optional_table("pivot_motion")) {
        m->allow({"control", "about_mm", "gain"});
        PivotMotionSpec motion;
        motion.control = m->string("control");
        refer(Reference::To::control, *m, "control");
        motion.about_mm = m->vec2("about_mm");
        motion.gain = m->number_or("gain", 1.0);
        motion.where = m->where();
        n.pivot_motion = motion;
      }
      n.rest = t.number_or("rest_deg", 0.0);
    } else if (n.kind == NodeKind::translational) {
      n.origin_mm = t.vec2("origin_mm");
      n.direction = t.direction_or("direction", {0.0, 1.0});
      n.rest = t.number_or("rest_mm", 0.0);
    }
    if (t.has("control")) {
      n.control = t.string("control");
      refer(Reference::To::control, t, "control");
    }
    n.mass_kg = t.optional_number("mass_kg", gt(0.0));
    n.inertia_kg_mm2 = t.optional_number("inertia_kg_mm2", gt(0.0));
    n.cg_mm = t.optional_vec2("cg_mm");
    n.torsional_stiffness_Nm_per_rad = t.optional_number("torsional_stiffness_Nm_per_rad", gt(0.0));
    n.axial_stiffness_N_per_mm = t.optional_number("axial_stiffness_N_per_mm", gt(0.0));
    n.damping_ratio = t.optional_number("damping_ratio", ge(0.0));
    n.where = t.where();
    return n;
  }

  ProfileSpec parse_profile(const Table& t) {
    ProfileSpec p;
    p.name = t.string("name");
    p.form = t.choice<ProfileForm>("form", {{"polar", ProfileForm::polar},
                                            {"xy", ProfileForm::xy},
                                            {"base_plus_lift", ProfileForm::base_plus_lift},
                                            {"circle", ProfileForm::circle},
                                            {"eccentric", ProfileForm::eccentric}});
    const Keys common = {"name", "form"};
    const Keys polar = {"file", "angle_deg", "radius_mm"};
    const Keys xy = {"file", "x_mm", "y_mm"};
    const Keys base_plus_lift = {"base_radius_mm", "file", "angle_deg", "lift_mm"};
    const Keys circle = {"disc_radius_mm"};
    const Keys eccentric = {"disc_radius_mm", "eccentricity_mm"};
    const Keys* own = &polar;
    switch (p.form) {
      case ProfileForm::polar: own = &polar; break;
      case ProfileForm::xy: own = &xy; break;
      case ProfileForm::base_plus_lift: own = &base_plus_lift; break;
      case ProfileForm::circle: own = &circle; break;
      case ProfileForm::eccentric: own = &eccentric; break;
    }
    t.allow(concat(common, *own), concat(concat(polar, xy), concat(base_plus_lift, eccentric)),
            std::string("form = ") + quote(to_string(p.form)));

    const std::vector<std::string> angle_names = {"angle_deg", "polar_angle_deg"};
    // tables of one revolution: >= 6 points, angles strictly increasing over < 360 deg
    const auto polar_table = [&](std::string_view value_key, const Rule& value_rule) {
      Series s = read_series(t, angle_names, "angle_deg", value_key);
      s.x.check_min_points(6);
      s.x.check_increasing();
      // a closed table that repeats its first point at +360 deg (common in measured data,
      // e.g. MBSim's contour.asc) is accepted: the repeat is dropped when it matches
      if (s.x.values.size() > 6 && std::abs(s.x.values.back() - s.x.values.front() - 360.0) <= 1e-9 &&
          std::abs(s.y.values.back() - s.y.values.front()) <= 1e-9 * std::max(1.0, std::abs(s.y.values.front()))) {
        s.x.values.pop_back();
        s.x.refs.pop_back();
        s.y.values.pop_back();
        s.y.refs.pop_back();
      }
      s.x.check_span_below_turn();
      s.y.check_each(value_rule);
      p.source_file = s.source_file;
      p.angle_deg = s.x.values;
      return s.y.values;
    };
    switch (p.form) {
      case ProfileForm::polar: p.radius_mm = polar_table("radius_mm", gt(0.0)); break;
      case ProfileForm::base_plus_lift:
        p.base_radius_mm = t.number("base_radius_mm", gt(0.0));
        // radius = base + lift > 0
        p.lift_mm = polar_table("lift_mm", gt(-p.base_radius_mm, "-base_radius_mm"));
        break;
      case ProfileForm::xy: {
        const Series s = read_series(t, {"x_mm"}, "x_mm", "y_mm");
        s.x.check_min_points(6);
        p.x_mm = s.x.values;
        p.y_mm = s.y.values;
        p.source_file = s.source_file;
        break;
      }
      case ProfileForm::circle: p.disc_radius_mm = t.number("disc_radius_mm", gt(0.0)); break;
      case ProfileForm::eccentric:
        p.disc_radius_mm = t.number("disc_radius_mm", gt(0.0));
        p.eccentricity_mm = t.number_or("eccentricity_mm", 0.0, ge(0.0) & lt(p.disc_radius_mm, "disc_radius_mm"));
        break;
    }
    p.where = t.where();
    return p;
  }

  MaterialSpec parse_material(const Table& t) {
    t.allow({"name", "youngs_modulus_GPa", "poisson_ratio", "density_kg_per_m3"});
    MaterialSpec m;
    m.name = t.string("name");
    m.youngs_modulus_GPa = t.number("youngs_modulus_GPa", gt(0.0));
    m.poisson_ratio = t.number("poisson_ratio", gt(0.0) & lt(0.5));
    m.density_kg_per_m3 = t.optional_number("density_kg_per_m3", gt(0.0));
    m.where = t.where();
    return m;
  }

  PinSpec parse_pin(const Table& t) {
    t.allow({"node", "point_mm"});
    PinSpec pin;
    pin.node = t.string("node");
    refer(Reference::To::node, t, "node");
    pin.point_mm = t.vec2("point_mm");
    pin.where = t.where();
    return pin;
  }

  SurfaceSpec parse_surface(const Table& t) {
    SurfaceSpec s;
    s.node = t.string("node");
    refer(Reference::To::node, t, "node");
    s.shape = t.choice<SurfaceShape>(
        "shape", {{"profile", SurfaceShape::profile}, {"circle", SurfaceShape::circle}, {"line", SurfaceShape::line}});
    const Keys common = {"node", "shape"};
    const Keys profile = {"profile", "origin_mm", "orientation_deg"};
    const Keys circle = {"center_mm", "radius_mm", "roller", "concave"};
    const Keys line = {"point_mm", "normal", "half_width_mm"};
    const Keys& own = s.shape == SurfaceShape::profile ? profile : s.shape == SurfaceShape::circle ? circle : line;
    t.allow(concat(common, own), concat(concat(profile, circle), line),
            std::string("shape = ") + quote(to_string(s.shape)));
    switch (s.shape) {
      case SurfaceShape::profile:
        s.profile = t.string("profile");
        refer(Reference::To::profile, t, "profile");
        s.origin_mm = t.optional_vec2("origin_mm").value_or(Vec2{0.0, 0.0});
        s.orientation_deg = t.number_or("orientation_deg", 0.0);
        break;
      case SurfaceShape::circle:
        s.origin_mm = t.vec2("center_mm");
        s.radius_mm = t.number("radius_mm", gt(0.0));
        s.roller = t.boolean_or("roller", false);
        s.concave = t.boolean_or("concave", false);
        break;
      case SurfaceShape::line:
        s.origin_mm = t.vec2("point_mm");
        s.normal = t.direction("normal");
        s.half_width_mm = t.optional_number("half_width_mm", gt(0.0));
        break;
    }
    s.where = t.where();
    return s;
  }

  ConnectionSpec parse_connection(const Table& t) {
    ConnectionSpec c;
    c.name = t.string("name");
    c.kind = t.choice<ConnectionKind>("type", {{"link", ConnectionKind::link},
                                               {"crank_slider", ConnectionKind::crank_slider},
                                               {"gear", ConnectionKind::gear},
                                               {"variable_gear", ConnectionKind::variable_gear},
                                               {"rack_pinion", ConnectionKind::rack_pinion},
                                               {"contact", ConnectionKind::contact}});
    const Keys common = {"name", "type"};
    const Keys link = {"a", "b", "length_mm"};
    const Keys gear = {"nodes", "ratio"};
    const Keys variable_gear = {"nodes", "ratio_table"};
    const Keys rack_pinion = {"nodes", "pitch_radius_mm"};
    const Keys contact = {"a", "b", "lash_mm", "materials", "width_mm", "friction_coefficient", "damping_N_s_per_mm"};
    const Keys* own = &link;
    switch (c.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider: own = &link; break;
      case ConnectionKind::gear: own = &gear; break;
      case ConnectionKind::variable_gear: own = &variable_gear; break;
      case ConnectionKind::rack_pinion: own = &rack_pinion; break;
      case ConnectionKind::contact: own = &contact; break;
    }
    t.allow(concat(common, *own), concat(concat(concat(link, gear), concat(variable_gear, rack_pinion)), contact),
            std::string("type = ") + quote(to_string(c.kind)));

    // gear-like connections name their two nodes: input side first
    const auto node_pair = [&] {
      std::array<SourceRef, 2> where;
      const auto nodes = t.string_pair("nodes", where);
      if (nodes[0] == nodes[1])
        throw InputError(where[1], "value " + quote(nodes[1]) + " must differ from nodes[0] (2 distinct nodes)");
      for (std::size_t i = 0; i < 2; ++i) refer(Reference::To::node, nodes[i], where[i]);
      c.node_a = nodes[0];
      c.node_b = nodes[1];
    };
    switch (c.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider:
        c.pin_a = parse_pin(t.table("a"));
        c.pin_b = parse_pin(t.table("b"));
        c.length_mm = t.optional_number("length_mm", gt(0.0));
        break;
      case ConnectionKind::gear:
        node_pair();
        c.ratio = t.number("ratio", nonzero());
        break;
      case ConnectionKind::variable_gear: {
        node_pair();
        const Table table = t.table("ratio_table");
        table.allow({"input_deg", "ratio"});
        const Column input = table.numbers("input_deg");
        const Column ratio = table.numbers("ratio");
        check_same_size(input, ratio);
        input.check_min_points(3);
        input.check_increasing();
        ratio.check_each(nonzero());
        c.ratio_input_deg = input.values;
        c.ratio_values = ratio.values;
        break;
      }
      case ConnectionKind::rack_pinion:
        node_pair();
        c.pitch_radius_mm = t.number("pitch_radius_mm", nonzero());
        break;
      case ConnectionKind::contact:
        c.surface_a = parse_surface(t.table("a"));
        c.surface_b = parse_surface(t.table("b"));
        c.lash_mm = t.number_or("lash_mm", 0.0, ge(0.0));
        if (t.has("materials")) {
          std::array<SourceRef, 2> where;
          const auto materials = t.string_pair("materials", where);
          for (std::size_t i = 0; i < 2; ++i) refer(Reference::To::material, materials[i], where[i]);
          c.material_a = materials[0];
          c.material_b = materials[1];
        }
        c.width_mm = t.optional_number("width_mm", gt(0.0));
        c.friction_coefficient = t.optional_number("friction_coefficient", ge(0.0));
        c.contact_damping_N_s_per_mm = t.optional_number("damping_N_s_per_mm", ge(0.0));
        break;
    }
    c.where = t.where();
    return c;
  }

  SpringSpec parse_spring(const Table& t) {
    SpringSpec s;
    s.name = t.string("name");
    s.kind = t.choice<SpringKind>("type", {{"compression", SpringKind::compression}, {"torsion", SpringKind::torsion}});
    const Keys common = {"name", "type", "node", "mass_kg", "surge_masses", "installed_length_mm",
                         "solid_length_mm", "wire_diameter_mm", "mean_coil_diameter_mm", "active_coils",
                         "shear_modulus_GPa"};
    const Keys compression = {"rate_N_per_mm", "preload_N", "table"};
    const Keys torsion = {"rate_Nmm_per_deg", "preload_Nmm"};
    const bool is_compression = s.kind == SpringKind::compression;
    t.allow(concat(common, is_compression ? compression : torsion), concat(compression, torsion),
            std::string("type = ") + quote(is_compression ? "compression" : "torsion"));

    s.node = t.string("node");
    refer(Reference::To::node, t, "node", is_compression ? NodeKind::translational : NodeKind::rotational,
          is_compression ? "a compression spring" : "a torsion spring");
    if (!is_compression) {
      s.rate_Nmm_per_deg = t.number("rate_Nmm_per_deg", gt(0.0));
      s.preload_Nmm = t.number_or("preload_Nmm", 0.0);
    } else if (t.has("table")) {
      // progressive law: exactly one of table / linear rate
      for (const std::string_view key : {"rate_N_per_mm", "preload_N"})
        if (t.has(key)) t.fail(key, "give either 'table' or 'rate_N_per_mm' and 'preload_N', not both");
      const Table table = t.table("table");
      table.allow({"displacement_mm", "force_N"});
      const Column displacement = table.numbers("displacement_mm");
      const Column force = table.numbers("force_N");
      check_same_size(displacement, force);
      displacement.check_min_points(3);
      displacement.check_increasing();
      force.check_increasing();
      s.table_displacement_mm = displacement.values;
      s.table_force_N = force.values;
    } else {
      if (!t.has("rate_N_per_mm")) t.fail("missing required key 'rate_N_per_mm' (or a 'table')");
      s.rate_N_per_mm = t.number("rate_N_per_mm", gt(0.0));
      s.preload_N = t.number_or("preload_N", 0.0, ge(0.0));
    }

    s.mass_kg = t.optional_number("mass_kg", gt(0.0));
    s.surge_masses = static_cast<int>(t.integer_or("surge_masses", 0, ge(0.0) & le(1000.0)));
    if (s.surge_masses > 0 && !s.mass_kg)
      t.fail("surge_masses", "value " + std::to_string(s.surge_masses) + " needs 'mass_kg' (the spring mass to distribute)");
    s.installed_length_mm = t.optional_number("installed_length_mm", gt(0.0));
    s.solid_length_mm = t.optional_number(
        "solid_length_mm", s.installed_length_mm ? gt(0.0) & lt(*s.installed_length_mm, "installed_length_mm") : gt(0.0));
    s.wire_diameter_mm = t.optional_number("wire_diameter_mm", gt(0.0));
    s.mean_coil_diameter_mm = t.optional_number("mean_coil_diameter_mm", gt(0.0));
    s.active_coils = t.optional_number("active_coils", gt(0.0));
    s.shear_modulus_GPa = t.optional_number("shear_modulus_GPa", gt(0.0));
    s.where = t.where();
    return s;
  }

  GasForceSpec parse_gas_force(const Table& t) {
    t.allow({"node", "file", "crank_angle_deg", "force_N"});
    GasForceSpec g;
    g.node = t.string("node");
    refer(Reference::To::node, t, "node", NodeKind::translational, "a gas force");
    const Series s = read_series(t, {"crank_deg", "crank_angle_deg"}, "crank_angle_deg", "force_N");
    s.x.check_min_points(2);
    s.x.check_increasing();
    g.crank_angle_deg = s.x.values;
    g.force_N = s.y.values;
    g.source_file = s.source_file;
    g.where = t.where();
    return g;
  }

  // every name used exists (and has the kind its user needs)
  void resolve(const DesignSpec& spec) const {
    for (const Reference& r : references_) {
      switch (r.to) {
        case Reference::To::node: {
          // "ground" is the implicit fixed frame: any connection may attach to it
          if (r.name == "ground" && !r.kind && !r.free_node) break;
          const NodeSpec* node = find_named(spec.nodes, r.name);
          if (!node) unknown(r, "node", names_of(spec.nodes) + "; or 'ground' for the fixed frame");
          if (r.kind && node->kind != *r.kind)
            throw InputError(r.where, "node " + quote(r.name) + " is " + to_string(node->kind) + "; " + r.role +
                                          " needs a " + to_string(*r.kind) + " node");
          if (r.free_node && node->control)
            throw InputError(r.where, "node " + quote(r.name) + " is set by control " + quote(*node->control) +
                                          " and cannot also be the driver");
          break;
        }
        case Reference::To::control:
          if (!find_named(spec.controls, r.name)) unknown(r, "control", names_of(spec.controls));
          break;
        case Reference::To::profile:
          if (!find_named(spec.profiles, r.name)) unknown(r, "profile", names_of(spec.profiles));
          break;
        case Reference::To::material:
          if (!find_named(spec.materials, r.name)) unknown(r, "material", names_of(spec.materials));
          break;
      }
    }
  }

  [[noreturn]] static void unknown(const Reference& r, const char* what, const std::string& names) {
    throw InputError(r.where, "unknown " + std::string(what) + " " + quote(r.name) + " (" + names + ")");
  }

  const Context& context_;
  std::vector<Reference> references_;
};

}  // namespace

DesignSpec parse_design(std::string_view text, const std::string& file_name, const std::string& directory) {
  const Context context{file_name, directory};
  toml::table document;
  try {
    document = toml::parse(text, std::string_view(file_name));
  } catch (const toml::parse_error& e) {
    throw InputError(context.ref(e.source(), ""), "TOML syntax error: " + std::string(e.description()));
  }
  return Parser(context).run(document);
}

DesignSpec load_design(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(SourceRef{path, 0, 0, ""}, "cannot open design file");
  std::ostringstream text;
  text << in.rdbuf();
  std::string directory = fs::path(path).parent_path().string();
  if (directory.empty()) directory = ".";
  return parse_design(text.str(), path, directory);
}

}  // namespace camopt::io
