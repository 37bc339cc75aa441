// SPDX-License-Identifier: MIT
#include "types/edge_se3.h"

#include "types/se3_math.h"

namespace dualgraph {

void EdgeSE3::setMeasurement(const Eigen::Isometry3d& i_T_j) {
  measurement_ = i_T_j;
  j_T_i_measured_ = i_T_j.inverse();
  q_j_i_measured_ = quatFromRotation(j_T_i_measured_.linear());
}

void EdgeSE3::computeError() {
  const Eigen::Isometry3d& world_T_i = vertexAs<0>()->estimate();
  const Eigen::Isometry3d& world_T_j = vertexAs<1>()->estimate();
  // Same product order as g2o, so the χ² of a g2o file agrees to round-off.
  error_ = g2oChart(j_T_i_measured_ * world_T_i.inverse() * world_T_j);
}

void EdgeSE3::linearizeOplus() {
  // Right increments Δ on both poses:
  //   world_T_j ← world_T_j · Δ:  E = (Z⁻¹ · i_T_j) · Δ · I
  //   world_T_i ← world_T_i · Δ:  E = Z⁻¹ · Δ⁻¹ · i_T_j, and Δ(δ)⁻¹ = Δ(−δ) to first order.
  // One quaternion extraction per edge: Z⁻¹'s is cached, the error's is the product.
  const Eigen::Isometry3d i_T_j = vertexAs<0>()->estimate().inverse() * vertexAs<1>()->estimate();
  const Eigen::Quaterniond q_i_j = quatFromRotation(i_T_j.linear());
  jacobianOplus<0>() = -g2oChartJacobianOfProduct(j_T_i_measured_, q_j_i_measured_, i_T_j.translation(), q_i_j);
  jacobianOplus<1>() = g2oChartJacobianOfProduct(j_T_i_measured_ * i_T_j, q_j_i_measured_ * q_i_j,
                                                 Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
}

Status EdgeSE3::read(TokenReader& in, const ParameterContainer& /*parameters*/) {
  Eigen::Isometry3d i_T_j;
  DG_RETURN_IF_ERROR(text_.read(in, i_T_j));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<6>(information, "information"));
  setMeasurement(i_T_j);
  information_ = information;
  return Status();
}

void EdgeSE3::write(std::ostream& out) const {
  text_.write(out, measurement_);
  out << ' ';
  writeUpperTriangle<6>(out, information_);
}

}  // namespace dualgraph
