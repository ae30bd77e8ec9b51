#include "camopt/io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using camopt::InputError;
using camopt::io::OutputTransaction;
using camopt::io::write_text_atomic;
using Catch::Contains;

using camopt::test::TempDir;

namespace {


// names of the entries of a directory, sorted
std::vector<std::string> list_directory(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("write_text_atomic writes the content and leaves no temp file", "[io][atomic]") {
  const TempDir dir;
  const std::string path = dir.file("lift.csv");
  write_text_atomic(path, "cam_deg,lift_mm\n0,0\n");
  CHECK(read_text(path) == "cam_deg,lift_mm\n0,0\n");
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"lift.csv"});
}

TEST_CASE("write_text_atomic replaces an existing file", "[io][atomic]") {
  const TempDir dir;
  const std::string path = dir.file("out.txt");
  write_text_atomic(path, "first version, longer than the second\n");
  write_text_atomic(path, "second\n");
  CHECK(read_text(path) == "second\n");
  write_text_atomic(path, "");
  CHECK(read_text(path).empty());
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"out.txt"});
}

TEST_CASE("write_text_atomic gives the file the usual permissions, not 0600", "[io][atomic]") {
  const TempDir dir;
  const std::string path = dir.file("out.txt");
  write_text_atomic(path, "x");
  const mode_t mask = ::umask(0);
  ::umask(mask);
  struct stat info {};
  REQUIRE(::stat(path.c_str(), &info) == 0);
  CHECK((info.st_mode & 0777) == (0666 & ~mask));
}

TEST_CASE("write_text_atomic into a missing directory names the path and the directory", "[io][atomic]") {
  const TempDir dir;
  const std::string missing = dir.file("no_such_dir");
  const std::string path = missing + "/lift.csv";
  REQUIRE_THROWS_AS(write_text_atomic(path, "x"), InputError);
  REQUIRE_THROWS_WITH(write_text_atomic(path, "x"),
                      Contains("cannot write '" + path + "'") &&
                          Contains("directory '" + missing + "' does not exist"));
  CHECK(fs::is_empty(dir.path()));
}

TEST_CASE("write_text_atomic whose rename fails removes its temp file", "[io][atomic]") {
  const TempDir dir;
  // a non-empty directory cannot be replaced by a file
  const std::string path = dir.file("occupied");
  fs::create_directories(fs::path(path) / "inside");
  REQUIRE_THROWS_WITH(write_text_atomic(path, "x"), Contains("cannot write '" + path + "'"));
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"occupied"});
}

TEST_CASE("OutputTransaction commit writes every staged file and no temp file", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("run/out");
  {
    OutputTransaction transaction(out);
    CHECK(transaction.directory() == out);
    CHECK(fs::is_directory(out));
    transaction.stage("lift.csv", "cam_deg,lift_mm\n0,0\n");
    transaction.stage("summary.json", "{}\n");
    // staged content is on disk already, under temp names only
    const auto during = list_directory(out);
    REQUIRE(during.size() == 2);
    for (const auto& name : during) CHECK_THAT(name, Contains(".tmp-"));
    transaction.commit();
  }
  CHECK(list_directory(out) == std::vector<std::string>{"lift.csv", "summary.json"});
  CHECK(read_text(out + "/lift.csv") == "cam_deg,lift_mm\n0,0\n");
  CHECK(read_text(out + "/summary.json") == "{}\n");
}

TEST_CASE("OutputTransaction without commit leaves an empty directory", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  {
    OutputTransaction transaction(out);
    transaction.stage("lift.csv", "cam_deg,lift_mm\n0,0\n");
    transaction.stage("summary.json", "{}\n");
    CHECK(list_directory(out).size() == 2);
  }
  CHECK(fs::is_directory(out));
  CHECK(fs::is_empty(out));
}

TEST_CASE("OutputTransaction abandoned by an exception keeps the old files", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  fs::create_directories(out);
  write_text_atomic(out + "/lift.csv", "old\n");
  try {
    OutputTransaction transaction(out);
    transaction.stage("lift.csv", "new\n");
    throw std::runtime_error("kernel failed");
  } catch (const std::runtime_error&) {
  }
  CHECK(list_directory(out) == std::vector<std::string>{"lift.csv"});
  CHECK(read_text(out + "/lift.csv") == "old\n");
}

TEST_CASE("OutputTransaction on a path that is a file names it", "[io][atomic]") {
  const TempDir dir;
  const std::string path = dir.file("plain_file");
  write_text_atomic(path, "x");
  REQUIRE_THROWS_AS(OutputTransaction(path), InputError);
  REQUIRE_THROWS_WITH(OutputTransaction(path), Contains("cannot create output directory '" + path + "'"));
}

TEST_CASE("OutputTransaction stage into a missing subdirectory throws and leaves nothing", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  OutputTransaction transaction(out);
  REQUIRE_THROWS_WITH(transaction.stage("sub/lift.csv", "x"),
                      Contains("lift.csv") && Contains("directory '" + out + "/sub' does not exist"));
  transaction.commit();
  CHECK(fs::is_empty(out));
}
