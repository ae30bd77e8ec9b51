#include "camopt/io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "camopt/core/error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using camopt::InputError;
using camopt::io::OutputTransaction;
using camopt::io::Durability;
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

TEST_CASE("write_text_atomic without waiting for the disk still replaces whole and leaves no temp file", "[io][atomic]") {
  const TempDir dir;
  const std::string path = dir.file("report.html");
  write_text_atomic(path, "first version, longer than the second\n", Durability::renamed);
  write_text_atomic(path, "second\n", Durability::renamed);
  CHECK(read_text(path) == "second\n");
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"report.html"});
  // in a transaction: staged without waiting, committed with the set, the previous file replaced
  {
    OutputTransaction out(dir.path(), {"report.html", "summary.json"});
    out.stage("report.html", "third\n", Durability::renamed);
    out.stage("summary.json", "{}\n");
    CHECK(read_text(path) == "second\n");
    out.commit();
  }
  CHECK(read_text(path) == "third\n");
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"report.html", "summary.json"});
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
    OutputTransaction transaction(out, {"lift.csv", "summary.json"});
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
    OutputTransaction transaction(out, {"lift.csv", "summary.json"});
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
    OutputTransaction transaction(out, {"lift.csv", "summary.json"});
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
  REQUIRE_THROWS_AS(OutputTransaction(path, {"lift.csv"}), InputError);
  REQUIRE_THROWS_WITH(OutputTransaction(path, {"lift.csv"}),
                      Contains("output directory '" + path + "' is a regular file: camopt writes only into a real "
                               "directory"));
}

TEST_CASE("OutputTransaction stage into a missing subdirectory throws and leaves nothing", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  OutputTransaction transaction(out, {"sub/lift.csv"});
  REQUIRE_THROWS_WITH(transaction.stage("sub/lift.csv", "x"),
                      Contains("lift.csv") && Contains("directory '" + out + "/sub' does not exist"));
  transaction.commit();
  CHECK(fs::is_empty(out));
}

TEST_CASE("OutputTransaction checks every output path before the first rename", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  {
    OutputTransaction transaction(out, {"lift.csv", "summary.json"});
    transaction.stage("lift.csv", "new\n");
    transaction.stage("summary.json", "{}\n");
    // a directory appears at the second path after staging: lift.csv must not be renamed
    fs::create_directories(out + "/summary.json");
    REQUIRE_THROWS_WITH(transaction.commit(), Contains("cannot write '" + out + "/summary.json': it is a directory"));
  }
  CHECK(list_directory(out) == std::vector<std::string>{"summary.json"});
  // and a new transaction refuses the folder before anything is staged
  REQUIRE_THROWS_WITH(OutputTransaction(out, {"lift.csv", "summary.json"}),
                      Contains("cannot write '" + out + "/summary.json': it is a directory"));
}

TEST_CASE("OutputTransaction refuses a link, fifo or directory at an output path when it is made", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  fs::create_directories(out);
  write_text_atomic(dir.file("elsewhere.csv"), "keep\n");
  fs::create_symlink(dir.file("elsewhere.csv"), out + "/lift.csv");
  REQUIRE(::mkfifo((out + "/summary.json").c_str(), 0600) == 0);
  REQUIRE_THROWS_WITH(OutputTransaction(out, {"lift.csv"}), Contains("lift.csv': it is a symbolic link"));
  REQUIRE_THROWS_WITH(OutputTransaction(out, {"summary.json"}), Contains("summary.json': it is a named pipe (fifo)"));
  CHECK(fs::is_symlink(out + "/lift.csv"));
  CHECK(fs::is_fifo(out + "/summary.json"));
  CHECK(read_text(dir.file("elsewhere.csv")) == "keep\n");
}

TEST_CASE("OutputTransaction commit removes the files of its list it did not stage, and no other", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  fs::create_directories(out);
  for (const char* name : {"lift.csv", "summary.json", "profile.dxf", "notes.txt"})
    write_text_atomic(out + "/" + name, "old\n");
  {
    OutputTransaction transaction(out, {"lift.csv", "summary.json", "profile.dxf"});
    transaction.stage("lift.csv", "new\n");
    transaction.stage("summary.json", "{}\n");
    // before the commit the previous set is whole
    CHECK(read_text(out + "/profile.dxf") == "old\n");
    transaction.commit();
  }
  CHECK(list_directory(out) == std::vector<std::string>{"lift.csv", "notes.txt", "summary.json"});
  CHECK(read_text(out + "/lift.csv") == "new\n");
  CHECK(read_text(out + "/notes.txt") == "old\n");
}

