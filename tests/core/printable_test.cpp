// printable(): user text quoted in a message reaches the terminal without control bytes or
// bytes that are not UTF-8, and well-formed UTF-8 passes unchanged
#include <catch2/catch.hpp>
#include <string>

#include "camopt/core/printable.hpp"

using camopt::printable;

TEST_CASE("printable escapes NUL, ESC, newline and DEL as hex escapes and keeps plain ASCII", "[core][printable]") {
  using namespace std::string_literals;
  CHECK(printable("a\0b"s) == "a\\x00b");
  CHECK(printable("\x1b[31mred") == "\\x1b[31mred");
  CHECK(printable("line1\nline2\t|\r") == "line1\\x0aline2\\x09|\\x0d");
  CHECK(printable("\x7f") == "\\x7f");
  CHECK(printable("lift_mm = 1.5e-3 (ok)") == "lift_mm = 1.5e-3 (ok)");
}

TEST_CASE("printable keeps well-formed UTF-8 and escapes every byte of a malformed sequence", "[core][printable]") {
  CHECK(printable("\xc2\xb5m \xc3\xb6l \xe2\x80\x94 \xf0\x9f\x94\xa7") == "\xc2\xb5m \xc3\xb6l \xe2\x80\x94 \xf0\x9f\x94\xa7");
  CHECK(printable("\xff\xfe") == "\\xff\\xfe");
  CHECK(printable("\xc0\x80") == "\\xc0\\x80");          // overlong NUL
  CHECK(printable("\xe0\x80\xaf") == "\\xe0\\x80\\xaf");  // overlong '/'
  CHECK(printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");  // a UTF-16 surrogate
  CHECK(printable("\xc2\x9b") == "\\xc2\\x9b");          // C1 control (CSI)
  CHECK(printable("ab\xe2\x80") == "ab\\xe2\\x80");      // cut short at the end
  CHECK(printable("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
}

TEST_CASE("printable cuts long text at max_bytes with an ellipsis", "[core][printable]") {
  const std::string long_text(1000, 'x');
  const std::string cut = printable(long_text, 20);
  CHECK(cut == std::string(20, 'x') + "...");
  CHECK(printable(long_text, std::string::npos) == long_text);
  CHECK(printable(std::string(10, '\0'), 8).substr(0, 8) == "\\x00\\x00");
}
