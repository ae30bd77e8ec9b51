// key paths into a TOML document, and the text edits of an override (toml_edit.hpp)
#include "toml_edit.hpp"

#include <cctype>
#include <cstdio>
#include <utility>

namespace camopt::io {

Override parse_override(std::string_view argument, std::string_view option) {
  const std::string given = std::string(option) + " " + std::string(argument);
  const std::size_t eq = argument.find('=');
  const auto trim = [](std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
  };
  if (eq == std::string_view::npos || trim(argument.substr(0, eq)).empty() || trim(argument.substr(eq + 1)).empty())
    throw InputError(given + ": expected KEY=VALUE, a key path and a TOML value (e.g. " + std::string(option) +
                     " connection.cam_roller.b.radius_mm=9)");
  return {trim(argument.substr(0, eq)), trim(argument.substr(eq + 1)), given};
}

namespace toml_detail {

namespace {

// one step of a key path: a key and the array indices after it (`pivot_mm[0]`)
struct Segment {
  std::string key;
  std::vector<std::size_t> indices;
};

std::vector<Segment> split_path(std::string_view path, const std::string& label) {
  std::vector<Segment> out;
  const auto bad = [&](const std::string& why) -> void {
    throw InputError(label + ": key path " + quote(path) + " " + why);
  };
  for (std::string_view rest = path;;) {
    const std::size_t dot = rest.find('.');
    std::string_view part = rest.substr(0, dot);
    Segment seg;
    const std::size_t bracket = part.find('[');
    seg.key = std::string(part.substr(0, bracket));
    if (seg.key.empty()) bad("has an empty key (keys are joined by single dots)");
    for (std::string_view idx = bracket == std::string_view::npos ? std::string_view{} : part.substr(bracket);
         !idx.empty();) {
      const std::size_t close = idx.find(']');
      std::size_t value = 0;
      const char* first = idx.data() + 1;
      const char* last = idx.data() + (close == std::string_view::npos ? idx.size() : close);
      const auto [ptr, ec] = std::from_chars(first, last, value);
      if (idx.front() != '[' || close == std::string_view::npos || ec != std::errc() || ptr != last || first == last)
        bad("has a malformed index (write key[0])");
      seg.indices.push_back(value);
      idx.remove_prefix(close + 1);
    }
    out.push_back(std::move(seg));
    if (dot == std::string_view::npos) break;
    rest.remove_prefix(dot + 1);
  }
  return out;
}

// an array whose entries are all tables: [[node]], [[connection]], ...
bool is_array_of_tables(const toml::node& node) {
  const auto* array = node.as_array();
  return array != nullptr && !array->empty() && array->is_array_of_tables();
}

std::string keys_of(const toml::table& table) {
  std::string out;
  for (auto&& [key, value] : table) out += (out.empty() ? "" : ", ") + std::string(key.str());
  return out.empty() ? "none" : out;
}

// the kind of a value for the type check of an override: number, string, boolean, array, table
std::string_view kind_of(const toml::node& node) {
  if (node.is_number()) return "a number";
  if (node.is_string()) return "a string";
  if (node.is_boolean()) return "a boolean";
  if (node.is_array()) return "an array";
  if (node.is_table()) return "a table";
  return "a date or time";
}

// the override's value as a TOML node: its text parsed, or a bare word taken as a string
std::pair<toml::table, std::string> parse_value(const Override& o) {
  try {
    toml::table parsed = toml::parse("v = " + o.value);
    if (parsed.size() == 1) return {std::move(parsed), o.value};
  } catch (const toml::parse_error&) {
  }
  const bool bare = std::all_of(o.value.begin(), o.value.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!bare)
    throw InputError(o.given + ": value " + quote(o.value) +
                     " is not a TOML value (a number, a \"string\", true or false, or an array [a, b])");
  const std::string text = quoted(o.value);
  return {toml::parse("v = " + text), text};
}

}  // namespace

Offsets::Offsets(std::string_view text) : text_(text) {
  starts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts_.push_back(i + 1);
}

std::size_t Offsets::at(const toml::source_position& p) const {
  std::size_t offset = line_start(p.line);
  for (toml::source_index column = 1; column < p.column && offset < text_.size(); ++column) {
    ++offset;
    while (offset < text_.size() && (static_cast<unsigned char>(text_[offset]) & 0xC0) == 0x80) ++offset;
  }
  return offset;
}

std::size_t Offsets::line_start(toml::source_index line) const {
  return line >= 1 && line <= starts_.size() ? starts_[line - 1] : text_.size();
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04X", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += escape;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

EditableToml::EditableToml(std::string text, std::string file, std::string option)
    : text_(std::move(text)), file_(std::move(file)), option_(std::move(option)) {
  const Context context{file_, "", {}};
  document_ = parse_document(text_, context);
}

KeyTarget EditableToml::resolve(std::string_view path, const std::string& label) const {
  const std::vector<Segment> segments = split_path(path, label);
  const toml::table* table = &document_;
  std::string at;  // the path walked so far, for messages
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& seg = segments[i];
    const bool last = i + 1 == segments.size();
    const toml::node* node = table->get(seg.key);
    const std::string here = at.empty() ? seg.key : at + "." + seg.key;
    if (node == nullptr) {
      if (last && seg.indices.empty()) return {table, seg.key, nullptr};
      throw InputError(label + ": no key '" + seg.key + "' in " + (at.empty() ? "the file" : at) + " (keys: " +
                       keys_of(*table) + ")");
    }
    std::string indexed_path = here;
    for (const std::size_t index : seg.indices) {
      const auto* array = node->as_array();
      if (array == nullptr) throw InputError(label + ": " + indexed_path + " is " + std::string(kind_of(*node)) + ", not an array");
      if (index >= array->size())
        throw InputError(label + ": index " + std::to_string(index) + " is out of range (" + indexed_path + " has " +
                         std::to_string(array->size()) + " elements)");
      node = &(*array)[index];
      indexed_path += "[" + std::to_string(index) + "]";
    }
    if (last) return {seg.indices.empty() ? table : nullptr, seg.key, node};
    if (seg.indices.empty() && is_array_of_tables(*node)) {
      // an entry of [[key]] by its name
      const std::string& name = segments[++i].key;
      const toml::table* found = nullptr;
      std::string names;
      for (const toml::node& entry : *node->as_array()) {
        const auto* entry_name = entry.as_table()->get_as<std::string>("name");
        if (entry_name == nullptr) continue;
        names += (names.empty() ? "" : ", ") + entry_name->get();
        if (entry_name->get() == name) found = entry.as_table();
      }
      if (found == nullptr)
        throw InputError(label + ": no [[" + seg.key + "]] named " + quote(name) + " (" + names + ")");
      if (i + 1 == segments.size() || !segments[i].indices.empty())
        throw InputError(label + ": " + here + "." + name + " is a table; name a key inside it (e.g. " + here + "." +
                         name + ".name)");
      table = found;
      at = here + "." + name;
      continue;
    }
    if (!node->is_table())
      throw InputError(label + ": " + indexed_path + " is " + std::string(kind_of(*node)) + ", not a table");
    table = node->as_table();
    at = indexed_path;
  }
  return {};
}

std::string EditableToml::value_text(const toml::node& node) const {
  const Offsets at(text_);
  const std::size_t begin = at.at(node.source().begin), end = at.at(node.source().end);
  return text_.substr(begin, end - begin);
}

void EditableToml::set(const Override& o) {
  const KeyTarget target = resolve(o.key, o.given);
  const auto [parsed, value] = parse_value(o);
  const toml::node& given = *parsed.get("v");
  const Offsets at(text_);
  if (target.node != nullptr) {
    // the type of the design's value is kept: a number stays a number
    if (kind_of(*target.node) != kind_of(given))
      throw InputError(o.given + ": " + o.key + " is " + std::string(kind_of(*target.node)) + " in the file (" +
                       value_text(*target.node) + "), got " + describe(given));
    if (const auto* t = target.node->as_table(); t != nullptr && !t->is_inline())
      throw InputError(o.given + ": " + o.key + " is a table; set the keys inside it");
    const std::size_t begin = at.at(target.node->source().begin), end = at.at(target.node->source().end);
    text_.replace(begin, end - begin, value);
  } else if (target.table->is_inline()) {
    // before the closing brace of { ... }
    std::size_t close = at.at(target.table->source().end);
    while (close > 0 && text_[close - 1] != '}') --close;
    std::size_t before = close - 1;
    while (before > 0 && std::isspace(static_cast<unsigned char>(text_[before - 1]))) --before;
    const bool empty = text_[before - 1] == '{';
    text_.insert(before, std::string(empty ? " " : ", ") + target.key + " = " + value + (empty ? " " : ""));
  } else {
    // a line after the table's header (the document itself: the first line)
    const std::size_t line = target.table == &document_ ? 0 : at.line_start(target.table->source().begin.line + 1);
    text_.insert(line, target.key + " = " + value + "\n");
  }
  reparse(o.given);
  overrides_.push_back(o);
}

void EditableToml::reparse(const std::string& label) {
  try {
    document_ = toml::parse(text_, std::string_view(file_));
  } catch (const toml::parse_error& e) {
    throw InputError(label + ": the edited file is not TOML: " + std::string(e.description()));
  }
}

std::vector<OverrideSpan> EditableToml::spans() const {
  std::vector<OverrideSpan> out;
  for (const Override& o : overrides_) {
    const KeyTarget target = resolve(o.key, o.given);
    if (target.node == nullptr) continue;
    OverrideSpan span{target.node->source().begin, target.node->source().end, o.given};
    if (target.table != nullptr)
      for (auto&& [key, value] : *target.table)
        if (key.str() == target.key) span.begin = key.source().begin;
    out.push_back(std::move(span));
  }
  return out;
}

}  // namespace toml_detail
}  // namespace camopt::io
