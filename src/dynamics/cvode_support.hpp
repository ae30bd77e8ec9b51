#pragma once
// what the time-domain dynamics models share (internal): owned SUNDIALS objects, a silent
// CVODE error handler, the failure Status of a CVODE flag, and Catmull-Rom weights for the
// tabulated kinematic path.
#include <cvodes/cvodes.h>  // CVODE with quadratures (the flexible model's work integrals)
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>

#include "camopt/core/error.hpp"

namespace camopt::dynamics::detail {

// compiled kernels for the serial N_Vector's and the dense SUNMatrix's operations (replacing
// the ops table entries; clones inherit them). The distribution's SUNDIALS libraries are built
// without optimisation, so on the small systems here CVODE's vector and matrix work would
// cost more than the model. Same results to rounding: tests/dynamics/cvode_fast_ops_test.cpp.
void use_fast_ops(N_Vector v);
void use_fast_ops(SUNMatrix a);

// CVODE's error messages go into the returned Status, not to stderr
inline void silent_error_handler(int, const char*, const char*, char*, void*) {}

// owned SUNDIALS objects (CVODE, dense matrix and solver, state and tolerance vectors)
struct Sundials {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr, atol = nullptr, quad = nullptr;
  SUNMatrix a = nullptr;
  SUNLinearSolver ls = nullptr;
  void* cvode = nullptr;
  Sundials() = default;
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  // CVODE BDF (with a dense direct solver unless the caller sets its own) on y (filled by the caller, with atol), the
  // callbacks' user data, root functions, a step budget and a maximum step [s]; errors go
  // into the caller's Status. False when any SUNDIALS call fails.
  bool create_bdf(CVRhsFn rhs, CVRootFn roots, int root_count, void* user_data, double relative_tolerance,
                  long max_steps, double max_step_s, bool dense_solver = true) {
    const sunindextype n = N_VGetLength(y);
    use_fast_ops(y);
    use_fast_ops(atol);
    cvode = CVodeCreate(CV_BDF, ctx);
    if (dense_solver) {
      a = SUNDenseMatrix(n, n, ctx);
      if (a) use_fast_ops(a);
      ls = SUNLinSol_Dense(y, a, ctx);
    }
    return cvode && (!dense_solver || (a && ls)) && CVodeInit(cvode, rhs, 0.0, y) == CV_SUCCESS &&
           CVodeSVtolerances(cvode, relative_tolerance, atol) == CV_SUCCESS &&
           CVodeSetUserData(cvode, user_data) == CV_SUCCESS &&
           (!dense_solver || CVodeSetLinearSolver(cvode, ls, a) == CV_SUCCESS) &&
           CVodeSetMaxNumSteps(cvode, max_steps) == CV_SUCCESS && CVodeSetMaxStep(cvode, max_step_s) == CV_SUCCESS &&
           (root_count == 0 || (CVodeRootInit(cvode, root_count, roots) == CV_SUCCESS &&
                                CVodeSetNoInactiveRootWarn(cvode) == CV_SUCCESS)) &&
           CVodeSetErrHandlerFn(cvode, silent_error_handler, nullptr) == CV_SUCCESS;
  }
  ~Sundials() {
    if (cvode) CVodeFree(&cvode);
    if (ls) SUNLinSolFree(ls);
    if (a) SUNMatDestroy(a);
    if (quad) N_VDestroy(quad);
    if (atol) N_VDestroy(atol);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
};

inline std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// the name of a CVODE return flag (SUNDIALS returns a malloc'd string)
inline std::string cvode_flag_name(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  const std::string why = name ? name : std::to_string(flag);
  std::free(name);
  return why;
}

// a C callback's exception, kept: its message goes into `error` ("<callback>: <what>") and the
// callback returns -1, CVODE's fatal flag; the run's failure Status then carries the message
// with the time and cam angle. Call it only inside a catch block.
inline int keep_callback_error(std::string& error, const char* callback) noexcept {
  try {
    try {
      throw;
    } catch (const std::exception& e) {
      error = std::string(callback) + ": " + e.what();
    } catch (...) {
      error = std::string(callback) + ": an exception that is not a std::exception";
    }
  } catch (...) {  // no memory for the message: the flag alone
  }
  return -1;
}

// " (<callback>: <what>)" for a failure message, or "" when no callback failed
inline std::string callback_note(const std::string& error) { return error.empty() ? "" : " (" + error + ")"; }

// the longest CVODE step [s] for a model whose cam forcing enters only through a kinematic
// path tabulated every grid_step_rad: a longer step can pass over a whole lift event unseen
// (at low speed, 10-160 rpm, the contact dynamics no longer limit the step)
inline double path_max_step_s(double grid_step_rad, double omega_rad_per_s) {
  return 4.0 * grid_step_rad / omega_rad_per_s;
}

// steps since the last CVodeInit / CVodeReInit (which restarts CVODE's counter)
inline long steps_since_restart(void* cvode) {
  long steps = 0;
  CVodeGetNumSteps(cvode, &steps);
  return steps;
}

// the whole run's budget: max_steps bounds steps plus events over the run. CVODE's own limit
// counts per call and restarts with CVodeReInit, so a chattering contact (an event every step
// or two) would never reach it. Returns an empty string, or the failure message (the caller
// adds where: time, cam angle, rpm).
inline std::string step_budget_exceeded(long steps, long events, long max_steps, const std::string& last_event) {
  if (steps + events <= max_steps) return {};
  return "more than " + std::to_string(max_steps) + " steps and events (" + std::to_string(events) +
         " contact events" + (last_event.empty() ? "" : ", last '" + last_event + "'") +
         "): the contacts chatter or the motion is too fast for the step; raise max_steps or the contact damping";
}

// Catmull-Rom weights of the four points around u in [0, 1) (p_{i-1}, p_i, p_{i+1}, p_{i+2}),
// and of the derivative d/du
inline void catmull_rom_weights(double u, double w[4]) {
  const double u2 = u * u, u3 = u2 * u;
  w[0] = 0.5 * (-u + 2 * u2 - u3);
  w[1] = 0.5 * (2 - 5 * u2 + 3 * u3);
  w[2] = 0.5 * (u + 4 * u2 - 3 * u3);
  w[3] = 0.5 * (-u2 + u3);
}
inline void catmull_rom_slopes(double u, double w[4]) {
  const double u2 = u * u;
  w[0] = 0.5 * (-1 + 4 * u - 3 * u2);
  w[1] = 0.5 * (-10 * u + 9 * u2);
  w[2] = 0.5 * (1 + 8 * u - 9 * u2);
  w[3] = 0.5 * (-2 * u + 3 * u2);
}

}  // namespace camopt::dynamics::detail
