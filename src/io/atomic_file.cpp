#include "camopt/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
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
#include "temp_files.hpp"

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

// what a file that is not a regular file is, for messages
std::string kind_of(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a named pipe (fifo)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a regular file";
  return "not a regular file";
}

// an output path is absent or a regular file: a link, device, fifo or directory there is
// never replaced (renaming over /dev/null as root would destroy it)
void require_replaceable(const std::string& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0 || S_ISREG(info.st_mode)) return;  // absent: later steps say why
  throw InputError("cannot write '" + path + "': it is " + kind_of(info.st_mode) +
                   "; camopt writes its outputs only as regular files (it never replaces a link, device, "
                   "fifo or directory)");
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

// remove a temp file this process made
void discard_temp(const std::string& temp_path) {
  ::unlink(temp_path.c_str());
  detail::forget_temp(temp_path);
}

// write `content` to a new temp file next to `path` (on the disk before it returns when
// `durability` says so); returns the temp path
std::string write_temp_file(const std::string& path, std::string_view content,
                            Durability durability = Durability::on_disk) {
  require_parent_directory(path);
  std::string temp_path;
  const int fd = detail::create_registered_temp(path, temp_path);
  if (fd < 0) throw_write_error(path, errno);

  // on failure: keep errno, drop the temp file
  const auto fail = [&](int error) {
    ::close(fd);
    discard_temp(temp_path);
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
  if (durability == Durability::on_disk && ::fsync(fd) != 0) fail(errno);
  if (::close(fd) != 0) {
    const int error = errno;
    discard_temp(temp_path);
    throw_write_error(path, error);
  }
  return temp_path;
}

// move a finished temp file over its final path; removes the temp file on failure
void rename_into_place(const std::string& temp_path, const std::string& path) {
  if (std::rename(temp_path.c_str(), path.c_str()) != 0) {
    const int error = errno;
    discard_temp(temp_path);
    throw_write_error(path, error);
  }
  detail::forget_temp(temp_path);
}

// a previous run's file of the set that this run did not write
void remove_stale(const std::string& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return;
  if (::unlink(path.c_str()) != 0 && errno != ENOENT)
    throw InputError("cannot remove '" + path + "', left by an earlier run: " + std::strerror(errno));
}

// the output directory, made if missing and opened; it must be a real directory
int open_output_directory(const std::string& directory) {
  struct stat info {};
  if (::lstat(directory.c_str(), &info) == 0) {
    if (!S_ISDIR(info.st_mode))
      throw InputError("output directory '" + directory + "' is " + kind_of(info.st_mode) +
                       (S_ISLNK(info.st_mode) ? "; give the directory it points to" : "") +
                       ": camopt writes only into a real directory");
  } else {
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec) throw InputError("cannot create output directory '" + directory + "': " + ec.message());
  }
  // O_NOFOLLOW: a link swapped in since the check is refused too
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) throw InputError("cannot open output directory '" + directory + "': " + std::strerror(errno));
  return fd;
}

// an exclusive flock on the directory: one camopt run writes into it at a time
void lock_directory(int fd, const std::string& directory, const std::function<void(const std::string&)>& on_wait) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return;
  if (errno == EWOULDBLOCK && on_wait)
    on_wait("another camopt run is writing '" + directory + "': waiting for it to finish");
  while (::flock(fd, LOCK_EX) != 0)
    if (errno != EINTR) {
      const int error = errno;
      ::close(fd);
      throw InputError("cannot lock output directory '" + directory + "': " + std::strerror(error));
    }
}

}  // namespace

void write_text_atomic(const std::string& path, std::string_view content, Durability durability) {
  require_replaceable(path);
  const std::string temp_path = write_temp_file(path, content, durability);
  try {
    require_replaceable(path);  // again: the check and the rename are far apart for a large file
  } catch (...) {
    discard_temp(temp_path);
    throw;
  }
  rename_into_place(temp_path, path);
}

OutputTransaction::OutputTransaction(std::string directory, std::vector<std::string> may_write,
                                     const std::function<void(const std::string&)>& on_wait,
                                     const std::function<std::vector<std::string>()>& locked_outputs)
    : directory_(std::move(directory)), may_write_(std::move(may_write)) {
  // the folder, locked against other runs, the names known only then, its output paths checked
  const int fd = open_output_directory(directory_);
  lock_directory(fd, directory_, on_wait);
  lock_fd_ = fd;
  try {
    if (locked_outputs)
      for (std::string& name : locked_outputs())
        if (std::find(may_write_.begin(), may_write_.end(), name) == may_write_.end()) may_write_.push_back(std::move(name));
    for (const std::string& name : may_write_) require_replaceable(path_of(name));
  } catch (...) {
    release_lock();
    throw;
  }
}

OutputTransaction::~OutputTransaction() {
  // never throws: unlink reports failure through errno only
  for (const auto& [temp_path, final_path] : staged_)
    if (!temp_path.empty()) discard_temp(temp_path);
  release_lock();
}

std::string OutputTransaction::path_of(const std::string& file_name) const {
  return (fs::path(directory_) / file_name).string();
}

void OutputTransaction::release_lock() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // closing the descriptor drops the flock
  lock_fd_ = -1;
}

void OutputTransaction::stage(const std::string& file_name, std::string_view content, Durability durability) {
  CAMOPT_ASSERT_MSG(!committed_, "OutputTransaction: stage() after commit()");
  CAMOPT_ASSERT_MSG(std::find(may_write_.begin(), may_write_.end(), file_name) != may_write_.end(),
                    "OutputTransaction: a file not in the command's list of outputs");
  const std::string final_path = path_of(file_name);
  for (const auto& staged : staged_)
    CAMOPT_ASSERT_MSG(staged.second != final_path, "OutputTransaction: file staged twice");
  // written now, so a full disk shows before anything is committed
  staged_.emplace_back(write_temp_file(final_path, content, durability), final_path);
  synced_ = synced_ || durability == Durability::on_disk;
}

void OutputTransaction::commit() {
  CAMOPT_ASSERT_MSG(!committed_, "OutputTransaction: commit() called twice");
  // every output path is checked before the first rename: nothing is renamed when one fails
  for (const std::string& name : may_write_) require_replaceable(path_of(name));
  // the staged files replace the previous ones
  for (auto& [temp_path, final_path] : staged_) {
    if (temp_path.empty()) continue;  // renamed by an earlier, failed commit
    // a committed entry has no temp file left for the destructor
    const std::string renaming = std::exchange(temp_path, std::string());
    rename_into_place(renaming, final_path);
  }
  // a previous run's file of the set that this run did not write would read as this run's
  for (const std::string& name : may_write_) {
    const std::string path = path_of(name);
    const bool staged = std::any_of(staged_.begin(), staged_.end(), [&](const auto& s) { return s.second == path; });
    if (!staged) remove_stale(path);
  }
  if (synced_) ::fsync(lock_fd_);  // the renames reach the disk with the files
  for (const auto& [temp_path, final_path] : staged_)
    if (const auto id = file_id(final_path)) committed_ids_[std::filesystem::path(final_path).filename().string()] = *id;
  committed_ = true;
  release_lock();
}

std::optional<FileId> file_id(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino),
                static_cast<std::int64_t>(st.st_size),
                static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec};
}

}  // namespace camopt::io
