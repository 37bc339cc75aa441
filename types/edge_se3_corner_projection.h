// SPDX-License-Identifier: MIT
// EdgeSE3CornerProjection: a point fixed on one pose (a gate corner) seen by a camera fixed on another.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

/// A point fixed in the frame of one pose, seen by a pinhole camera fixed on another (tag
/// `EDGE_SE3_CORNER_PROJECTION`, this project's own): slot 0 the VertexSE3 `world_T_body` carrying the
/// camera at `body_T_camera` (a PARAMS_SE3OFFSET), slot 1 the VertexSE3 `world_T_object` whose point
/// `p_object` [m] (a gate corner in the gate frame) is seen. Measurement m: the undistorted normalised image
/// coordinates (x/z, y/z) of that point, camera frame z forward. Residual, 2-vector (unitless):
/// e = π(camera_T_world · world_T_object · p_object) − m with π(p) = (p_x/p_z, p_y/p_z); a point at
/// p_z ≤ 1e-6 m is projected as if at 1e-6 m (a large error, so the optimiser steps away). Information
/// 2×2 in the same units (fx²/σ_px² for pixel noise σ_px). Analytic Jacobians w.r.t. both poses' g2o
/// increments. File: `EDGE_SE3_CORNER_PROJECTION body_id object_id parameter_id px py pz mx my` + the 3
/// upper-triangular information entries.
class EdgeSE3CornerProjection final : public BaseEdge<2, Eigen::Vector2d, VertexSE3, VertexSE3> {
 public:
  static constexpr const char* kTag = "EDGE_SE3_CORNER_PROJECTION";

  EdgeSE3CornerProjection() { measurement_.setZero(); }

  /// The camera on the body (written as the PARAMS_SE3OFFSET `parameter_id`).
  void setCamera(int parameter_id, const Eigen::Isometry3d& body_T_camera);
  /// The point in the object's frame [m].
  void setPoint(const Eigen::Vector3d& p_object) { p_object_ = p_object; }
  const Eigen::Isometry3d& camera() const { return body_T_camera_; }
  const Eigen::Vector3d& point() const { return p_object_; }
  int parameterId() const { return parameter_id_; }

  void computeError() override;
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeSE3CornerProjection>(*this); }

 protected:
  void linearizeOplus() override;

 private:
  /// The point in the camera frame, its depth clamped to ≥ 1e-6 m.
  Eigen::Vector3d pointInCamera() const;

  Eigen::Isometry3d body_T_camera_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d p_object_ = Eigen::Vector3d::Zero();
  int parameter_id_ = 0;
};

}  // namespace dualgraph
