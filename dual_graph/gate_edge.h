// SPDX-License-Identifier: MIT
// GateEdgeMeasurement, one gate constraint relative to a pose node, and its edge and gate vertex.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// One gate constraint relative to a pose node (a temporary node, a keyframe or a single-graph node),
/// ready to become an edge node → gate: a detection re-expressed in the node's frame, or a distilled edge.
/// kPose: measurement node_T_gate, `pose_information` 6×6 in g2o units ([t; q.vec], EdgeSE3).
/// kPoint: measurement p_node (gate centre in node axes, m), `point_information` 3×3 in m⁻² (EdgeSE3PointXYZ).
struct GateEdgeMeasurement {
  int gate_id = -1;
  LandmarkModel model = LandmarkModel::kPose;
  Eigen::Isometry3d node_T_gate = Eigen::Isometry3d::Identity();
  Matrix6d pose_information = Matrix6d::Identity();
  /// kPose, a distilled edge under a systematic floor (dual_graph/systematic_floor.h) with learn_odometry_noise: its
  /// information before the floor (the detections' own spread), for the odometry-noise learner — the floor stands
  /// for errors two sightings of the gate share. Zero: the same as `pose_information`.
  Matrix6d statistical_pose_information = Matrix6d::Zero();
  Eigen::Vector3d p_node = Eigen::Vector3d::Zero();
  Eigen::Matrix3d point_information = Eigen::Matrix3d::Identity();
  int observations = 1;  ///< detections this constraint stands for

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using GateEdgeMeasurements = std::vector<GateEdgeMeasurement, Eigen::aligned_allocator<GateEdgeMeasurement>>;

/// Motion compensation: the observation taken at body pose `body` re-expressed in the frame of a node
/// with node_T_body (the VIO increment from the node's instant to the observation's), as one edge: its
/// ObservationModel's `attach` (observation_model.h). When `node_T_body_covariance` (metric [t; θ], right
/// perturbation) is given, its uncertainty is added: for a pose, Ad(gate_T_body) Σ Ad(gate_T_body)ᵀ in the gate
/// frame; for a point, J Σ Jᵀ with J = R_node_body [I, −[p_body]×]. kPoint uses the observation's centre (a
/// pose's translation); kPose needs a pose observation; kinds that anchor no gate (rays) make no single edge
/// (kInvalidArgument for both). kNotPositiveDefinite for unusable covariances.
Result<GateEdgeMeasurement> attachObservationToNode(const GateObservation& observation,
                                                    const Eigen::Isometry3d& node_T_body,
                                                    const Matrix6d* node_T_body_covariance, LandmarkModel model);

/// Adds the edge node → gate for `measurement` (EdgeSE3 or EdgeSE3PointXYZ) with the robust kernel
/// (may be null). Both vertices must exist with the types of `measurement.model`.
Result<EdgeBase*> addGateEdge(Graph& graph, int node_id, int gate_vertex_id, const GateEdgeMeasurement& measurement,
                              std::shared_ptr<const RobustKernel> kernel);

/// Adds a gate landmark vertex (VertexSE3 or VertexPointXYZ) with estimate world_T_gate (its translation
/// for a point).
Status addGateVertex(Graph& graph, int id, LandmarkModel model, const Eigen::Isometry3d& world_T_gate);

/// The landmark estimate implied by a node pose and a measurement: world_T_node · node_T_gate
/// (for a point, the translation is world_T_node · p_node).
Eigen::Isometry3d gateFromNode(const Eigen::Isometry3d& world_T_node, const GateEdgeMeasurement& measurement);

}  // namespace dualgraph
