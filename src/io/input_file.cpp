#include "camopt/io/input_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "camopt/core/error.hpp"

namespace camopt::io {

std::string read_input_file(const std::string& path, const std::string& what) {
  auto fail = [&](const std::string& why) -> std::string {
    throw InputError(SourceRef{path, 0, 0, ""}, "cannot read " + what + ": " + why);
  };
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return fail(errno == ENOENT ? "no such file" : std::strerror(errno));
  if (S_ISDIR(st.st_mode)) return fail("is a directory");
  if (!S_ISREG(st.st_mode)) return fail("is not a regular file (a device, pipe or socket)");
  if (static_cast<unsigned long long>(st.st_size) > kMaxInputBytes)
    return fail("is " + std::to_string(st.st_size) + " bytes, above the " + std::to_string(kMaxInputBytes >> 20) +
                " MiB limit of input files");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> stream(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!stream) return fail(std::strerror(errno));
  std::string text;
  char buffer[65536];
  std::size_t count = 0;
  while ((count = std::fread(buffer, 1, sizeof buffer, stream.get())) > 0) {
    text.append(buffer, count);
    if (text.size() > kMaxInputBytes) return fail("grew past the " + std::to_string(kMaxInputBytes >> 20) + " MiB limit of input files while read");
  }
  if (std::ferror(stream.get()) != 0) return fail(std::strerror(errno));
  return text;
}

}  // namespace camopt::io
