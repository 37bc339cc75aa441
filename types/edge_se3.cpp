// SPDX-License-Identifier: MIT
#include "types/edge_se3.h"

#include "types/se3_math.h"

namespace dualgraph {

void EdgeSE3::setMeasurement(const Eigen::Isometry3d& i_T_j) {
  measurement_ = i_T_j;
  j_T_i_measured_ = i_T_j.inverse();
}

void EdgeSE3::computeError() {
  const Eigen::Isometry3d& world_T_i = vertexAs<0>()->estimate();
  const Eigen::Isometry3d& world_T_j = vertexAs<1>()->estimate();
  // Same product order as g2o, so the χ² of a g2o file agrees to round-off.
  const Eigen::Isometry3d error_pose = j_T_i_measured_ * world_T_i.inverse() * world_T_j;
  error_ = g2oChart(error_pose, error_w_);
  error_rotation_ = error_pose.linear();
}

void EdgeSE3::prefetch() const { prefetchBytes(this, sizeof(EdgeSE3)); }

void EdgeSE3::linearizeOplus() {
  // Right increments Δ(δ) = (R_δ ≈ I + 2[δq]×, δt), written with the error pose E = (R_E, t_E)
  // and its sign-fixed unit quaternion (w, v) = (error_w_, error_.tail<3>()) kept by
  // computeError, and Z⁻¹ = (R_A, t_A): no pose product, no matrix → quaternion conversion.
  //   world_T_j ← world_T_j · Δ:  E · Δ  →  t: R_E δt,  q: (w, v) ⊗ (1, δq), vec = (w I + [v]×) δq
  //     J_j = [[R_E, 0], [0, w I + [v]×]]
  //   world_T_i ← world_T_i · Δ:  Z⁻¹ · Δ(−δ) · B with B = world_T_i⁻¹ · world_T_j, t_E = t_A + R_A t_B
  //     t: t_A + R_A (−δt + R_δ⁻¹ t_B)  →  −R_A δt + 2 R_A [t_B]× δq = −R_A δt + 2 [t_E − t_A]× R_A δq
  //     q: q_A ⊗ (1, −δq) ⊗ q_B = q_E + (0, −R_A δq) ⊗ q_E, and vec((0, p) ⊗ (w, v)) = (w I − [v]×) p
  //     J_i = [[−R_A, 2 [t_E − t_A]× R_A], [0, ([v]× − w I) R_A]]
  // (the same matrices as g2oChartJacobianOfProduct(Z⁻¹, B) and (E, I), up to round-off).
  const Eigen::Matrix3d rotation_a = j_T_i_measured_.linear();
  const Eigen::Vector3d v = error_.tail<3>();
  const Eigen::Matrix3d v_cross = skew(v);
  const Eigen::Matrix3d w_identity = error_w_ * Eigen::Matrix3d::Identity();
  auto& j_i = jacobianOplus<0>();
  j_i.topLeftCorner<3, 3>() = -rotation_a;
  j_i.topRightCorner<3, 3>().noalias() =
      2.0 * skew(error_.head<3>() - j_T_i_measured_.translation()) * rotation_a;
  j_i.bottomLeftCorner<3, 3>().setZero();
  j_i.bottomRightCorner<3, 3>().noalias() = (v_cross - w_identity) * rotation_a;
  auto& j_j = jacobianOplus<1>();
  j_j.topLeftCorner<3, 3>() = error_rotation_;
  j_j.topRightCorner<3, 3>().setZero();
  j_j.bottomLeftCorner<3, 3>().setZero();
  j_j.bottomRightCorner<3, 3>() = w_identity + v_cross;
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
