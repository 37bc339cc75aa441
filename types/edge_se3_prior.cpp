// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_se3_prior.h"

#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

void EdgeSE3Prior::setMeasurement(const Eigen::Isometry3d& world_T_sensor) {
  measurement_ = world_T_sensor;
  sensor_T_world_measured_ = world_T_sensor.inverse();
}

void EdgeSE3Prior::setOffset(int parameter_id, const Eigen::Isometry3d& body_T_sensor) {
  parameter_id_ = parameter_id;
  body_T_sensor_ = body_T_sensor;
}

void EdgeSE3Prior::computeError() {
  const Eigen::Isometry3d world_T_sensor = vertexAs<0>()->estimate() * body_T_sensor_;
  error_ = g2oChart(sensor_T_world_measured_ * world_T_sensor);
}

void EdgeSE3Prior::linearizeOplus() {
  // world_T_body ← world_T_body · Δ:  E = (Z⁻¹ · world_T_body) · Δ · body_T_sensor.
  jacobianOplus<0>() =
      g2oChartJacobianOfProduct(sensor_T_world_measured_ * vertexAs<0>()->estimate(), body_T_sensor_);
}

Status EdgeSE3Prior::read(TokenReader& in, const ParameterContainer& parameters) {
  int parameter_id = 0;
  DG_RETURN_IF_ERROR(in.readInt(parameter_id, "parameter id"));
  Eigen::Isometry3d body_T_sensor;
  DG_RETURN_IF_ERROR(lookUpSE3Offset(parameters, parameter_id, in, body_T_sensor));
  Eigen::Isometry3d world_T_sensor;
  DG_RETURN_IF_ERROR(text_.read(in, world_T_sensor));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<6>(information, "information"));
  setOffset(parameter_id, body_T_sensor);
  setMeasurement(world_T_sensor);
  information_ = information;
  return Status();
}

void EdgeSE3Prior::write(std::ostream& out) const {
  out << parameter_id_ << ' ';
  text_.write(out, measurement_);
  out << ' ';
  writeUpperTriangle<6>(out, information_);
}

}  // namespace dualgraph
