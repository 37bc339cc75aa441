// SPDX-License-Identifier: MIT
// Factories for the dual graph's edges: relative pose, pose prior, point observation, point prior.
#pragma once

#include <memory>

#include "dualgraph/core/graph.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"

namespace dualgraph {

/// The edges the dual graph builds, from measurements and information matrices in the edges' own
/// units (for EdgeSE3/EdgeSE3Prior g2o units: convert a metric covariance with
/// `poseInformationFromMetricCovariance`, types/se3_covariance.h). Each returns the edge stored in `graph`.

/// `from → to` with measurement from_T_to (odometry increments, SE(3) detections, distilled edges).
Result<EdgeSE3*> addRelativePoseEdge(Graph& graph, int from_id, int to_id, const Eigen::Isometry3d& from_T_to,
                                     const Matrix6d& information_g2o);
/// Prior world_T_x on a pose vertex.
Result<EdgeSE3Prior*> addPosePriorEdge(Graph& graph, int id, const Eigen::Isometry3d& world_T_x,
                                       const Matrix6d& information_g2o);
/// A point `point_id` seen from pose `pose_id` at p_pose (pose axes), information in m⁻².
Result<EdgeSE3PointXYZ*> addPointObservationEdge(Graph& graph, int pose_id, int point_id,
                                                 const Eigen::Vector3d& p_pose, const Eigen::Matrix3d& information);
/// Prior p_world on a point vertex, information in m⁻².
Result<EdgePointXYZPrior*> addPointPriorEdge(Graph& graph, int point_id, const Eigen::Vector3d& p_world,
                                             const Eigen::Matrix3d& information);

}  // namespace dualgraph
