// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_se3_point_xyz.h"

#include "dualgraph/types/g2o_text.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

void EdgeSE3PointXYZ::setOffset(int parameter_id, const Eigen::Isometry3d& body_T_sensor) {
  parameter_id_ = parameter_id;
  body_T_sensor_ = body_T_sensor;
}

void EdgeSE3PointXYZ::computeError() {
  const Eigen::Isometry3d sensor_T_world = (vertexAs<0>()->estimate() * body_T_sensor_).inverse();
  error_ = sensor_T_world * vertexAs<1>()->estimate() - measurement_;
}

void EdgeSE3PointXYZ::linearizeOplus() {
  // world_T_body ← world_T_body · Δ, with Δ⁻¹ · p_body ≈ p_body − δt + 2 [p_body]× δq:
  //   e = R_offsetᵀ (Δ⁻¹ · p_body − t_offset) − m
  //   J_e_pose = [−R_offsetᵀ, 2 R_offsetᵀ [p_body]×],   J_e_point = (R_body R_offset)ᵀ.
  const Eigen::Isometry3d& world_T_body = vertexAs<0>()->estimate();
  const Eigen::Vector3d p_body = world_T_body.inverse() * vertexAs<1>()->estimate();
  const Eigen::Matrix3d sensor_R_body = body_T_sensor_.linear().transpose();
  Jacobian<0>& J_e_pose = jacobianOplus<0>();
  J_e_pose.leftCols<3>() = -sensor_R_body;
  J_e_pose.rightCols<3>() = 2.0 * sensor_R_body * skew(p_body);
  jacobianOplus<1>() = sensor_R_body * world_T_body.linear().transpose();
}

Status EdgeSE3PointXYZ::read(TokenReader& in, const ParameterContainer& parameters) {
  int parameter_id = 0;
  DG_RETURN_IF_ERROR(in.readInt(parameter_id, "parameter id"));
  Eigen::Isometry3d body_T_sensor;
  DG_RETURN_IF_ERROR(lookUpSE3Offset(parameters, parameter_id, in, body_T_sensor));
  Eigen::Vector3d p_sensor;
  DG_RETURN_IF_ERROR(in.readDouble(p_sensor.x(), "mx"));
  DG_RETURN_IF_ERROR(in.readDouble(p_sensor.y(), "my"));
  DG_RETURN_IF_ERROR(in.readDouble(p_sensor.z(), "mz"));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<3>(information, "information"));
  setOffset(parameter_id, body_T_sensor);
  setMeasurement(p_sensor);
  information_ = information;
  return Status();
}

void EdgeSE3PointXYZ::write(std::ostream& out) const {
  out << parameter_id_ << ' ';
  writeNumbers(out, measurement_.data(), 3);
  out << ' ';
  writeUpperTriangle<3>(out, information_);
}

}  // namespace dualgraph
