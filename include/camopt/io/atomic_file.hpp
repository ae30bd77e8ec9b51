#pragma once
// every output is written to a temporary file in the same directory, then renamed, so
// no partial file survives an error.
#include <string>
#include <string_view>
#include <vector>

namespace camopt::io {

// write `content` to `path` atomically (temp file + rename); throws InputError naming
// the path when the directory is missing or not writable
void write_text_atomic(const std::string& path, std::string_view content);

// a set of output files committed together: stage() writes each to a temp file,
// commit() renames them all; the destructor removes any temp file not committed.
class OutputTransaction {
 public:
  explicit OutputTransaction(std::string directory);  // creates the directory if missing
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  void stage(const std::string& file_name, std::string_view content);
  void commit();
  const std::string& directory() const { return directory_; }

 private:
  std::string directory_;
  std::vector<std::pair<std::string, std::string>> staged_;  // temp path, final path
  bool committed_ = false;
};

}  // namespace camopt::io
