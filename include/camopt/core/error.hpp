#pragma once
// the error contract (STYLE.md §5), one channel per kind of failure:
// - CAMOPT_ASSERT: a bug in camopt; aborts with the location in every build type.
// - CAMOPT_THROW_UNLESS / InputError: a bad argument or bad user input; the message names
//   the field, the value and the rule it broke.
// - Status ([[nodiscard]]): the outcome of a numerical computation (no convergence,
//   singular, ...) with the angle and residual where it failed. NumericalError carries a
//   Status to the CLI; it is thrown only outside C callbacks, and never from a constructor
//   (numerical objects come from factories that return a Status).
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace camopt {

// where a value came from in a user file: file:line:column and the key path
struct SourceRef {
  std::string file;
  int line = 0;
  int column = 0;
  std::string key_path;

  // "file:line:column: key.path" (omits what is unknown)
  std::string str() const;
};

// bad user input; the message names the field, the value and the rule it broke
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
  InputError(const SourceRef& where, const std::string& message)
      : std::runtime_error(where.str() + ": " + message) {}
};

enum class StatusCode {
  ok,
  no_convergence,      // iterative solve stopped above tolerance
  cannot_assemble,     // a link cannot close, a contact cannot be reached
  singular,            // toggle / pressure angle reached 90 deg
  undercut,            // synthesized profile curvature crosses zero
  integrator_failure,  // SUNDIALS gave up
  infeasible,          // optimisation constraints cannot be met
  not_implemented,     // capability not built yet
  interrupted,         // the caller asked the run to stop (Ctrl-C): no result, not a failure
};

const char* to_string(StatusCode code);

// outcome of a numerical computation: code, message and where (angle, residual, ...)
struct [[nodiscard]] Status {
  StatusCode code = StatusCode::ok;
  std::string message;
  std::string where;

  bool ok() const { return code == StatusCode::ok; }
  static Status success() { return {}; }
  std::string str() const;
};

// a numerical failure escaping to the CLI (thrown only outside C callbacks)
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(Status status)
      : std::runtime_error(status.str()), status_(std::move(status)) {}
  const Status& status() const { return status_; }

 private:
  Status status_;
};

// a number for a message: the shortest of %g-style output with `digits` significant digits
std::string format_value(double value, int digits = 10);

[[noreturn]] void assertion_failed(const char* expr, const char* file, int line, const char* msg);

// throws InputError("<message> (rule: <expr>)"); see CAMOPT_THROW_UNLESS
[[noreturn]] void precondition_failed(const char* expr, const std::string& message);

}  // namespace camopt

// programmer bug: abort with location (active in every build type)
#define CAMOPT_ASSERT(cond)                                                        \
  do {                                                                             \
    if (!(cond)) ::camopt::assertion_failed(#cond, __FILE__, __LINE__, nullptr);   \
  } while (0)
#define CAMOPT_ASSERT_MSG(cond, msg)                                               \
  do {                                                                             \
    if (!(cond)) ::camopt::assertion_failed(#cond, __FILE__, __LINE__, msg);       \
  } while (0)

// public precondition on an argument: throws InputError naming the field, its value and the
// rule, e.g. CAMOPT_THROW_UNLESS(step > 0, "sweep step_deg = " + format_value(step) + " must be > 0")
#define CAMOPT_THROW_UNLESS(cond, message)                                         \
  do {                                                                             \
    if (!(cond)) ::camopt::precondition_failed(#cond, message);                    \
  } while (0)
