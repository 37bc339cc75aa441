// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/observation_model.h"

#include "dualgraph/dual_graph/observation_models.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

AttachedObservation AttachedObservation::of(const GateObservation& observation, LandmarkModel landmark) {
  AttachedObservation attached;
  attached.gate_id = observation.gate_id;
  attached.kind = observation.kind;
  attached.edge.gate_id = observation.gate_id;
  attached.edge.model = landmark;
  return attached;
}

Result<AttachedObservation> ObservationModel::attachCentre(const GateObservation& observation,
                                                           const NodeAttachment& at) const {
  const std::string what = "observation of gate " + std::to_string(observation.gate_id);
  const Eigen::Vector3d p_body = centreInBody(observation);
  const Eigen::Matrix3d rotation = at.node_T_body.linear();
  Eigen::Matrix3d covariance = rotation * centreCovarianceInBody(observation) * rotation.transpose();
  if (at.compensation != nullptr) {
    Eigen::Matrix<double, 3, 6> J;
    J << rotation, -rotation * skew(p_body);
    covariance += J * *at.compensation * J.transpose();
  }
  Result<Eigen::Matrix3d> information = pointInformationFromCovariance(covariance, what + ": position covariance");
  if (!information.ok()) return information.status();
  AttachedObservation attached = AttachedObservation::of(observation, LandmarkModel::kPoint);
  GateEdgeMeasurement& edge = attached.edge;
  edge.p_node = at.node_T_body * p_body;
  edge.node_T_gate = Eigen::Isometry3d::Identity();
  edge.node_T_gate.translation() = edge.p_node;
  edge.point_information = *information;
  return attached;
}

const ObservationModel* findObservationModel(ObservationKind kind) {
  static const PoseObservationModel pose;
  static const PositionObservationModel position;
  static const CornerRaysObservationModel corners;
  switch (kind) {
    case ObservationKind::kPose: return &pose;
    case ObservationKind::kPosition: return &position;
    case ObservationKind::kCorners: return &corners;
  }
  return nullptr;
}

const ObservationModel& observationModel(ObservationKind kind) {
  const ObservationModel* model = findObservationModel(kind);
  return model != nullptr ? *model : *findObservationModel(ObservationKind::kPose);
}

}  // namespace dualgraph
