// the fuzz targets under the normal build: every seed (tests/fuzz/seeds.txt) must be
// accepted, and every input a fuzzer ever crashed on (tests/fuzz/regressions/<target>/)
// must now be accepted or rejected with an InputError (fuzz_entry.hpp aborts otherwise).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_entry.hpp"

namespace fs = std::filesystem;

namespace {

using Entry = bool (*)(std::string_view);
const std::map<std::string, Entry> entries = {{"target_lift_csv", camopt::fuzz::target_lift_csv},
                                              {"design_toml", camopt::fuzz::design_toml},
                                              {"constraint_toml", camopt::fuzz::constraint_toml}};

const fs::path source_dir = CAMOPT_SOURCE_DIR;

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<fs::path> files_in(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& file : fs::directory_iterator(dir))
      if (file.is_regular_file() && (extension.empty() || file.path().extension() == extension))
        files.push_back(file.path());
  return files;
}

}  // namespace

TEST_CASE("every fuzz seed is accepted", "[fuzz]") {
  std::ifstream list(source_dir / "tests/fuzz/seeds.txt");
  REQUIRE(list);
  std::map<std::string, int> seeds;
  for (std::string line; std::getline(list, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string target, dir, extension;
    fields >> target >> dir >> extension;
    REQUIRE(entries.count(target) == 1);
    for (const fs::path& file : files_in(source_dir / dir, extension)) {
      INFO(target << " " << file.string());
      CHECK(entries.at(target)(read_bytes(file)));
      ++seeds[target];
    }
  }
  CHECK(seeds["design_toml"] >= 11);
  CHECK(seeds["constraint_toml"] >= 2);
  CHECK(seeds["target_lift_csv"] >= 8);
}

TEST_CASE("inputs the fuzzers crashed on are handled", "[fuzz]") {
  int replayed = 0;
  for (const auto& [target, entry] : entries)
    for (const fs::path& file : files_in(source_dir / "tests/fuzz/regressions" / target, "")) {
      INFO(target << " " << file.string());
      (void)entry(read_bytes(file));  // aborts on a bug
      ++replayed;
    }
  CHECK(replayed >= 5);  // the hand-written edge cases: overflow, one row, near-duplicate angles, deep nesting, tiny radius
}
