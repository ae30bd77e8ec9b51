#pragma once
// the contact extremes of a sweep's summary refined between its grid points (summary.cpp
// collects the grid values; contact_extremes.cpp refines them): every grid-local extreme
// that could beat the best grid value is bracketed by its neighbouring grid points and
// maximised there by Brent's method on solves of the mechanism at trial driver values, each
// seeded from the nearest grid point (solve_near). Not installed: nothing outside
// src/kinematics includes it.
#include <cstddef>
#include <functional>
#include <optional>

#include "camopt/kinematics/sweep.hpp"

namespace camopt::kin::detail {

// solves of one control position of a sweep at driver values between its grid points
class ContactProbe {
 public:
  ContactProbe(const Mechanism& m, const SweepResult& r, std::size_t position);

  // every connection's contact state at driver x [deg or mm] within the grid's range, solved
  // from the nearest grid point; nullptr when that solve fails (failed() is then set)
  const std::vector<ContactState>* at(double x);
  bool failed() const { return failed_; }
  long solves() const { return solves_; }

  const Mechanism& mech;
  const SweepResult& result;
  const std::size_t position;

 private:
  std::optional<Workspace> ws_;
  std::vector<double> scale_;  // per variable and order: internal unit per sweep output unit
  std::vector<Jet3> seed_;
  bool failed_ = false;
  long solves_ = 0;
};

// a quantity of one contact's state, larger is worse; -infinity where it is not defined
// (e.g. the contact is open)
using ContactQuantity = std::function<double(const ContactState&)>;

// where a quantity is largest: its value, driver [deg or mm] and connection
struct ContactExtreme {
  Extreme extreme;
  std::size_t contact = 0;
};

// the largest value of q over the sweep's range and the given connections: the best grid
// value, raised by refining every grid-local maximum whose optimistic bound reaches the
// larger of `floor` and the best found; nullopt when q is defined at no grid point. The
// value returned is one the mechanism takes (a solved trial or a grid point), never below
// the best grid value.
std::optional<ContactExtreme> refined_max(ContactProbe& probe, const std::vector<std::size_t>& contacts,
                                          const ContactQuantity& q, double floor = -INFINITY);

}  // namespace camopt::kin::detail
