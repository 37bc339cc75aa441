// SPDX-License-Identifier: MIT
// EdgeSE3Prior (EDGE_SE3_PRIOR): an absolute pose prior on a VertexSE3, measured at a sensor offset.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/g2o_text.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

/// Absolute pose prior on one VertexSE3 `world_T_body` (g2o tag `EDGE_SE3_PRIOR`), measured at
/// a sensor mounted at `body_T_sensor` (a PARAMS_SE3OFFSET). Measurement Z = `world_T_sensor`.
/// Residual (g2o's): e = g2oChart(Z⁻¹ · world_T_body · body_T_sensor), order [t; q.vec], w ≥ 0.
/// Information Ω (6×6) in g2o units: m⁻² for t, (q.vec)⁻² ≈ 4 rad⁻² for the rotation (see
/// informationMetricToG2o()).
/// File: `EDGE_SE3_PRIOR body_id parameter_id x y z qx qy qz qw` + 21 upper-triangular Ω entries;
/// read() copies the offset of the PARAMS_SE3OFFSET with that id (unknown id → error); the
/// quaternion is used as written when near unit norm, as g2o reads this tag (see VertexSE3).
/// Built in code, the offset is the identity and the parameter id 0 until setOffset(): a graph
/// written with such an edge needs a matching `PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1` line to be read
/// back. Analytic Jacobian.
class EdgeSE3Prior final : public BaseEdge<6, Eigen::Isometry3d, VertexSE3> {
 public:
  static constexpr const char* kTag = "EDGE_SE3_PRIOR";

  EdgeSE3Prior() { setMeasurement(Eigen::Isometry3d::Identity()); }

  /// Stores Z = `world_T_sensor` and caches Z⁻¹.
  void setMeasurement(const Eigen::Isometry3d& world_T_sensor) override;
  /// The sensor offset and the id of the PARAMS_SE3OFFSET it is written as.
  void setOffset(int parameter_id, const Eigen::Isometry3d& body_T_sensor);
  int parameterId() const { return parameter_id_; }
  const Eigen::Isometry3d& offset() const { return body_T_sensor_; }

  void computeError() override;
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeSE3Prior>(*this); }

 protected:
  void linearizeOplus() override;

 private:
  Eigen::Isometry3d sensor_T_world_measured_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d body_T_sensor_ = Eigen::Isometry3d::Identity();
  int parameter_id_ = 0;
  G2oPoseText text_{QuaternionReading::kAsWrittenNearUnit};  // g2o does not normalise this tag
};

}  // namespace dualgraph
