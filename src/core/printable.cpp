#include "camopt/core/printable.hpp"

namespace camopt {

namespace {

// length of the well-formed UTF-8 sequence at text[i] (0: not UTF-8, or a control character)
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  if (b >= 0x20 && b < 0x7f) return 1;
  std::size_t n = 0;
  unsigned lowest = 0;  // the smallest code point of that length (no overlong forms)
  if (b >= 0xc2 && b <= 0xdf) n = 2, lowest = 0x80;
  else if (b >= 0xe0 && b <= 0xef) n = 3, lowest = 0x800;
  else if (b >= 0xf0 && b <= 0xf4) n = 4, lowest = 0x10000;
  else return 0;
  if (i + n > text.size()) return 0;
  unsigned code = b & (0x7fu >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3fu);
  }
  const bool surrogate = code >= 0xd800 && code <= 0xdfff;
  const bool c1_control = code >= 0x80 && code < 0xa0;
  return code >= lowest && code <= 0x10ffff && !surrogate && !c1_control ? n : 0;
}

}  // namespace

std::string printable(std::string_view text, std::size_t max_bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (out.size() >= max_bytes) {
      out += "...";
      break;
    }
    if (const std::size_t n = utf8_length(text, i); n > 0) {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    const auto b = static_cast<unsigned char>(text[i++]);
    out += "\\x";
    out += kHex[b >> 4];
    out += kHex[b & 15];
  }
  return out;
}

}  // namespace camopt
