// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/observation_models.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status PoseObservationModel::validate(const GateObservation& observation, const std::string& where) const {
  DG_RETURN_IF_ERROR(checkRigidTransform(observation.body_T_gate, where + "body_T_gate"));
  DG_RETURN_IF_ERROR(checkCovariance(observation.pose_covariance, where + "pose_covariance"));
  if (observation.has_alternative) {
    DG_RETURN_IF_ERROR(checkRigidTransform(observation.alternative_body_T_gate, where + "alternative_body_T_gate"));
    DG_RETURN_IF_ERROR(checkCovariance(observation.alternative_covariance, where + "alternative_covariance"));
  }
  if (observation.corner_rays.count == 0) return Status();
  if (observation.corner_rays.count != 4) {
    return Status(StatusCode::kInvalidArgument, where + "corner_rays.count " +
                                                    std::to_string(observation.corner_rays.count) +
                                                    " on a pose: 0 (none) or 4 (the corners it was solved from)");
  }
  return validateCornerRays(observation.corner_rays, where + "corner_rays.");
}

Status PoseObservationModel::checkUsable(const LocalizerParams&, const std::string&) const { return Status(); }

Result<AttachedObservation> PoseObservationModel::attach(const GateObservation& observation, const NodeAttachment& at,
                                                         LandmarkModel landmark) const {
  if (landmark == LandmarkModel::kPoint) return attachCentre(observation, at);
  const std::string what = "observation of gate " + std::to_string(observation.gate_id);
  AttachedObservation attached = AttachedObservation::of(observation, LandmarkModel::kPose);
  GateEdgeMeasurement& edge = attached.edge;
  edge.node_T_gate = at.node_T_body * observation.body_T_gate;
  Matrix6d covariance = observation.pose_covariance;
  if (at.compensation != nullptr) {
    const Matrix6d adjoint = se3Adjoint(observation.body_T_gate.inverse());
    covariance += adjoint * *at.compensation * adjoint.transpose();
  }
  Result<Matrix6d> information = poseInformationFromMetricCovariance(covariance, what + ": covariance");
  if (!information.ok()) return information.status();
  edge.pose_information = *information;
  edge.p_node = edge.node_T_gate.translation();
  if (observation.corner_rays.count == 4) attachCornerRays(observation.corner_rays, observation.body_T_gate, at, attached);
  return attached;
}

Status PoseObservationModel::addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node,
                                               int gate, const std::shared_ptr<const RobustKernel>& kernel) const {
  if (attached.rays.count == 4) return addCornerRayEdges(attached, pool, node, gate, kernel);
  return pool.addGateEdge(node, gate, attached.edge, kernel);
}

Eigen::Vector3d PoseObservationModel::centreInBody(const GateObservation& observation) const {
  return observation.body_T_gate.translation();
}

Eigen::Matrix3d PoseObservationModel::centreCovarianceInBody(const GateObservation& observation) const {
  // body_T_gate · exp([ρ; θ]) moves the centre by R_body_gate · ρ to first order.
  const Eigen::Matrix3d rotation = observation.body_T_gate.linear();
  return rotation * observation.pose_covariance.topLeftCorner<3, 3>() * rotation.transpose();
}

}  // namespace dualgraph
