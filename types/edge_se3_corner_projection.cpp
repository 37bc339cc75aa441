// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_se3_corner_projection.h"

#include <algorithm>

#include "dualgraph/types/g2o_text.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

constexpr double kMinDepth = 1e-6;  // [m]

}  // namespace

void EdgeSE3CornerProjection::setCamera(int parameter_id, const Eigen::Isometry3d& body_T_camera) {
  parameter_id_ = parameter_id;
  body_T_camera_ = body_T_camera;
}

Eigen::Vector3d EdgeSE3CornerProjection::pointInCamera() const {
  const Eigen::Isometry3d camera_T_object =
      (vertexAs<0>()->estimate() * body_T_camera_).inverse() * vertexAs<1>()->estimate();
  Eigen::Vector3d p_camera = camera_T_object * p_object_;
  p_camera.z() = std::max(p_camera.z(), kMinDepth);
  return p_camera;
}

void EdgeSE3CornerProjection::computeError() {
  const Eigen::Vector3d p = pointInCamera();
  error_ = Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()) - measurement_;
}

void EdgeSE3CornerProjection::linearizeOplus() {
  // Right increments with Δ ≈ (I + [θ]×, δt), θ = 2 δq (g2o's chart):
  //   body:   p_body ← Δ⁻¹ · p_body ≈ p_body − δt + [p_body]× θ     → ∂p_body = [−I, 2 [p_body]×]
  //   object: p_world ← R_wo (p_object + δt + θ × p_object)        → ∂p_world = R_wo [I, −2 [p_object]×]
  //   p_camera = R_cb (p_body − t_bc), R_cb = body_R_cameraᵀ;  ∂π/∂p = [1/z 0 −x/z²; 0 1/z −y/z²].
  const Eigen::Isometry3d& world_T_body = vertexAs<0>()->estimate();
  const Eigen::Isometry3d& world_T_object = vertexAs<1>()->estimate();
  const Eigen::Vector3d p_body = world_T_body.inverse() * (world_T_object * p_object_);
  const Eigen::Vector3d p = pointInCamera();
  Eigen::Matrix<double, 2, 3> d_pi;
  d_pi << 1.0 / p.z(), 0.0, -p.x() / (p.z() * p.z()), 0.0, 1.0 / p.z(), -p.y() / (p.z() * p.z());
  const Eigen::Matrix<double, 2, 3> d_body = d_pi * body_T_camera_.linear().transpose();  // ∂e/∂p_body
  Jacobian<0>& j_body = jacobianOplus<0>();
  j_body.leftCols<3>() = -d_body;
  j_body.rightCols<3>() = 2.0 * d_body * skew(p_body);
  const Eigen::Matrix<double, 2, 3> d_object = d_body * world_T_body.linear().transpose() * world_T_object.linear();
  Jacobian<1>& j_object = jacobianOplus<1>();
  j_object.leftCols<3>() = d_object;
  j_object.rightCols<3>() = -2.0 * d_object * skew(p_object_);
}

Status EdgeSE3CornerProjection::read(TokenReader& in, const ParameterContainer& parameters) {
  int parameter_id = 0;
  DG_RETURN_IF_ERROR(in.readInt(parameter_id, "parameter id"));
  Eigen::Isometry3d body_T_camera;
  DG_RETURN_IF_ERROR(lookUpSE3Offset(parameters, parameter_id, in, body_T_camera));
  Eigen::Vector3d p_object;
  DG_RETURN_IF_ERROR(in.readDouble(p_object.x(), "px"));
  DG_RETURN_IF_ERROR(in.readDouble(p_object.y(), "py"));
  DG_RETURN_IF_ERROR(in.readDouble(p_object.z(), "pz"));
  Eigen::Vector2d m;
  DG_RETURN_IF_ERROR(in.readDouble(m.x(), "mx"));
  DG_RETURN_IF_ERROR(in.readDouble(m.y(), "my"));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<2>(information, "information"));
  setCamera(parameter_id, body_T_camera);
  setPoint(p_object);
  setMeasurement(m);
  information_ = information;
  return Status();
}

void EdgeSE3CornerProjection::write(std::ostream& out) const {
  out << parameter_id_ << ' ';
  writeNumbers(out, p_object_.data(), 3);
  out << ' ';
  writeNumbers(out, measurement_.data(), 2);
  out << ' ';
  writeUpperTriangle<2>(out, information_);
}

}  // namespace dualgraph
