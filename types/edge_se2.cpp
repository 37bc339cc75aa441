// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_se2.h"

#include "dualgraph/types/g2o_text.h"

namespace dualgraph {

void EdgeSE2::setMeasurement(const SE2& i_T_j) {
  measurement_ = i_T_j;
  j_T_i_measured_ = i_T_j.inverse();
}

void EdgeSE2::computeError() {
  const SE2& world_T_i = vertexAs<0>()->estimate();
  const SE2& world_T_j = vertexAs<1>()->estimate();
  error_ = (j_T_i_measured_ * (world_T_i.inverse() * world_T_j)).toVector();
}

void EdgeSE2::linearizeOplus() {
  // e_t = R_zᵀ (R_iᵀ (t_j − t_i) − t_z),  e_θ = θ_j − θ_i − θ_z (wrapped), with additive increments.
  // d R(θ)ᵀ/dθ = −S R(θ)ᵀ, S = [[0, −1], [1, 0]].
  const SE2& world_T_i = vertexAs<0>()->estimate();
  const SE2& world_T_j = vertexAs<1>()->estimate();
  const Eigen::Matrix2d zR_world = measurement_.rotation().transpose() * world_T_i.rotation().transpose();
  const Eigen::Vector2d d_world = world_T_j.translation() - world_T_i.translation();
  const Eigen::Vector2d perpendicular(-d_world.y(), d_world.x());  // S · d, S commutes with rotations
  Jacobian<0>& J_e_i = jacobianOplus<0>();
  J_e_i.setZero();
  J_e_i.topLeftCorner<2, 2>() = -zR_world;
  J_e_i.topRightCorner<2, 1>() = -zR_world * perpendicular;
  J_e_i(2, 2) = -1.0;
  Jacobian<1>& J_e_j = jacobianOplus<1>();
  J_e_j.setZero();
  J_e_j.topLeftCorner<2, 2>() = zR_world;
  J_e_j(2, 2) = 1.0;
}

Status EdgeSE2::read(TokenReader& in, const ParameterContainer& /*parameters*/) {
  double dx = 0.0, dy = 0.0, dtheta = 0.0;
  DG_RETURN_IF_ERROR(in.readDouble(dx, "dx"));
  DG_RETURN_IF_ERROR(in.readDouble(dy, "dy"));
  DG_RETURN_IF_ERROR(in.readDouble(dtheta, "dtheta"));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<3>(information, "information"));
  setMeasurement(SE2(dx, dy, dtheta));
  information_ = information;
  return Status();
}

void EdgeSE2::write(std::ostream& out) const {
  const Eigen::Vector3d v = measurement_.toVector();
  writeNumbers(out, v.data(), 3);
  out << ' ';
  writeUpperTriangle<3>(out, information_);
}

}  // namespace dualgraph
