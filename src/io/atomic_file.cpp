#include "camopt/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include "camopt/core/error.hpp"

namespace camopt::io {
namespace {

namespace fs = std::filesystem;

// the process umask, read without changing it (linux >= 4.7); 022 when unknown
mode_t process_umask() {
  static const mode_t mask = [] {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
      if (key == "Umask:") {
        std::string octal;
        status >> octal;
        return static_cast<mode_t>(std::strtoul(octal.c_str(), nullptr, 8));
      }
    }
    return static_cast<mode_t>(022);
  }();
  return mask;
}

[[noreturn]] void throw_write_error(const std::string& path, int error) {
  throw InputError("cannot write '" + path + "': " + std::strerror(error));
}

// the directory a file goes into must already exist
void require_parent_directory(const std::string& path) {
  fs::path directory = fs::path(path).parent_path();
  if (directory.empty()) directory = ".";
  std::error_code ec;
  const auto status = fs::status(directory, ec);
  if (!fs::exists(status))
    throw InputError("cannot write '" + path + "': directory '" + directory.string() + "' does not exist");
  if (!fs::is_directory(status))
    throw InputError("cannot write '" + path + "': '" + directory.string() + "' is not a directory");
}

// write `content` to a new temp file next to `path`; returns the temp path
std::string write_temp_file(const std::string& path, std::string_view content) {
  require_parent_directory(path);
  std::string temp_path = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(temp_path.data());
  if (fd < 0) throw_write_error(path, errno);

  // on failure: keep errno, drop the temp file
  const auto fail = [&](int error) {
    ::close(fd);
    ::unlink(temp_path.c_str());
    throw_write_error(path, error);
  };
  // mkstemp creates 0600; give the file the usual permissions
  if (::fchmod(fd, 0666 & ~process_umask()) != 0) fail(errno);
  const char* data = content.data();
  std::size_t remaining = content.size();
  while (remaining > 0) {
    const ssize_t written = ::write(fd, data, remaining);
    if (written < 0) {
      if (errno == EINTR) continue;
      fail(errno);
    }
    data += written;
    remaining -= static_cast<std::size_t>(written);
  }
  if (::fsync(fd) != 0) fail(errno);
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp_path.c_str());
    throw_write_error(path, error);
  }
  return temp_path;
}

// move a finished temp file over its final path; removes the temp file on failure
void rename_into_place(const std::string& temp_path, const std::string& path) {
  if (std::rename(temp_path.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp_path.c_str());
    throw_write_error(path, error);
  }
}

}  // namespace

void write_text_atomic(const std::string& path, std::string_view content) {
  rename_into_place(write_temp_file(path, content), path);
}

OutputTransaction::OutputTransaction(std::string directory) : directory_(std::move(directory)) {
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec) throw InputError("cannot create output directory '" + directory_ + "': " + ec.message());
  if (!fs::is_directory(directory_, ec))
    throw InputError("cannot create output directory '" + directory_ + "': a file of that name exists");
}

OutputTransaction::~OutputTransaction() {
  // never throws: unlink reports failure through errno only
  for (const auto& [temp_path, final_path] : staged_)
    if (!temp_path.empty()) ::unlink(temp_path.c_str());
}

void OutputTransaction::stage(const std::string& file_name, std::string_view content) {
  CAMOPT_ASSERT_MSG(!committed_, "OutputTransaction: stage() after commit()");
  const std::string final_path = (fs::path(directory_) / file_name).string();
  for (const auto& staged : staged_)
    CAMOPT_ASSERT_MSG(staged.second != final_path, "OutputTransaction: file staged twice");
  // written now, so a full disk shows before anything is committed
  staged_.emplace_back(write_temp_file(final_path, content), final_path);
}

void OutputTransaction::commit() {
  CAMOPT_ASSERT_MSG(!committed_, "OutputTransaction: commit() called twice");
  for (auto& [temp_path, final_path] : staged_) {
    if (temp_path.empty()) continue;  // renamed by an earlier, failed commit
    // a committed entry has no temp file left for the destructor
    const std::string renaming = std::exchange(temp_path, std::string());
    rename_into_place(renaming, final_path);
  }
  committed_ = true;
}

}  // namespace camopt::io
