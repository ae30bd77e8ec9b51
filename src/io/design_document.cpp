// the design document: key paths read and set on the file's text, then parsed (design_document.hpp)
#include "camopt/io/design_document.hpp"

#include <utility>

#include "camopt/io/design_file.hpp"

#include "design_parser.hpp"
#include "toml_edit.hpp"

namespace camopt::io {

using toml_detail::EditableToml;

DesignDocument::DesignDocument(std::unique_ptr<EditableToml> toml, std::string file, std::string directory)
    : toml_(std::move(toml)), file_(std::move(file)), directory_(std::move(directory)) {}
DesignDocument::DesignDocument(DesignDocument&&) noexcept = default;
DesignDocument& DesignDocument::operator=(DesignDocument&&) noexcept = default;
DesignDocument::~DesignDocument() = default;

DesignDocument DesignDocument::load(const std::string& path) {
  std::string directory;
  std::string text = toml_detail::read_text_file(path, "design file", directory);
  return from_text(std::move(text), path, directory);
}

DesignDocument DesignDocument::from_text(std::string text, const std::string& file_name, const std::string& directory) {
  return DesignDocument(std::make_unique<EditableToml>(std::move(text), file_name, "--set"), file_name, directory);
}

std::string DesignDocument::get(std::string_view key_path) const {
  const std::string label = "key path " + std::string(key_path);
  const toml_detail::KeyTarget target = toml_->resolve(key_path, label);
  if (target.node == nullptr) throw InputError(label + ": no key '" + target.key + "' in the design");
  return toml_->value_text(*target.node);
}

double DesignDocument::get_number(std::string_view key_path) const {
  const std::string label = "key path " + std::string(key_path);
  const toml_detail::KeyTarget target = toml_->resolve(key_path, label);
  if (target.node == nullptr) throw InputError(label + ": no key '" + target.key + "' in the design");
  if (!target.node->is_number())
    throw InputError(label + ": expected a number, got " + toml_detail::describe(*target.node));
  return *target.node->value<double>();
}

void DesignDocument::set(std::string_view key_path, std::string_view value_text) {
  set(Override{std::string(key_path), std::string(value_text),
               "--set " + std::string(key_path) + "=" + std::string(value_text)});
}

void DesignDocument::set(const Override& o) { toml_->set(o); }

const std::vector<Override>& DesignDocument::overrides() const { return toml_->overrides(); }

const std::string& DesignDocument::text() const { return toml_->text(); }

DesignSpec DesignDocument::spec() const {
  const toml_detail::Context context{file_, directory_, toml_->spans()};
  return parse_design_document(toml_->document(), context);
}

DesignSpec load_design(const std::string& path, const std::vector<Override>& overrides) {
  if (overrides.empty()) return load_design(path);
  DesignDocument doc = DesignDocument::load(path);
  for (const Override& o : overrides) doc.set(o);
  return doc.spec();
}

}  // namespace camopt::io
