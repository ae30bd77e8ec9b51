#pragma once
// user text quoted in messages
#include <cstddef>
#include <string>
#include <string_view>

namespace camopt {

// user text made safe to quote in a message on a terminal: control bytes (NUL, ESC, newline
// ...) and bytes that are not UTF-8 become \xNN, and text beyond max_bytes is cut with "..."
std::string printable(std::string_view text, std::size_t max_bytes = 160);

}  // namespace camopt
