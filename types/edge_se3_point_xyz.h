// SPDX-License-Identifier: MIT
// EdgeSE3PointXYZ (EDGE_SE3_TRACKXYZ): a 3-D point observed from a pose through a sensor offset.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

/// A 3-D point observed from a pose (g2o tag `EDGE_SE3_TRACKXYZ`): slot 0 the VertexSE3
/// `world_T_body`, slot 1 the VertexPointXYZ `p_world`, through a sensor at `body_T_sensor`
/// (a PARAMS_SE3OFFSET). Measurement m = `p_sensor`, the point in the sensor frame (metres).
/// Residual: e = (world_T_body · body_T_sensor)⁻¹ · p_world − m, in the sensor frame.
/// Information Ω (3×3) in m⁻², sensor axes.
/// File: `EDGE_SE3_TRACKXYZ body_id point_id parameter_id mx my mz` + 6 upper-triangular Ω
/// entries; read() copies the offset of that PARAMS_SE3OFFSET (unknown id → error). Built in
/// code, the offset is the identity with parameter id 0 until setOffset(). Analytic Jacobians
/// w.r.t. the pose's g2o increment and the point.
class EdgeSE3PointXYZ final : public BaseEdge<3, Eigen::Vector3d, VertexSE3, VertexPointXYZ> {
 public:
  static constexpr const char* kTag = "EDGE_SE3_TRACKXYZ";

  EdgeSE3PointXYZ() { measurement_.setZero(); }

  /// The sensor offset and the id of the PARAMS_SE3OFFSET it is written as.
  void setOffset(int parameter_id, const Eigen::Isometry3d& body_T_sensor);
  int parameterId() const { return parameter_id_; }
  const Eigen::Isometry3d& offset() const { return body_T_sensor_; }

  void computeError() override;
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeSE3PointXYZ>(*this); }

 protected:
  void linearizeOplus() override;

 private:
  Eigen::Isometry3d body_T_sensor_ = Eigen::Isometry3d::Identity();
  int parameter_id_ = 0;
};

}  // namespace dualgraph
