#pragma once
// reading an input file whole, with the checks every reader shares: it must be a regular
// file (not a directory, device, pipe or socket) of at most kMaxInputBytes, readable; an
// InputError says which rule failed ("no such file", "permission denied", "is a directory").
#include <cstddef>
#include <string>

namespace camopt::io {

inline constexpr std::size_t kMaxInputBytes = std::size_t{64} << 20;  // 64 MiB

// the file's bytes; `what` names it in messages ("design file", "target lift csv")
std::string read_input_file(const std::string& path, const std::string& what);

}  // namespace camopt::io
