#include "camopt/io/design_rewrite.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "camopt/core/error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using camopt::io::design_with_profile_file;
using camopt::test::TempDir;

namespace {

// the rewritten text without its first line (the header comment naming the source)
std::string body_of(const std::string& text) { return text.substr(text.find('\n') + 1); }

}  // namespace

TEST_CASE("design_with_profile_file edits the profile's lines and keeps every comment and number as written",
          "[io][design_rewrite]") {
  const TempDir dir;
  fs::create_directories(dir / "d");
  const std::string design = dir.write("d/in.toml",
                                       "# a design, described\n"
                                       "schema = 1\n"
                                       "[[profile]]\n"
                                       "name = \"lobe\"   # the cam\n"
                                       "form = \"base_plus_lift\"\n"
                                       "base_radius_mm = 18.0\n"
                                       "angle_deg = [0, 90,\n"
                                       "             180, 270]  # four points\n"
                                       "lift_mm = [0, 1, 2, 1]\n"
                                       "\n"
                                       "# the other profile\n"
                                       "[[profile]]\n"
                                       "name = \"other\"\n"
                                       "form = \"polar\"\n"
                                       "file = \"tables/other.csv\"   # measured\n"
                                       "\n"
                                       "[[connection]]\n"
                                       "b = { node = \"finger\", center_mm = [17.6, -0.1], radius_mm = 8.50 }\n");
  const std::string text = design_with_profile_file(design, "lobe", "profile.csv", dir.file("out"));
  CHECK(text.rfind("# written by camopt from " + design + ": profile 'lobe' reads the polar table profile.csv", 0) ==
        0);
  // the other profile's table is named from the output folder
  CHECK(body_of(text) == "# a design, described\n"
                         "schema = 1\n"
                         "[[profile]]\n"
                         "name = \"lobe\"   # the cam\n"
                         "form = \"polar\"\n"
                         "file = \"profile.csv\"\n"
                         "\n"
                         "# the other profile\n"
                         "[[profile]]\n"
                         "name = \"other\"\n"
                         "form = \"polar\"\n"
                         "file = \"../d/tables/other.csv\"   # measured\n"
                         "\n"
                         "[[connection]]\n"
                         "b = { node = \"finger\", center_mm = [17.6, -0.1], radius_mm = 8.50 }\n");
}

TEST_CASE("design_with_profile_file rewrites an inline profile table in place", "[io][design_rewrite]") {
  const TempDir dir;
  const std::string design =
      dir.write("in.toml",
                "profile = [ { name = \"lobe\", form = \"polar\", angle_deg = [0, 120, 240], radius_mm = [1, 2, 3] },\n"
                "            { name = \"disc\", form = \"circle\", disc_radius_mm = 12.5 } ]  # two\n");
  const std::string text = design_with_profile_file(design, "lobe", "profile.csv", dir.path().string());
  CHECK(body_of(text) ==
        "profile = [ { name = \"lobe\", form = \"polar\", file = \"profile.csv\" },\n"
        "            { name = \"disc\", form = \"circle\", disc_radius_mm = 12.5 } ]  # two\n");
}

TEST_CASE("design_with_profile_file names a missing profile", "[io][design_rewrite]") {
  const TempDir dir;
  const std::string design = dir.write("in.toml", "[[profile]]\nname = \"lobe\"\nform = \"circle\"\n");
  REQUIRE_THROWS_AS(design_with_profile_file(design, "nose", "profile.csv", dir.path().string()), camopt::InputError);
  REQUIRE_THROWS_WITH(design_with_profile_file(design, "nose", "profile.csv", dir.path().string()),
                      Catch::Contains("no [[profile]] named 'nose'"));
}
