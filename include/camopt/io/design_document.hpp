#pragma once
// a design file as an editable document: any value is addressed by a key path and can be
// read or changed before the file is parsed into a DesignSpec (docs/design-format.md, "Key
// paths"). `camopt <command> --set key.path=value` and the Python API use it.
//
// key paths: tables and keys joined by dots (`design.name`, `driver.step_deg`); an array
// of tables by the `name` of an entry (`node.finger.mass_kg`,
// `connection.cam_roller.b.radius_mm`, `hla.<name>.<key>`); an array element by index
// (`node.finger.pivot_mm[0]`). Values are TOML text: 8.5, "polar", true, [-22, -28]; a bare
// word (letters, digits, _ and -) is taken as a string.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "camopt/core/design_spec.hpp"

namespace camopt::io {

// one override: `key=value` as given on the command line
struct Override {
  std::string key;    // the key path
  std::string value;  // TOML text of the new value
  std::string given;  // as given, with its option: "--set node.finger.mass_kg=0.05"
};

// "key.path=value" -> Override; InputError naming `option` without a '=' or a key
Override parse_override(std::string_view argument, std::string_view option = "--set");

namespace toml_detail {
class EditableToml;
}

class DesignDocument {
 public:
  static DesignDocument load(const std::string& path);
  // `directory` resolves relative `file = ...` references
  static DesignDocument from_text(std::string text, const std::string& file_name, const std::string& directory);
  DesignDocument(DesignDocument&&) noexcept;
  DesignDocument& operator=(DesignDocument&&) noexcept;
  ~DesignDocument();

  // the value at `key_path` as TOML text; InputError when the path leads nowhere
  std::string get(std::string_view key_path) const;
  // the number at `key_path`; InputError when it is not a number
  double get_number(std::string_view key_path) const;

  // the value at `key_path` replaced (or its key added to the table); InputError naming the
  // override for an unknown key, a name no table has, an index out of range or a value of
  // another type than the design's
  void set(std::string_view key_path, std::string_view value_text);
  void set(const Override& o);
  const std::vector<Override>& overrides() const;

  // the design parsed (io::parse_design's checks; contacts that touch at rest solved): a
  // value an override gave is reported at the override, every other at its line
  DesignSpec spec() const;
  // the file text with the overrides edited in (comments and layout kept)
  const std::string& text() const;
  const std::string& file() const { return file_; }

 private:
  DesignDocument(std::unique_ptr<toml_detail::EditableToml> toml, std::string file, std::string directory);
  std::unique_ptr<toml_detail::EditableToml> toml_;
  std::string file_, directory_;
};

// the design at `path` with the overrides applied, parsed
DesignSpec load_design(const std::string& path, const std::vector<Override>& overrides);

}  // namespace camopt::io
