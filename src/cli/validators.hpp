#pragma once
// command-line value checks with short messages ("value -0.5 must be > 0"), in place of
// CLI11's PositiveNumber / NonNegativeNumber, which print the whole double range
#include <CLI/CLI.hpp>
#include <charconv>
#include <initializer_list>
#include <string>

#include "camopt/core/error.hpp"

namespace camopt::cli {

namespace check {
inline CLI::Validator bound(bool strict, const char* name) {
  return CLI::Validator(
      [strict](std::string& text) -> std::string {
        double v = 0.0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
        if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return "value " + text + " is not a number";
        if (strict ? !(v > 0.0) : !(v >= 0.0)) return "value " + text + (strict ? " must be > 0" : " must be >= 0");
        return "";
      },
      name);
}
}  // namespace check

inline CLI::Validator positive_number() { return check::bound(true, "POSITIVE"); }

// InputError "OPTION: does nothing WHY" for any of `options` given on the command line of
// `cmd`: an option the chosen mode ignores is a mistake, not a silent default
inline void reject_unused(const CLI::App& cmd, std::initializer_list<const char*> options, const std::string& why) {
  for (const char* name : options)
    if (const CLI::Option* o = cmd.get_option_no_throw(name); o != nullptr && o->count() > 0)
      throw InputError(std::string(name) + ": does nothing " + why);
}
inline CLI::Validator non_negative_number() { return check::bound(false, "NONNEGATIVE"); }

}  // namespace camopt::cli
