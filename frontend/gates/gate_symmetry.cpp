// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_symmetry.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace dualgraph {

Eigen::Matrix3d nearestGateSymmetry(const Eigen::Matrix3d& R_reference, const Eigen::Matrix3d& R_detected,
                                    GateSides sides) {
  const Eigen::Matrix3d reference_R_detected = R_reference.transpose() * R_detected;
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_angle = std::numeric_limits<double>::infinity();
  const int side_count = sides == GateSides::kEither ? 2 : 1;
  for (int side = 0; side < side_count; ++side) {
    for (int quarter = 0; quarter < 4; ++quarter) {
      const Eigen::Matrix3d candidate = Eigen::AngleAxisd(side * M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                                        Eigen::AngleAxisd(quarter * M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
      const double angle = Eigen::AngleAxisd(reference_R_detected * candidate).angle();
      if (angle < best_angle) {
        best_angle = angle;
        best = candidate;
      }
    }
  }
  return best;
}

}  // namespace dualgraph
