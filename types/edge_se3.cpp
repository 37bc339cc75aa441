// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_se3.h"

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

void EdgeSE3::setMeasurement(const Eigen::Isometry3d& i_T_j) {
  measurement_ = i_T_j;
  j_T_i_measured_ = i_T_j.inverse();
}

void EdgeSE3::computeError() {
  const Eigen::Isometry3d& world_T_i = vertexAs<0>()->estimate();
  const Eigen::Isometry3d& world_T_j = vertexAs<1>()->estimate();
  // E = (Z⁻¹ · world_T_i⁻¹) · world_T_j, g2o's product order, so the χ² of a g2o file agrees to
  // round-off. Written out as Eigen's Isometry inverse() and operator* compute it (the same
  // expressions on the same 4×4 storage, hence the same bits) but inline and without the
  // bottom rows, which the chart does not read.
  Eigen::Isometry3d i_T_world;
  i_T_world.linear() = world_T_i.linear().transpose();
  i_T_world.translation() = -i_T_world.linear() * world_T_i.translation();
  Eigen::Isometry3d j_T_world;
  j_T_world.linear() = j_T_i_measured_.linear() * i_T_world.linear();
  j_T_world.translation() = j_T_i_measured_.linear() * i_T_world.translation() + j_T_i_measured_.translation();
  Eigen::Isometry3d error_pose;
  error_pose.linear() = j_T_world.linear() * world_T_j.linear();
  error_pose.translation() = j_T_world.linear() * world_T_j.translation() + j_T_world.translation();
  error_ = g2oChart(error_pose, error_w_);
  error_rotation_ = error_pose.linear();
}

void EdgeSE3::prefetch() const { prefetchBytes<sizeof(EdgeSE3)>(this); }

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
  // Written column by column with cross products (a_k = R_A e_k, u = 2 (t_E − t_A)):
  //   J_i e_k = [−a_k; 0],  J_i e_{3+k} = [u × a_k; v × a_k − w a_k],  J_j = [[R_E, 0], [0, w I + [v]×]].
  const Eigen::Vector3d u = 2.0 * (error_.head<3>() - j_T_i_measured_.translation());
  const Eigen::Vector3d v = error_.tail<3>();
  const double w = error_w_;
  auto& j_i = jacobianOplus<0>();
  auto& j_j = jacobianOplus<1>();
  j_i.bottomLeftCorner<3, 3>().setZero();
  j_j.topRightCorner<3, 3>().setZero();
  j_j.bottomLeftCorner<3, 3>().setZero();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = j_T_i_measured_.linear().col(k);
    j_i.block<3, 1>(0, k) = -a;
    j_i.block<3, 1>(0, 3 + k) = u.cross(a);
    j_i.block<3, 1>(3, 3 + k) = v.cross(a) - w * a;
  }
  j_j.topLeftCorner<3, 3>() = error_rotation_;
  j_j.bottomRightCorner<3, 3>() << w, -v.z(), v.y(),
                                   v.z(), w, -v.x(),
                                   -v.y(), v.x(), w;
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
