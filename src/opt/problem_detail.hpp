#pragma once
// CamProblem's grid point, shared by problem.cpp and problem_rows.cpp (not installed)
#include <Eigen/Core>
#include <array>

#include "camopt/opt/problem.hpp"

namespace camopt::opt {

struct CamProblem::GridPoint {
  double deg = 0.0;                               // cam angle [deg]
  int position = 0;                               // swing: control position index
  std::array<double, 4> constant{};               // d^k L / dtheta^k at u = 0 [mm/deg^k]
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows;  // d^k L / dtheta^k per unit of u [mm/deg^k]
  bool variable = false;                          // inside the main part (rows not all zero)
};

}  // namespace camopt::opt
