// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/systematic_floor.h"

#include <Eigen/Geometry>

namespace dualgraph {

Eigen::Matrix3d floorTranslationCovariance(const SystematicFloor& floor, const Eigen::Vector3d& p_node,
                                           const Eigen::Matrix3d& axes_R_node) {
  const double range = p_node.norm();
  if (!(range > 0.0)) return Eigen::Matrix3d::Zero();
  const Eigen::Vector3d sight = axes_R_node * (p_node / range);
  const Eigen::Matrix3d along = sight * sight.transpose();
  const double var_along = floor.range_fraction * floor.range_fraction * range * range;
  const double var_across = floor.lateral_fraction * floor.lateral_fraction * range * range;
  return var_along * along + var_across * (Eigen::Matrix3d::Identity() - along);
}

void addFloorToPoseCovariance(const SystematicFloor& floor, const Eigen::Isometry3d& node_T_gate,
                              Matrix6d& covariance) {
  // Right perturbation: the translation part lives in the gate's axes.
  Matrix6d metric = Matrix6d::Zero();
  metric.topLeftCorner<3, 3>() =
      floorTranslationCovariance(floor, node_T_gate.translation(), node_T_gate.linear().transpose());
  metric.bottomRightCorner<3, 3>().diagonal().setConstant(floor.rotation_rad * floor.rotation_rad);
  covariance += covarianceMetricToG2o(metric);
}

}  // namespace dualgraph
