#include "camopt/core/error.hpp"

#include <sstream>

namespace camopt {

std::string SourceRef::str() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  if (!key_path.empty()) s += ": " + key_path;
  return s;
}

const char* to_string(StatusCode code) {
  switch (code) {
    case StatusCode::ok: return "ok";
    case StatusCode::no_convergence: return "no convergence";
    case StatusCode::cannot_assemble: return "cannot assemble";
    case StatusCode::singular: return "singular configuration";
    case StatusCode::undercut: return "undercut";
    case StatusCode::integrator_failure: return "integrator failure";
    case StatusCode::infeasible: return "infeasible";
    case StatusCode::not_implemented: return "not implemented";
    case StatusCode::interrupted: return "interrupted";
  }
  return "unknown";
}

std::string Status::str() const {
  std::string s = to_string(code);
  if (!message.empty()) s += ": " + message;
  if (!where.empty()) s += " (at " + where + ")";
  return s;
}

void assertion_failed(const char* expr, const char* file, int line, const char* msg) {
  std::fprintf(stderr, "camopt internal error: assertion '%s' failed at %s:%d%s%s\n", expr, file, line,
               msg ? ": " : "", msg ? msg : "");
  std::abort();
}

void precondition_failed(const char* expr, const std::string& message) {
  throw InputError(message + " (rule: " + expr + ")");
}

std::string format_value(double value, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << value;
  return s.str();
}

}  // namespace camopt
