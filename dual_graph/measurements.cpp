// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/measurements.h"

#include <cmath>
#include <utility>

#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

GateObservation GateObservation::pose(double t, int gate_id, const Eigen::Isometry3d& body_T_gate,
                                      const Matrix6d& covariance) {
  GateObservation observation;
  observation.t = t;
  observation.gate_id = gate_id;
  observation.kind = ObservationKind::kPose;
  observation.body_T_gate = body_T_gate;
  observation.pose_covariance = covariance;
  observation.p_body = body_T_gate.translation();
  return observation;
}

GateObservation GateObservation::position(double t, int gate_id, const Eigen::Vector3d& p_body,
                                          const Eigen::Matrix3d& covariance) {
  GateObservation observation;
  observation.t = t;
  observation.gate_id = gate_id;
  observation.kind = ObservationKind::kPosition;
  observation.p_body = p_body;
  observation.body_T_gate.translation() = p_body;
  observation.position_covariance = covariance;
  return observation;
}

GateObservation GateObservation::corners(double t, int gate_id, const GateCornerRays& rays,
                                         const Eigen::Isometry3d& predicted_body_T_gate) {
  GateObservation observation;
  observation.t = t;
  observation.gate_id = gate_id;
  observation.kind = ObservationKind::kCorners;
  observation.corner_rays = rays;
  observation.body_T_gate = predicted_body_T_gate;
  observation.p_body = predicted_body_T_gate.translation();
  return observation;
}

GateObservation inTurnedGateFrame(GateObservation observation, const Eigen::Matrix3d& turn) {
  Eigen::Isometry3d gate_T_turned = Eigen::Isometry3d::Identity();
  gate_T_turned.linear() = turn;
  observation.body_T_gate = observation.body_T_gate * gate_T_turned;
  const Matrix6d adjoint = se3Adjoint(gate_T_turned.inverse());
  observation.pose_covariance = adjoint * observation.pose_covariance * adjoint.transpose();
  if (observation.has_alternative) {
    observation.alternative_body_T_gate = observation.alternative_body_T_gate * gate_T_turned;
    observation.alternative_covariance = adjoint * observation.alternative_covariance * adjoint.transpose();
  }
  GateCornerRays& rays = observation.corner_rays;
  rays.p_gate.leftCols(rays.count) = turn.transpose() * rays.p_gate.leftCols(rays.count);
  return observation;
}

GateObservation withAlternativeTaken(GateObservation observation) {
  if (!observation.has_alternative) return observation;
  std::swap(observation.body_T_gate, observation.alternative_body_T_gate);
  std::swap(observation.pose_covariance, observation.alternative_covariance);
  observation.p_body = observation.body_T_gate.translation();
  return observation;
}

Eigen::Vector3d GateObservation::centreInBody() const { return observationModel(kind).centreInBody(*this); }

Eigen::Matrix3d GateObservation::centreCovarianceInBody() const {
  return observationModel(kind).centreCovarianceInBody(*this);
}

Status validateOdometrySample(const OdometrySample& sample) {
  if (!std::isfinite(sample.t)) return Status(StatusCode::kInvalidArgument, "odometry sample: time stamp is not finite");
  // Every sample passes here (twice in the pipeline): the verdict first, without heap or message; the message only
  // for a sample that fails.
  if (isRigidTransform(sample.odom_T_body) &&
      (!sample.relative_covariance || surelyValidCovariance<6>(*sample.relative_covariance))) {
    return Status();
  }
  const std::string where = "odometry sample at t=" + formatTimestamp(sample.t) + ": ";
  DG_RETURN_IF_ERROR(checkRigidTransform(sample.odom_T_body, where + "odom_T_body"));
  if (sample.relative_covariance) {
    DG_RETURN_IF_ERROR(checkCovariance(*sample.relative_covariance, where + "relative_covariance"));
  }
  return Status();
}

Status validateGateObservation(const GateObservation& observation) {
  if (!std::isfinite(observation.t)) return Status(StatusCode::kInvalidArgument, "gate observation: time stamp is not finite");
  const std::string where =
      "gate observation of gate " + std::to_string(observation.gate_id) + " at t=" + std::to_string(observation.t) + ": ";
  if (observation.gate_id < 0) return Status(StatusCode::kInvalidArgument, where + "gate_id must be >= 0");
  const ObservationModel* model = findObservationModel(observation.kind);
  if (model == nullptr) {
    return Status(StatusCode::kInvalidArgument,
                  where + "unknown kind " + std::to_string(static_cast<int>(observation.kind)));
  }
  return model->validate(observation, where);
}

}  // namespace dualgraph
