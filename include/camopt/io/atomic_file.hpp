#pragma once
// every output is written to a temporary file in the same directory, then renamed, so
// no partial file survives an error or a SIGINT / SIGTERM / SIGHUP / SIGQUIT. Only a
// regular file is ever replaced: a symbolic link, device, fifo or directory at an output
// path is an InputError naming it.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace camopt::io {

// on_disk: the file's data reach the disk (fsync) before it is renamed into place, as every
// result file. renamed: the rename alone, for a derived file that can be rebuilt from the
// results (the report): as atomic against an error or a signal, without waiting for the disk
enum class Durability { on_disk, renamed };

// write `content` to `path` atomically (temp file + rename); throws InputError naming
// the path when the directory is missing or not writable, or when `path` exists and is
// not a regular file (nothing is created then)
void write_text_atomic(const std::string& path, std::string_view content,
                       Durability durability = Durability::on_disk);

// which file a path names: a file replaced by another (a rename) has another inode, a file
// written again another size or time
struct FileId {
  std::uint64_t device = 0, inode = 0;
  std::int64_t size = -1, mtime_ns = 0;
  bool operator==(const FileId&) const = default;
};
// the file at `path`, nothing when there is none
std::optional<FileId> file_id(const std::string& path);

// the set of output files of one run, committed together into one directory.
// The constructor makes the directory (if missing; it must be a real directory, not a
// symbolic link), locks it against other camopt runs (flock on the directory: a second run
// waits, after calling `on_wait` with a message naming the directory, until the first has
// committed or died), and checks the output paths. stage() writes a file to a temp file;
// commit() checks every output path before the first rename, renames the staged files, and
// removes the files of `may_write` this run did not stage (a previous run's): the folder
// then holds exactly this run's set. Without commit() (an error) the destructor removes the
// temp files and the folder keeps the previous run's set untouched.
class OutputTransaction {
 public:
  // may_write: every file name the command can write into the directory; locked_outputs, when
  // given, is called once the folder is locked and adds the names it returns to may_write
  // (files named after the data of the run the folder holds, read without another run's writes)
  OutputTransaction(std::string directory, std::vector<std::string> may_write,
                    const std::function<void(const std::string&)>& on_wait = {},
                    const std::function<std::vector<std::string>()>& locked_outputs = {});
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  // file_name: one of may_write; the directory is synced at commit() when a file was staged on_disk
  void stage(const std::string& file_name, std::string_view content, Durability durability = Durability::on_disk);
  void commit();
  const std::string& directory() const { return directory_; }
  // after commit(): the files it put in place, by file name, taken before the folder was
  // unlocked (a later run's commit replaces them by other files)
  const std::map<std::string, FileId>& committed() const { return committed_ids_; }

 private:
  std::string path_of(const std::string& file_name) const;
  void release_lock();

  std::string directory_;
  std::vector<std::string> may_write_;
  std::vector<std::pair<std::string, std::string>> staged_;  // temp path, final path
  int lock_fd_ = -1;  // the directory, opened and flock'ed
  bool synced_ = false;  // a file staged on_disk: commit() syncs the directory
  bool committed_ = false;
  std::map<std::string, FileId> committed_ids_;
};

}  // namespace camopt::io
