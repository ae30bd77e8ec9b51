#include "camopt/io/design_rewrite.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <toml++/toml.h>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/io/input_file.hpp"
#include "toml_edit.hpp"

namespace camopt::io {

namespace {
namespace fs = std::filesystem;
using toml_detail::Offsets;
using toml_detail::quoted;

// the keys of a profile table that hold its data: replaced by form = "polar" and file
const char* const kProfileDataKeys[] = {"angle_deg",      "radius_mm",      "lift_mm", "x_mm", "y_mm",
                                        "base_radius_mm", "disc_radius_mm", "eccentricity_mm", "file", "form"};

// one replacement of the bytes [begin, end) of the original text
struct Edit {
  std::size_t begin = 0, end = 0;
  std::string text;
};

// the new text of the named profile: form and file, the data keys dropped
void edit_profile(const toml::table& t, const std::string& profile_file, std::string_view text, const Offsets& at,
                  std::vector<Edit>& edits) {
  const auto is_data = [](std::string_view key) {
    return std::any_of(std::begin(kProfileDataKeys), std::end(kProfileDataKeys),
                       [&](const char* k) { return key == k; });
  };
  const std::string new_lines = "form = \"polar\"\nfile = " + quoted(profile_file) + "\n";
  if (t.is_inline()) {
    // { name = ..., <kept keys as written, in their order>, form = "polar", file = ... }
    std::vector<std::pair<std::size_t, std::size_t>> kept;
    for (const auto& [key, value] : t)
      if (!is_data(key.str())) kept.emplace_back(at.at(key.source().begin), at.at(value.source().end));
    std::sort(kept.begin(), kept.end());
    std::string inline_text = "{ ";
    for (const auto& [begin, end] : kept) inline_text += std::string(text.substr(begin, end - begin)) + ", ";
    inline_text += "form = \"polar\", file = " + quoted(profile_file) + " }";
    edits.push_back({at.at(t.source().begin), at.at(t.source().end), inline_text});
    return;
  }
  // a [[profile]] table: each data key's whole lines go; form and file follow the name
  for (const auto& [key, value] : t) {
    if (key.str() == "name") {
      const std::size_t next_line = at.line_start(value.source().end.line + 1);
      edits.push_back({next_line, next_line, new_lines});
    } else if (is_data(key.str())) {
      edits.push_back({at.line_start(key.source().begin.line), at.line_start(value.source().end.line + 1), ""});
    }
  }
}

// every relative `file = ...` of the other tables, made relative to the output folder
void edit_file_references(const toml::node& node, const toml::table* skip, const fs::path& design_dir,
                          const fs::path& out_dir, const Offsets& at, std::vector<Edit>& edits) {
  if (const auto* array = node.as_array()) {
    for (const auto& element : *array) edit_file_references(element, skip, design_dir, out_dir, at, edits);
    return;
  }
  const auto* table = node.as_table();
  if (table == nullptr || table == skip) return;
  for (const auto& [key, value] : *table) {
    const auto* file = value.as_string();
    if (key.str() != "file" || file == nullptr) {
      edit_file_references(value, skip, design_dir, out_dir, at, edits);
      continue;
    }
    const fs::path path(file->get());
    if (path.is_absolute()) continue;
    const fs::path relative = fs::weakly_canonical(design_dir / path).lexically_relative(out_dir);
    edits.push_back({at.at(value.source().begin), at.at(value.source().end), quoted(relative.generic_string())});
  }
}

}  // namespace

std::string design_with_profile_file(const std::string& design_path, const std::string& profile_name,
                                     const std::string& profile_file, const std::string& out_dir,
                                     const std::vector<Override>& overrides) {
  std::string text = read_input_file(design_path, "design file");
  // the overridden values edited into the text: the design written is the design that ran
  std::string overridden;
  if (!overrides.empty()) {
    toml_detail::EditableToml edited(std::move(text), design_path, "--set");
    for (const Override& o : overrides) {
      edited.set(o);
      overridden += "\n#   " + o.given;
    }
    text = edited.text();
  }
  toml::table root;
  try {
    root = toml::parse(text, design_path);
  } catch (const toml::parse_error& e) {
    throw InputError(design_path + ": " + std::string(e.description()));
  }
  const Offsets at(text);

  // the profile to replace
  const toml::table* profile = nullptr;
  if (const auto* profiles = root.get_as<toml::array>("profile"))
    for (const auto& node : *profiles)
      if (const auto* t = node.as_table(); t != nullptr && t->get_as<std::string>("name") &&
                                           t->get_as<std::string>("name")->get() == profile_name)
        profile = t;
  if (profile == nullptr) throw InputError(design_path + ": no [[profile]] named '" + profile_name + "'");

  // the edits, applied from the end of the text so earlier offsets stay valid
  std::vector<Edit> edits;
  edit_profile(*profile, profile_file, text, at, edits);
  const fs::path design_dir = fs::absolute(fs::path(design_path)).parent_path();
  edit_file_references(root, profile, design_dir, fs::weakly_canonical(fs::absolute(out_dir)), at, edits);
  // at one offset a deletion goes before an insertion, which then lands where the deletion began
  std::sort(edits.begin(), edits.end(),
            [](const Edit& a, const Edit& b) { return a.begin != b.begin ? a.begin > b.begin : a.end > b.end; });
  for (const Edit& e : edits) text.replace(e.begin, e.end - e.begin, e.text);

  return "# written by camopt from " + fs::absolute(fs::path(design_path)).lexically_normal().string() +
         ": profile '" + profile_name + "' reads the polar table " + profile_file + " beside this file" +
         (overridden.empty() ? "" : ", with the overrides" + overridden) + "\n" + text;
}

}  // namespace camopt::io
