#include "camopt/io/design_rewrite.hpp"

#include <filesystem>
#include <sstream>
#include <toml++/toml.h>

#include "camopt/core/error.hpp"

namespace camopt::io {

namespace {
namespace fs = std::filesystem;

void absolutise(toml::table& t, const fs::path& base) {
  if (auto* f = t.get_as<std::string>("file")) {
    const fs::path p(f->get());
    if (p.is_relative()) *f = fs::weakly_canonical(base / p).string();
  }
}
}  // namespace

std::string design_with_profile_file(const std::string& design_path, const std::string& profile_name,
                                     const std::string& profile_file) {
  toml::table root;
  try {
    root = toml::parse_file(design_path);
  } catch (const toml::parse_error& e) {
    throw InputError(design_path + ": " + std::string(e.description()));
  }
  const fs::path base = fs::absolute(fs::path(design_path)).parent_path();
  bool found = false;
  if (auto* profiles = root.get_as<toml::array>("profile")) {
    for (auto& node : *profiles) {
      auto* t = node.as_table();
      if (!t) continue;
      const auto* name = t->get_as<std::string>("name");
      if (name && name->get() == profile_name) {
        for (const char* key : {"angle_deg", "radius_mm", "lift_mm", "x_mm", "y_mm", "base_radius_mm",
                                "disc_radius_mm", "eccentricity_mm", "file", "form"})
          t->erase(key);
        t->insert_or_assign("form", "polar");
        t->insert_or_assign("file", profile_file);
        found = true;
      } else {
        absolutise(*t, base);
      }
    }
  }
  if (auto* gas = root.get_as<toml::array>("gas_force"))
    for (auto& node : *gas)
      if (auto* t = node.as_table()) absolutise(*t, base);
  if (!found) throw InputError(design_path + ": no [[profile]] named '" + profile_name + "'");
  std::ostringstream os;
  os << "# written by camopt synthesize from " << fs::absolute(fs::path(design_path)).string() << "\n"
     << "# profile '" << profile_name << "' now reads the synthesized polar table " << profile_file << "\n\n"
     << toml::toml_formatter(root) << "\n";
  return os.str();
}

}  // namespace camopt::io
