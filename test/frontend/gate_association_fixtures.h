// SPDX-License-Identifier: MIT
// Test helpers of the association tests: a pose turned about the world's z, and an association expected to succeed.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "dualgraph/frontend/gates/gate_association.h"

namespace dualgraph::association_testing {

/// world_T_frame at (x, y, z) [m], turned by `yaw` [rad] about the world's z axis.
inline Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d world_T_frame = Eigen::Isometry3d::Identity();
  world_T_frame.translation() = Eigen::Vector3d(x, y, z);
  world_T_frame.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return world_T_frame;
}

/// associator.associate(world_T_body, detections, map), which the test expects to succeed (empty when it fails).
inline std::vector<AssociationResult> run(const GateAssociator& associator, const Eigen::Isometry3d& world_T_body,
                                          std::vector<GateObservation> detections, const GateMap& map) {
  Result<std::vector<AssociationResult>> results = associator.associate(world_T_body, std::move(detections), map);
  EXPECT_TRUE(results.ok()) << results.status().toString();
  return results.ok() ? *results : std::vector<AssociationResult>();
}

}  // namespace dualgraph::association_testing