TEST_CASE("OutputTransaction refuses a symbolic link as its directory", "[io][atomic]") {
  const TempDir dir;
  fs::create_directories(dir.file("real"));
  fs::create_directory_symlink(dir.file("real"), dir.file("link"));
  REQUIRE_THROWS_WITH(OutputTransaction(dir.file("link"), {"lift.csv"}),
                      Contains("output directory '" + dir.file("link") + "' is a symbolic link; give the directory "
                               "it points to"));
  CHECK(fs::is_empty(dir.file("real")));
}

TEST_CASE("write_text_atomic refuses a symbolic link, a fifo and a directory, and leaves each as it was",
          "[io][atomic]") {
  const TempDir dir;
  write_text_atomic(dir.file("real.csv"), "keep\n");
  fs::create_symlink(dir.file("real.csv"), dir.file("link.csv"));
  REQUIRE(::mkfifo(dir.file("pipe.csv").c_str(), 0600) == 0);
  fs::create_directories(dir.file("folder.csv"));
  REQUIRE_THROWS_WITH(write_text_atomic(dir.file("link.csv"), "x"),
                      Contains("cannot write '" + dir.file("link.csv") + "': it is a symbolic link"));
  REQUIRE_THROWS_WITH(write_text_atomic(dir.file("pipe.csv"), "x"), Contains("it is a named pipe (fifo)"));
  REQUIRE_THROWS_WITH(write_text_atomic(dir.file("folder.csv"), "x"), Contains("it is a directory"));
  CHECK(fs::is_symlink(dir.file("link.csv")));
  CHECK(fs::is_fifo(dir.file("pipe.csv")));
  CHECK(fs::is_directory(dir.file("folder.csv")));
  CHECK(read_text(dir.file("real.csv")) == "keep\n");
  CHECK(list_directory(dir.path()) == std::vector<std::string>{"folder.csv", "link.csv", "pipe.csv", "real.csv"});
}

TEST_CASE("a second OutputTransaction on a directory waits until the first has committed", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  const std::vector<std::string> names = {"lift.csv", "summary.json"};
  std::optional<OutputTransaction> first;
  first.emplace(out, names);
  first->stage("lift.csv", "first\n");
  first->stage("summary.json", "first\n");

  std::atomic<bool> waiting{false}, locked{false};
  std::string message;
  std::thread second_run([&] {
    OutputTransaction second(out, names, [&](const std::string& m) {
      message = m;
      waiting = true;
    });
    locked = true;
    second.stage("lift.csv", "second\n");
    second.commit();
  });
  for (int i = 0; i < 10000 && !waiting; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  REQUIRE(waiting);
  // still waiting while the first holds the folder
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK_FALSE(locked);
  first->commit();
  second_run.join();
  CHECK(locked);
  CHECK(message == "another camopt run is writing '" + out + "': waiting for it to finish");
  // the second run's set, whole: its lift.csv, and no summary.json of the first
  CHECK(list_directory(out) == std::vector<std::string>{"lift.csv"});
  CHECK(read_text(out + "/lift.csv") == "second\n");
}

TEST_CASE("OutputTransaction adds the names of locked_outputs once it holds the folder", "[io][atomic]") {
  const TempDir dir;
  const std::string out = dir.file("out");
  std::optional<OutputTransaction> first;
  first.emplace(out, std::vector<std::string>{"lift.csv", "lift.png"});
  first->stage("lift.csv", "first\n");
  first->stage("lift.png", "first\n");

  // the second run's extra names: the .png files it finds in the folder when it is called
  std::atomic<bool> waiting{false};
  std::vector<std::string> seen;
  std::thread second_run([&] {
    OutputTransaction second(
        out, {"lift.csv"}, [&](const std::string&) { waiting = true; },
        [&] {
          for (const std::string& name : list_directory(out))
            if (fs::path(name).extension() == ".png") seen.push_back(name);
          return seen;
        });
    second.stage("lift.csv", "second\n");
    second.commit();
  });
  for (int i = 0; i < 10000 && !waiting; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  REQUIRE(waiting);
  first->commit();
  second_run.join();
  // called after the first run's commit: it saw lift.png, and the second's commit removed it
  CHECK(seen == std::vector<std::string>{"lift.png"});
  CHECK(list_directory(out) == std::vector<std::string>{"lift.csv"});
  CHECK(read_text(out + "/lift.csv") == "second\n");
}
