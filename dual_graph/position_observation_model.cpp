// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/observation_models.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status PositionObservationModel::validate(const GateObservation& observation, const std::string& where) const {
  if (!observation.p_body.allFinite()) return Status(StatusCode::kInvalidArgument, where + "p_body has a non-finite entry");
  return checkCovariance(observation.position_covariance, where + "position_covariance");
}

Status PositionObservationModel::checkUsable(const LocalizerParams& params, const std::string& what) const {
  if (params.landmark == LandmarkModel::kPose) {
    return Status(StatusCode::kInvalidArgument, what + ": position-only observations need landmark: point");
  }
  return Status();
}

Result<AttachedObservation> PositionObservationModel::attach(const GateObservation& observation,
                                                             const NodeAttachment& at, LandmarkModel landmark) const {
  if (landmark == LandmarkModel::kPose) {
    return Status(StatusCode::kInvalidArgument,
                  "observation of gate " + std::to_string(observation.gate_id) +
                      ": a position-only observation cannot constrain an SE(3) gate landmark (landmark: point)");
  }
  return attachCentre(observation, at);
}

Status PositionObservationModel::addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node,
                                                   int gate, const std::shared_ptr<const RobustKernel>& kernel) const {
  return pool.addGateEdge(node, gate, attached.edge, kernel);
}

Eigen::Vector3d PositionObservationModel::centreInBody(const GateObservation& observation) const {
  return observation.p_body;
}

Eigen::Matrix3d PositionObservationModel::centreCovarianceInBody(const GateObservation& observation) const {
  return observation.position_covariance;
}

}  // namespace dualgraph
