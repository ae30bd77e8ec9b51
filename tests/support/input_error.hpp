#pragma once
// the message of the InputError a call throws (a test of a refused input compares it)
#include <catch2/catch.hpp>
#include <string>

#include "camopt/core/error.hpp"

namespace camopt::test {

template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("expected an InputError");
  return {};
}

}  // namespace camopt::test
