// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/observation_models.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status validateCornerRays(const GateCornerRays& rays, const std::string& where) {
  if (rays.count < 2 || rays.count > 4) {
    return Status(StatusCode::kInvalidArgument, where + "count " + std::to_string(rays.count) + " is not 2 ... 4");
  }
  if (!rays.p_gate.leftCols(rays.count).allFinite() || !rays.normalized.leftCols(rays.count).allFinite()) {
    return Status(StatusCode::kInvalidArgument, where + "has a non-finite corner or ray");
  }
  for (int k = 0; k < rays.count; ++k) {
    DG_RETURN_IF_ERROR(checkCovariance(rays.covariance[static_cast<size_t>(k)],
                                       where + "covariance[" + std::to_string(k) + "]"));
  }
  return checkRigidTransform(rays.body_T_camera, where + "body_T_camera");
}

void attachCornerRays(const GateCornerRays& rays, const Eigen::Isometry3d& body_T_gate, const NodeAttachment& at,
                      AttachedObservation& attached) {
  attached.rays = rays;
  const Eigen::Isometry3d& body_T_camera = rays.body_T_camera;
  attached.rays.body_T_camera = at.node_T_body * body_T_camera;
  const Eigen::Matrix3d camera_R_body = body_T_camera.linear().transpose();
  for (int k = 0; k < attached.rays.count; ++k) {
    Eigen::Matrix2d covariance = attached.rays.covariance[static_cast<size_t>(k)];
    if (at.compensation != nullptr) {
      // The node → body increment's uncertainty (right perturbation ε of node_T_body) moves the corner in the
      // body frame by −ε_t + [p_body]× ε_θ; p_body from body_T_gate (the frontend's pose of the gate).
      const Eigen::Vector3d p_body = body_T_gate * Eigen::Vector3d(attached.rays.p_gate.col(k));
      const Eigen::Vector3d p = body_T_camera.inverse() * p_body;
      if (p.z() > 1e-6) {
        Eigen::Matrix<double, 2, 3> d_pi;
        d_pi << 1.0 / p.z(), 0.0, -p.x() / (p.z() * p.z()), 0.0, 1.0 / p.z(), -p.y() / (p.z() * p.z());
        Eigen::Matrix<double, 3, 6> d_body;
        d_body << -Eigen::Matrix3d::Identity(), skew(p_body);
        const Eigen::Matrix<double, 2, 6> jacobian = d_pi * camera_R_body * d_body;
        covariance += jacobian * *at.compensation * jacobian.transpose();
      }
    }
    attached.ray_information[static_cast<size_t>(k)] = covariance.inverse();
  }
}

Status addCornerRayEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                         const std::shared_ptr<const RobustKernel>& kernel) {
  const GateCornerRays& rays = attached.rays;
  for (int c = 0; c < rays.count; ++c) {
    DG_RETURN_IF_ERROR(pool.addCornerEdge(node, gate, rays.body_T_camera, rays.p_gate.col(c), rays.normalized.col(c),
                                          attached.ray_information[static_cast<size_t>(c)], kernel));
  }
  return Status();
}

Status CornerRaysObservationModel::validate(const GateObservation& observation, const std::string& where) const {
  return validateCornerRays(observation.corner_rays, where + "corner_rays.");
}

Status CornerRaysObservationModel::checkUsable(const LocalizerParams& params, const std::string& what) const {
  if (params.mode != LocalizerMode::kDual || params.landmark != LandmarkModel::kPose) {
    return Status(StatusCode::kInvalidArgument,
                  what + ": corner rays (a partial gate) are used by the dual graph with landmark: pose only");
  }
  return Status();
}

Result<AttachedObservation> CornerRaysObservationModel::attach(const GateObservation& observation,
                                                               const NodeAttachment& at, LandmarkModel landmark) const {
  if (landmark != LandmarkModel::kPose) {
    return Status(StatusCode::kInvalidArgument, "observation of gate " + std::to_string(observation.gate_id) +
                                                    ": corner rays need landmark: pose");
  }
  AttachedObservation attached = AttachedObservation::of(observation, landmark);
  attachCornerRays(observation.corner_rays, observation.body_T_gate, at, attached);
  return attached;
}

Status CornerRaysObservationModel::addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool,
                                                     int node, int gate,
                                                     const std::shared_ptr<const RobustKernel>& kernel) const {
  return addCornerRayEdges(attached, pool, node, gate, kernel);
}

Eigen::Vector3d CornerRaysObservationModel::centreInBody(const GateObservation& observation) const {
  return observation.body_T_gate.translation();  // the prediction, not a measurement
}

Eigen::Matrix3d CornerRaysObservationModel::centreCovarianceInBody(const GateObservation& observation) const {
  const Eigen::Matrix3d rotation = observation.body_T_gate.linear();
  return rotation * observation.pose_covariance.topLeftCorner<3, 3>() * rotation.transpose();
}

}  // namespace dualgraph
