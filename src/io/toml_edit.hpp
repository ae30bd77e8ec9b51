#pragma once
// a TOML text edited in place by key path (`--set key.path=value`): the value's own text is
// replaced (or the key inserted into its table), every other byte stays as written, and the
// document is parsed again so each later reader sees the file's own locations. Shared by
// the design document, the constraint sets and the design rewrite. internal to camopt_io.
#include <toml++/toml.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "camopt/io/design_document.hpp"
#include "toml_table.hpp"

namespace camopt::io::toml_detail {

// byte offsets in the text of toml++ source positions (1-based lines, columns in code points)
class Offsets {
 public:
  explicit Offsets(std::string_view text);
  std::size_t at(const toml::source_position& p) const;
  // the start of line `line` (1-based); the text's end past the last line
  std::size_t line_start(toml::source_index line) const;

 private:
  std::string_view text_;
  std::vector<std::size_t> starts_;
};

// a TOML basic string
std::string quoted(const std::string& s);

// where a key path leads in a document: the table holding its last key, and the value (null
// when the key is absent from that table: a set inserts it)
struct KeyTarget {
  const toml::table* table = nullptr;
  std::string key;
  const toml::node* node = nullptr;
};

class EditableToml {
 public:
  // `option` names the overrides in messages ("--set", "--set-constraint")
  EditableToml(std::string text, std::string file, std::string option);

  const std::string& text() const { return text_; }
  const toml::table& document() const { return document_; }
  const std::vector<Override>& overrides() const { return overrides_; }

  // the value at `path`; InputError naming `label` (the override as given) when the path
  // leads nowhere (an unknown key, a name no table has, an index out of range)
  KeyTarget resolve(std::string_view path, const std::string& label) const;
  // the value's TOML text as written
  std::string value_text(const toml::node& node) const;
  // the value at `o.key` replaced by `o.value` (TOML text, or a bare word taken as a string)
  void set(const Override& o);
  // where each override's value (and inserted key) now is, for the parser's context
  std::vector<OverrideSpan> spans() const;

 private:
  void reparse(const std::string& label);

  std::string text_, file_, option_;
  toml::table document_;
  std::vector<Override> overrides_;
};

}  // namespace camopt::io::toml_detail
