// what the CVODE runs share (cvode_support.hpp): an exception inside a C callback is kept as
// a message and the callback returns CVODE's fatal flag, so no exception crosses SUNDIALS
#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>

#include "dynamics/cvode_support.hpp"  // private to src/dynamics (tests/CMakeLists.txt adds src/)

using namespace camopt::dynamics::detail;

TEST_CASE("cvode support: a callback keeps the exception's message and returns the fatal flag", "[dynamics][cvode]") {
  std::string error;
  int flag = 0;
  try {
    throw std::runtime_error("no contact point at 12 deg");
  } catch (...) {
    flag = keep_callback_error(error, "right-hand side");
  }
  CHECK(flag == -1);
  CHECK(error == "right-hand side: no contact point at 12 deg");
  CHECK(callback_note(error) == " (right-hand side: no contact point at 12 deg)");
  std::string other;
  try {
    throw 42;
  } catch (...) {
    flag = keep_callback_error(other, "root function");
  }
  CHECK(flag == -1);
  CHECK(other == "root function: an exception that is not a std::exception");
  CHECK(callback_note("").empty());
}
